//! From the visible difference to proportion correct: d' = k Q, and the proportion correct of
//! d' in the two-pair task of the suite's experiment (which pair held the difference?) and in
//! the two-interval forced choice of ModelFest (which interval held the stimulus?), each with
//! its Monte Carlo simulation. (How the observer compares the two videos to get Q is the
//! decision stage, [`super::decision_stage`].)
//!
//! **Two-pair task.**
//! Each presentation of a video gives the observer one value on a decision axis: the reference
//! ~ N(0, 1), the test ~ N(d', 1), with independent noise per presentation (so the identical
//! pair's two references differ too). The observer takes the differencing strategy of the
//! 4IAX / dual-pair task (Macmillan & Creelman 2005, "Detection Theory: A User's Guide", 2nd
//! ed., ch. 9): pick the pair whose values differ more. With U = x3 - x4 ~ N(d', 2) for the
//! reference/test pair and V = x1 - x2 ~ N(0, 2) for the identical pair,
//!
//! ```text
//! |U| > |V|  <=>  (U - V)(U + V) > 0,
//! ```
//!
//! and U - V, U + V are independent N(d', 4) (equal variances make them uncorrelated), so
//!
//! ```text
//! p_c = P(both > 0) + P(both < 0) = Phi(d'/2)^2 + Phi(-d'/2)^2.
//! ```
//!
//! d' = k Q: the pooled visible difference Q ([`super::pooling`]) times the sensitivity
//! constant k, fitted to ModelFest's 2IFC thresholds ([`DEFAULT_K`]). The
//! formula itself lives with the simulated observer (`experiment::predicted`), which answers
//! from it; this file holds the derivation, its inverse and the simulation that checks it.
//!
//! **2IFC (ModelFest).** One interval holds the blank ~ N(0, 1), the other the stimulus
//! ~ N(d', 1); the observer picks the larger. The difference is N(d', 2), so
//! p_c = Phi(d' / sqrt 2), and ModelFest's 84%-correct threshold is at
//! d' = sqrt 2 Phi^-1(0.84) = 1.4072 ([`two_ifc_d_prime_for`]).

use renderer::hash::{hash, unit_f64};

pub use experiment::predicted::{phi, two_pair_p_correct};

/// Default sensitivity constant k (d' per unit of Q): fitted with [`super::pooling::FITTED`] to
/// the 43 ModelFest thresholds by least squares on log thresholds (2IFC, 84% correct;
/// `blurlab predict validate modelfest`).
pub const DEFAULT_K: f64 = 4.1813;

/// d' at which the two-pair task's proportion correct is `p` (0.5 < p < 1); solves
/// Phi(d/2)^2 + Phi(-d/2)^2 = p: with a = Phi(d/2), a^2 + (1 - a)^2 = p, so
/// a = (1 + sqrt(2p - 1)) / 2.
pub fn d_prime_for(p: f64) -> Option<f64> {
    if !(p > 0.5 && p < 1.0) {
        return None;
    }
    let a = 0.5 * (1.0 + (2.0 * p - 1.0).sqrt());
    Some(2.0 * inverse_phi(a))
}

/// Proportion correct of 2IFC detection at separation `d_prime`: Phi(d' / sqrt 2).
pub fn two_ifc_p_correct(d_prime: f64) -> f64 {
    phi(d_prime / std::f64::consts::SQRT_2)
}

/// ModelFest's threshold criterion, proportion correct in 2IFC (at d' = 1.4072).
pub const CRITERION: f64 = 0.84;

/// d' at which 2IFC detection is `p` correct (0.5 < p < 1): sqrt 2 Phi^-1(p).
pub fn two_ifc_d_prime_for(p: f64) -> Option<f64> {
    (p > 0.5 && p < 1.0).then(|| std::f64::consts::SQRT_2 * inverse_phi(p))
}

