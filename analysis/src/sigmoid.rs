//! The psychometric function's core shape: a sigmoid S(z) rising from 0 to 1.
//!
//! The stimulus axis is x = ln spp and detection *falls* as spp rises, so the psychometric
//! module evaluates S at z = beta (alpha - x). Each sigmoid returns S and its complement
//! 1 - S computed directly (never as 1 - S), plus ln(1 - S), so the likelihood stays finite and
//! accurate when a fit is nearly a step.

use crate::continued_fraction::{C_INFINITE, Lentz};
use serde::Serialize;

/// The sigmoid family of a fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Sigmoid {
    /// S(z) = 1 / (1 + e^-z) (the default).
    Logistic,
    /// Weibull in the stimulus, i.e. the Gumbel (log-Weibull) form in ln spp:
    /// S(z) = 1 - exp(-e^z).
    Weibull,
    /// Cumulative normal: S(z) = Phi(z).
    Normal,
}

/// S, 1 - S and ln(1 - S) at one z.
#[derive(Clone, Copy, Debug)]
pub struct SigmoidValue {
    pub s: f64,
    pub sc: f64,
    pub ln_sc: f64,
}

/// |z| beyond this changes nothing in f64 for any family (S is exactly 0 or 1), and clamping
/// keeps exp(z) in the Gumbel form finite.
const Z_LIMIT: f64 = 300.0;

renderer::named!(Sigmoid, "sigmoid", [
    Logistic => "logistic",
    Weibull => "weibull",
    Normal => "normal",
]);

impl Sigmoid {
    /// Evaluate S, 1 - S and ln(1 - S).
    pub fn eval(self, z: f64) -> SigmoidValue {
        let z = z.clamp(-Z_LIMIT, Z_LIMIT);
        match self {
            Sigmoid::Logistic => {
                let e = (-z.abs()).exp();
                let (s, sc) = if z >= 0.0 {
                    (1.0 / (1.0 + e), e / (1.0 + e))
                } else {
                    (e / (1.0 + e), 1.0 / (1.0 + e))
                };
                SigmoidValue {
                    s,
                    sc,
                    ln_sc: -(z.max(0.0) + e.ln_1p()),
                }
            }
            Sigmoid::Weibull => {
                let ez = z.exp();
                SigmoidValue {
                    s: -(-ez).exp_m1(),
                    sc: (-ez).exp(),
                    ln_sc: -ez,
                }
            }
            Sigmoid::Normal => {
                let ln_sc = ln_phi(-z);
                SigmoidValue {
                    s: phi(z),
                    sc: ln_sc.exp(),
                    ln_sc,
                }
            }
        }
    }

    /// S^-1(q) for q in (0, 1).
    pub fn inverse(self, q: f64) -> f64 {
        match self {
            Sigmoid::Logistic => (q / (1.0 - q)).ln(),
            Sigmoid::Weibull => (-(-q).ln_1p()).ln(),
            Sigmoid::Normal => -std::f64::consts::SQRT_2 * statrs::function::erf::erfc_inv(2.0 * q),
        }
    }
}

/// Standard normal CDF, with full relative accuracy in both tails (the fits'; the decision
/// rule keeps statrs' `experiment::predicted::phi`, justified there).
pub fn phi(z: f64) -> f64 {
    0.5 * erfc(-z / std::f64::consts::SQRT_2)
}

/// ln Phi(z), finite for every finite z (the lower tail is computed in log space).
pub fn ln_phi(z: f64) -> f64 {
    ln_erfc(-z / std::f64::consts::SQRT_2) - std::f64::consts::LN_2
}

/// ln Gamma(1/2) = ln sqrt(pi).
const LN_SQRT_PI: f64 = 0.572_364_942_924_700_1;

/// erfc(x) = Q(1/2, x^2) for x >= 0 (regularized upper incomplete gamma), accurate to a few ulps
/// relative: below 1 as 1 - P(1/2, x^2) by its positive series, above by Q's continued fraction.
/// (statrs' erfc was measured 1e-10 relative off at x = 0.5, too coarse for the likelihood.)
pub fn erfc(x: f64) -> f64 {
    if x < 0.0 {
        2.0 - erfc(-x)
    } else if x < 1.0 {
        1.0 - erf_series(x)
    } else {
        ln_erfc(x).exp()
    }
}

/// ln erfc(x), finite for all finite x.
pub fn ln_erfc(x: f64) -> f64 {
    if x < 1.0 {
        erfc(x).ln()
    } else {
        let x2 = x * x;
        -x2 + x.ln() - LN_SQRT_PI + upper_gamma_fraction(0.5, x2).ln()
    }
}

