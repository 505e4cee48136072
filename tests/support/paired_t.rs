//! The exact rejection probability of a two-sided paired t-test whose n differences are
//! independent draws of a small integer variable (a subject's correct answers in one group
//! minus those in another; dividing both by the trial count does not change t).
//!
//! t depends on the data only through S = sum d_i and Q = sum d_i^2:
//!
//!     t = mean / (sd / sqrt n) = S sqrt(n - 1) / sqrt(n Q - S^2),
//!
//! so the joint distribution of (S, Q), built by adding one subject at a time, gives the test's
//! exact distribution, with no normal approximation. n Q = S^2 means zero variance, which the
//! analysis reports as undefined (never significant).

use analysis::student_t::two_sided_p;

/// P(p < alpha) for the two-sided paired t-test over `n` subjects whose differences d have
/// `P(d = i - m) = pmf[i]`, m = (pmf.len() - 1) / 2, split by the sign of t: the rejections
/// with t < 0 and those with t > 0.
#[derive(Clone, Copy, Debug)]
pub struct Rejection {
    pub negative: f64,
    pub positive: f64,
}

impl Rejection {
    pub fn total(self) -> f64 {
        self.negative + self.positive
    }
}

pub fn rejection_probability(pmf: &[f64], n: usize, alpha: f64) -> Rejection {
    let m = (pmf.len() as i64 - 1) / 2;
    let s_max = n as i64 * m;
    let q_max = n as i64 * m * m;
    let q_span = (q_max + 1) as usize;
    let at = |s: i64, q: i64| (s + s_max) as usize * q_span + q as usize;
    let mut cur = vec![0.0; (2 * s_max + 1) as usize * q_span];
    cur[at(0, 0)] = 1.0;
    for step in 0..n as i64 {
        let mut next = vec![0.0; cur.len()];
        for s in -step * m..=step * m {
            for q in 0..=step * m * m {
                let w = cur[at(s, q)];
                if w == 0.0 {
                    continue;
                }
                for (i, &pd) in pmf.iter().enumerate() {
                    let d = i as i64 - m;
                    next[at(s + d, q + d * d)] += w * pd;
                }
            }
        }
        cur = next;
    }
    let n_f = n as f64;
    let mut reject = Rejection {
        negative: 0.0,
        positive: 0.0,
    };
    for s in -s_max..=s_max {
        for q in 0..=q_max {
            let w = cur[at(s, q)];
            let spread = n as i64 * q - s * s;
            if w == 0.0 || spread <= 0 {
                continue;
            }
            let t = s as f64 * (n_f - 1.0).sqrt() / (spread as f64).sqrt();
            if two_sided_p(t, n_f - 1.0) < alpha {
                if t < 0.0 {
                    reject.negative += w;
                } else {
                    reject.positive += w;
                }
            }
        }
    }
    reject
}

#[test]
fn a_small_case_matches_enumeration() {
    // d in {-1, 0, 1} with probabilities 1/4, 1/2, 1/4 over n = 4 subjects: all 81 outcomes,
    // each tested with the textbook statistic mean / (sd / sqrt n).
    let pmf = [0.25, 0.5, 0.25];
    let n = 4;
    let (mut expected, mut expected_negative) = (0.0, 0.0);
    for code in 0..81 {
        let d: Vec<f64> = (0..n)
            .map(|k| ((code / 3i64.pow(k)) % 3 - 1) as f64)
            .collect();
        let p: f64 = d.iter().map(|&x| pmf[(x + 1.0) as usize]).product();
        let mean = d.iter().sum::<f64>() / n as f64;
        let var = d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n as f64 - 1.0);
        if var > 1e-12 && two_sided_p(mean / (var / n as f64).sqrt(), n as f64 - 1.0) < 0.2 {
            expected += p;
            expected_negative += if mean < 0.0 { p } else { 0.0 };
        }
    }
    let got = rejection_probability(&pmf, n as usize, 0.2);
    assert!(
        expected > 0.01 && (got.total() - expected).abs() < 1e-12,
        "{got:?} vs {expected}"
    );
    // A symmetric difference: each tail holds half.
    assert!((got.negative - expected_negative).abs() < 1e-12, "{got:?}");
    assert!((got.negative - 0.5 * expected).abs() < 1e-12, "{got:?}");
}
