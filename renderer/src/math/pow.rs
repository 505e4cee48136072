//! `x^p` for the Fresnel curve's whole exponents: the product of `x`'s powers in f64.
//!
//! Why: libm's `powf` was 8% of the thesis's spheres scene (`perf` at 6d8d2e6), about half of
//! it the Fresnel weight of each mirror bounce, whose exponent is 5 in every material of the
//! suite. For a whole exponent `n` in 1..=16, square and multiply in f64 takes at most eight
//! products, each rounding by `2^-53`, which the later squarings at most double: the f64 value
//! is within `n 2^-52` (relative) of `x^n`, so its rounding to f32 is the correctly rounded
//! `x^n` but where that lies within `n 2^-52` of a halfway point between two floats; libm's
//! `powf` is within 0.82 ulp, not correctly rounded (for `n = 5` the two differ in 143,992 of
//! the 1,065,353,217 floats in [0, 1], `git show 1615eed:docs/benchmarks/lanes.md`, spin8.
//! Other exponents keep libm's `powf`.

/// `x^p`: for a whole `p` in 1..=16 the f64 product (see the module notes; within
/// `0.5 + 2^-20` ulp), else `x.powf(p)`.
#[inline]
pub fn pow_whole(x: f32, p: f32) -> f32 {
    let n = p as u32;
    if n as f32 != p || !(1..=16).contains(&n) {
        return x.powf(p);
    }
    let b = f64::from(x);
    // High bit first: `r = b^(n >> k)` for k from the top bit down.
    let mut r = b;
    for k in (0..31 - n.leading_zeros()).rev() {
        r *= r;
        if n >> k & 1 == 1 {
            r *= b;
        }
    }
    r as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hash::{hash, unit_f32};

    /// The correctly rounded `x^p` (f64's `powf` is within an ulp of f64, far below f32's).
    fn exact(x: f32, p: f32) -> f32 {
        f64::from(x).powf(f64::from(p)) as f32
    }

    /// Whole exponents: within one f32 ulp of the correctly rounded value everywhere, and equal
    /// to it but for near-halfway cases (bounded from the products' rounding: a share of about
    /// `n 2^-28`); bases all over [0, 1], tiny ones and the ends included.
    #[test]
    fn whole_powers_are_the_correctly_rounded_value_but_at_halfway_cases() {
        for n in 1..=16u32 {
            let p = n as f32;
            let (mut equal, mut all) = (0u64, 0u64);
            let mut bases: Vec<f32> =
                vec![0.0, 1.0, 0.5, 1e-6, 1e-12, f32::MIN_POSITIVE, 0.999_999];
            bases.extend((0..50_000u64).map(|i| unit_f32(hash(14, &[u64::from(n), i]))));
            for x in bases {
                let (got, want) = (pow_whole(x, p), exact(x, p));
                let ulp = (want.next_up() - want).max(f32::from_bits(1));
                assert!(
                    (got - want).abs() <= ulp,
                    "{x:e}^{n}: {got:e} against {want:e}"
                );
                equal += u64::from(got.to_bits() == want.to_bits());
                all += 1;
            }
            assert!(equal * 10_000 >= all * 9_999, "{n}: {equal} of {all} equal");
        }
    }

    /// Other exponents are libm's `powf`, bit for bit; and the ones the loop must not take.
    #[test]
    fn other_exponents_keep_powf() {
        for p in [
            0.0f32,
            0.5,
            2.5,
            17.0,
            20.0,
            200.0,
            -1.0,
            -3.0,
            f32::NAN,
            1e9,
        ] {
            for x in [0.0f32, 0.3, 0.75, 1.0] {
                let (got, want) = (pow_whole(x, p), x.powf(p));
                assert!(
                    got.to_bits() == want.to_bits(),
                    "{x}^{p}: {got} against {want}"
                );
            }
        }
        assert_eq!(pow_whole(0.5, 5.0), 0.03125);
        assert_eq!(pow_whole(0.0, 5.0), 0.0);
        assert_eq!(pow_whole(1.0, 16.0), 1.0);
    }
}