/// erf(x) = P(1/2, x^2) = e^{-x^2} x / Gamma(3/2) sum_n x^{2n} / ((3/2)(5/2)...(n + 1/2)),
/// all terms positive (no cancellation); for 0 <= x < 1 it converges in < 30 terms.
fn erf_series(x: f64) -> f64 {
    let x2 = x * x;
    let (mut ap, mut term, mut sum) = (0.5, 2.0, 2.0);
    for _ in 0..200 {
        ap += 1.0;
        term *= x2 / ap;
        sum += term;
        if term < sum * f64::EPSILON {
            break;
        }
    }
    // P(1/2, x^2) = e^{-x^2} x sum / Gamma(1/2) with sum starting at 1/a = 2.
    (-x2).exp() * x * sum / std::f64::consts::PI.sqrt()
}

/// The continued fraction F of Q(a, x) = e^{-x} x^a F / Gamma(a) (modified Lentz):
/// F = 1 / (x + 1 - a - 1 (1 - a) / (x + 3 - a - 2 (2 - a) / (x + 5 - a - ...))).
fn upper_gamma_fraction(a: f64, x: f64) -> f64 {
    let mut b = x + 1.0 - a;
    let mut f = Lentz::start(C_INFINITE, b);
    for i in 1..10_000 {
        b += 2.0;
        if (f.step(-(i as f64) * (i as f64 - a), b) - 1.0).abs() <= f64::EPSILON {
            break;
        }
    }
    f.h
}

#[cfg(test)]
// Reference values are quoted with all the digits they were computed to.
#[allow(clippy::excessive_precision)]
mod tests {
    use super::*;

    const ALL: [Sigmoid; 3] = [Sigmoid::Logistic, Sigmoid::Weibull, Sigmoid::Normal];

    #[test]
    fn complement_and_log_complement_agree_with_s() {
        for sig in ALL {
            for &z in &[-20.0, -3.0, -0.5, 0.0, 0.7, 2.0, 6.0] {
                let v = sig.eval(z);
                assert!((v.s + v.sc - 1.0).abs() < 1e-15, "{sig:?} {z}");
                assert!((v.ln_sc - v.sc.ln()).abs() < 1e-12 * v.sc.ln().abs().max(1.0));
            }
        }
    }

    #[test]
    fn inverse_round_trips() {
        for sig in ALL {
            for &q in &[1e-6, 0.1, 0.5, 0.75, 0.99] {
                let z = sig.inverse(q);
                assert!(
                    (sig.eval(z).s - q).abs() < 1e-12 * q.max(1e-3),
                    "{sig:?} {q}"
                );
            }
        }
        // Known values: logistic 0.5 -> 0; Gumbel 0.5 -> ln ln 2; normal 0.975 -> 1.959963985.
        assert_eq!(Sigmoid::Logistic.inverse(0.5), 0.0);
        assert!((Sigmoid::Weibull.inverse(0.5) - 2f64.ln().ln()).abs() < 1e-15);
        assert!((Sigmoid::Normal.inverse(0.975) - 1.959_963_984_540_054).abs() < 1e-9);
    }

    #[test]
    fn extreme_z_stays_finite() {
        for sig in ALL {
            for &z in &[-1e300, -1e6, 1e6, 1e300, f64::MAX] {
                let v = sig.eval(z);
                assert!(v.s.is_finite() && v.sc.is_finite() && v.ln_sc.is_finite());
            }
        }
    }

    #[test]
    fn ln_phi_matches_reference_in_the_far_tail() {
        // mpmath log(ncdf(z)) at 30 digits: ln Phi(-40) = -804.608442013753788,
        // ln Phi(-30) = -454.321243956343197; continuity across the series/fraction switch.
        assert!((ln_phi(-40.0) + 804.608_442_013_753_8).abs() < 1e-12);
        assert!((ln_phi(-30.0) + 454.321_243_956_343_2).abs() < 1e-12);
        let s = std::f64::consts::SQRT_2;
        assert!((ln_phi(-s * (1.0 - 1e-12)) - ln_phi(-s * (1.0 + 1e-12))).abs() < 1e-10);
    }

    #[test]
    fn erfc_matches_high_precision_reference() {
        // mpmath erfc at 30 digits; relative error a few ulps (bound 8 eps, 4 eps per
        // transcendental step of the continued fraction / series).
        for (x, v) in [
            (0.1, 0.887_537_083_981_715_101_6),
            (0.5, 0.479_500_122_186_953_462_3),
            (0.906, 0.200_096_217_371_523_010_0),
            (1.5, 0.033_894_853_524_689_272_93),
            (3.0, 2.209_049_699_858_544_137e-5),
            (6.0, 2.151_973_671_249_891_312e-17),
            (10.0, 2.088_487_583_762_544_757e-45),
            (-0.5, 1.520_499_877_813_046_537_7),
        ] {
            let got = erfc(x);
            assert!(
                ((got - v) / v).abs() < 8.0 * f64::EPSILON * (1.0 + x * x),
                "{x}: {got:e} vs {v:e}"
            );
        }
    }
}
