//! The modified Lentz method for continued fractions (Numerical Recipes 5.2), shared by the
//! incomplete gamma (`sigmoid`'s erfc tail) and the incomplete beta (`student_t`'s p-value).
//!
//! Each caller starts the recurrence in the state its fraction needs and feeds it the partial
//! numerators and denominators; the callers keep their own loops because they test for
//! convergence at different points (the beta fraction only after each pair of terms).

/// Below this a denominator counts as zero and is replaced, so no step divides by zero.
const TINY: f64 = 1e-300;

/// The running value `h` of a fraction and Lentz's two ratios `c` and `d`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Lentz {
    pub h: f64,
    c: f64,
    d: f64,
}

impl Lentz {
    /// The state after the first term: `h = d = 1 / b0` (guarded), with `c` given.
    pub fn start(c: f64, b0: f64) -> Self {
        let d = 1.0 / guard(b0);
        Lentz { h: d, c, d }
    }

    /// Takes the next partial numerator `a` and denominator `b`; returns the factor `h` was
    /// multiplied by, whose distance from 1 says how far the fraction still moves.
    pub fn step(&mut self, a: f64, b: f64) -> f64 {
        self.d = 1.0 / guard(a * self.d + b);
        self.c = guard(b + a / self.c);
        let del = self.d * self.c;
        self.h *= del;
        del
    }
}

/// `x`, or `TINY` where `x` is within `TINY` of zero.
fn guard(x: f64) -> f64 {
    if x.abs() < TINY { TINY } else { x }
}

/// Lentz's initial `c` for a fraction whose first convergent is `1 / b0`: effectively
/// infinite, so the first step's `c` is its denominator.
pub(crate) const C_INFINITE: f64 = 1.0 / TINY;

#[cfg(test)]
mod tests {
    use super::*;

    const PHI: f64 = 1.618_033_988_749_895;

    /// Steps until a step moves the value by at most an ulp; the value.
    fn converge(mut l: Lentz, term: impl Fn(u32) -> (f64, f64)) -> f64 {
        for k in 1..1000 {
            let (a, b) = term(k);
            if (l.step(a, b) - 1.0).abs() <= f64::EPSILON {
                break;
            }
        }
        l.h
    }

    /// 1 / (1 + 1 / (1 + 1 / ...)) = 1 / golden ratio.
    #[test]
    fn golden_ratio_converges() {
        let h = converge(Lentz::start(C_INFINITE, 1.0), |_| (1.0, 1.0));
        assert!((h - 1.0 / PHI).abs() < 4.0 * f64::EPSILON, "{h}");
    }

    /// tan x = x / (1 - x^2 / (3 - x^2 / (5 - ...))).
    #[test]
    fn tangent_fraction_matches_tan() {
        let x: f64 = 0.7;
        let h = converge(Lentz::start(C_INFINITE, 1.0), |k| {
            (-x * x, (2 * k + 1) as f64)
        });
        assert!((x * h - x.tan()).abs() < 8.0 * f64::EPSILON, "{}", x * h);
    }

    /// A zero first denominator is guarded, not divided by: 1 / (0 + 1 / (1 + 1 / ...)) is
    /// the golden ratio itself.
    #[test]
    fn zero_first_denominator_is_guarded() {
        let h = converge(Lentz::start(C_INFINITE, 0.0), |_| (1.0, 1.0));
        assert!((h - PHI).abs() < 4.0 * f64::EPSILON * PHI, "{h}");
    }
}
