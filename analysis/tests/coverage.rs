//! Coverage of the bootstrap interval: across many simulated pooled data sets with a known
//! threshold, the 95% interval must contain it about 95% of the time.

use analysis::bootstrap::{BootstrapSettings, Bound, bootstrap};
use analysis::psychometric::{FitSettings, Model, fit};
use analysis::sigmoid::Sigmoid;
use analysis::simulate::simulate_curve;

/// `datasets` pooled curves (8 thesis levels x 48 trials, logistic, threshold 40 spp,
/// slope 1.5 / ln spp), each bootstrapped with `resamples`; returns the coverage rate.
fn coverage(datasets: u64, resamples: usize) -> f64 {
    let truth = Model {
        sigmoid: Sigmoid::Logistic,
        alpha: 40f64.ln(),
        beta: 1.5,
        lapse: 0.0,
        guess: 0.5,
    };
    let levels = [1, 8, 27, 64, 125, 216, 343, 512];
    let settings = BootstrapSettings {
        resamples,
        seed: 99,
        target: 0.75,
        confidence: 0.95,
    };
    let mut covered = 0;
    for d in 0..datasets {
        let curve = simulate_curve(&truth, &levels, 48, 1234, &[d]);
        let f = fit(&curve, &FitSettings::default());
        let b = bootstrap(&f, d, &settings);
        let lo = match b.ci_lower {
            Some(Bound::Value { spp }) => spp,
            Some(Bound::BelowRange { .. }) => 0.0,
            _ => f64::INFINITY,
        };
        let hi = match b.ci_upper {
            Some(Bound::Value { spp }) => spp,
            Some(Bound::AboveRange { .. }) => f64::INFINITY,
            _ => 0.0,
        };
        covered += (lo <= 40.0 && 40.0 <= hi) as u32;
    }
    covered as f64 / datasets as f64
}

/// The slow suite (issue 41): statistical runs that `.ci/run` runs as their own step.
mod slow_suite {
    use super::*;

    #[test]
    #[ignore = "slow suite: run by .ci/run, or cargo test --workspace --tests -- --ignored slow_suite::"]
    fn bootstrap_interval_covers_the_true_threshold_about_95_percent() {
        // Expected rate. With R resamples the interval runs from the (k+1)-th smallest replicate
        // threshold to the (k+1)-th largest, k = floor(0.025 R). If the true threshold behaves like
        // one more replicate (the premise of the percentile interval), its rank among the R + 1
        // values is uniform and the interval holds it with probability (R - 2k - 1) / (R + 1):
        // 0.949 for the CLI's R = 2000, and exactly 0.95 for R = 39 (k = 0: the range of the 39
        // replicates), which is used here to make the test cheap without changing what it tests.
        // Tolerance. The observed rate over D independent data sets is binomial: sd =
        // sqrt(0.95 * 0.05 / D) = 0.0109 for D = 400; accept within 3 sd, [0.917, 0.983] (a
        // correct method fails with probability 0.3%; with the fixed seeds the result is fixed).
        // A departure beyond that is a real coverage error of the method, not noise.
        let (datasets, resamples) = (400, 39);
        let k = (resamples as f64 * 0.025).floor();
        let expected = (resamples as f64 - 2.0 * k - 1.0) / (resamples as f64 + 1.0);
        assert_eq!(expected, 0.95);
        let sd = (expected * (1.0 - expected) / datasets as f64).sqrt();
        let t = std::time::Instant::now();
        let rate = coverage(datasets, resamples);
        eprintln!(
            "coverage {rate} (expected {expected}, sd {sd:.4}) in {:?}",
            t.elapsed()
        );
        assert!((rate - expected).abs() <= 3.0 * sd, "coverage {rate}");
    }
}

/// The same at the CLI's 2000 resamples (expected (2000 - 101) / 2001 = 0.949): too slow for
/// CI, run with `cargo test --release -p analysis --test coverage -- --ignored`.
#[test]
#[ignore]
fn coverage_at_the_cli_resample_count() {
    let (datasets, resamples) = (400, 2000);
    let k = (resamples as f64 * 0.025).floor();
    let expected = (resamples as f64 - 2.0 * k - 1.0) / (resamples as f64 + 1.0);
    let sd = (expected * (1.0 - expected) / datasets as f64).sqrt();
    let rate = coverage(datasets, resamples);
    eprintln!("coverage {rate} (expected {expected:.4}, sd {sd:.4})");
    assert!((rate - expected).abs() <= 3.0 * sd, "coverage {rate}");
}