/// Inverse standard normal CDF by bisection on [`phi`] (exact to rounding; not a hot path).
fn inverse_phi(p: f64) -> f64 {
    let (mut lo, mut hi) = (-40.0f64, 40.0f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if phi(mid) < p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// A standard normal from two uniforms of the counter-based hash (Box-Muller).
fn normal(seed: u64, trial: u64, i: u64) -> f64 {
    let u1 = unit_f64(hash(seed, &[trial, 2 * i]));
    let u2 = unit_f64(hash(seed, &[trial, 2 * i + 1]));
    // 1 - u1 is in (0, 1]: the logarithm stays finite.
    (-2.0 * (1.0 - u1).ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
}

/// Monte Carlo of the task itself: `trials` trials at separation `d_prime`, each drawing the
/// four presentations (the test's pair first or second, the test left or right, as the
/// experiment balances them) and answering by the differencing rule. Returns the proportion
/// correct.
pub fn simulate_task(d_prime: f64, trials: u64, seed: u64) -> f64 {
    let mut correct = 0u64;
    for t in 0..trials {
        let diff_pair = 1 + (t % 2) as usize;
        let test_left = (t / 2) % 2 == 0;
        let mut x = [0.0; 4];
        for (i, v) in x.iter_mut().enumerate() {
            *v = normal(seed, t, i as u64);
        }
        let test_index = 2 * (diff_pair - 1) + if test_left { 0 } else { 1 };
        x[test_index] += d_prime;
        let answer = if (x[0] - x[1]).abs() > (x[2] - x[3]).abs() {
            1
        } else {
            2
        };
        correct += (answer == diff_pair) as u64;
    }
    correct as f64 / trials as f64
}

/// Monte Carlo of 2IFC detection: `trials` trials at separation `d_prime`, the stimulus in
/// the first or second interval by turns, the observer picking the interval with the larger
/// value. Returns the proportion correct.
pub fn simulate_two_ifc(d_prime: f64, trials: u64, seed: u64) -> f64 {
    let mut correct = 0u64;
    for t in 0..trials {
        let stimulus = (t % 2) as usize;
        let mut x = [normal(seed, t, 0), normal(seed, t, 1)];
        x[stimulus] += d_prime;
        let answer = if x[0] > x[1] { 0 } else { 1 };
        correct += (answer == stimulus) as u64;
    }
    correct as f64 / trials as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_formula_matches_a_simulation_of_the_task() {
        // 200 000 trials per d': binomial sd <= 0.0011; allow 4 sd.
        let n = 200_000;
        for (i, d) in [0.0, 0.5, 1.0, 2.0, 2.1036, 3.0, 5.0]
            .into_iter()
            .enumerate()
        {
            let p = two_pair_p_correct(d);
            let sim = simulate_task(d, n, 17 + i as u64);
            let sd = (p * (1.0 - p) / n as f64).sqrt().max(1e-6);
            assert!(
                (sim - p).abs() < 4.0 * sd + 1e-9,
                "d' {d}: formula {p}, simulated {sim}"
            );
        }
    }

    #[test]
    fn the_two_ifc_formula_matches_a_simulation() {
        // 200 000 trials per d': binomial sd <= 0.0011; allow 4 sd.
        let n = 200_000;
        let d84 = two_ifc_d_prime_for(0.84).unwrap();
        assert!((d84 - 1.4064).abs() < 1e-4, "{d84}");
        for (i, d) in [0.0, 0.5, 1.0, d84, 2.0, 3.0].into_iter().enumerate() {
            let p = two_ifc_p_correct(d);
            let sim = simulate_two_ifc(d, n, 31 + i as u64);
            let sd = (p * (1.0 - p) / n as f64).sqrt();
            assert!(
                (sim - p).abs() < 4.0 * sd,
                "d' {d}: formula {p}, simulated {sim}"
            );
        }
        assert!((two_ifc_p_correct(d84) - 0.84).abs() < 1e-12);
        assert_eq!(two_ifc_d_prime_for(1.0), None);
    }

    #[test]
    fn inverse_and_exact_chance() {
        assert_eq!(two_pair_p_correct(0.0), 0.5);
        for p in [0.51, 0.6, 0.75, 0.9, 0.99] {
            let d = d_prime_for(p).unwrap();
            assert!((two_pair_p_correct(d) - p).abs() < 1e-12, "{p}");
        }
        assert_eq!(d_prime_for(0.5), None);
        // Less sensitive than 2AFC detection at the same d' (p = Phi(d' / sqrt 2)): the
        // identical pair's own noise and the unknown sign of the difference cost accuracy.
        assert!(two_pair_p_correct(1.0) < two_ifc_p_correct(1.0));
        // d' = 1 gives 57.3% in the two-pair task (docs/predict.md).
        assert!((two_pair_p_correct(1.0) - 0.5734).abs() < 1e-4);
    }
}
