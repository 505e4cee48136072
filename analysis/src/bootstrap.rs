//! Parametric bootstrap: confidence intervals for the JND and the goodness of fit.
//!
//! Each resample draws new binomial counts from the fitted function at the tested levels (same
//! trials per level) and refits them the same way. Resample r of a group uses only
//! hash(seed, [group id, r, level index, trial]), so the replicates do not depend on the thread
//! count or on which other groups are analyzed.
//!
//! A replicate's threshold may be an interval (a step fit) or out of range. The interval's
//! lower end is taken from the replicates' lower ends and its upper end from their upper ends
//! (out of range counting as -inf / +inf): a conservative percentile interval that never
//! averages an interval into a number. An end beyond the tested levels is reported as such.

use crate::data::{Curve, LevelCount};
use crate::jnd::{Threshold, model_threshold};
use crate::psychometric::{Fit, fit_with};
use rayon::prelude::*;
use renderer::hash::{hash, unit_f64};
use serde::Serialize;

/// How to bootstrap.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct BootstrapSettings {
    pub resamples: usize,
    pub seed: u64,
    /// Proportion correct defining the JND.
    pub target: f64,
    /// Coverage of the interval (0.95).
    pub confidence: f64,
}

/// One end of a confidence interval.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Bound {
    Value {
        spp: f64,
    },
    /// The end lies below the lowest tested level.
    BelowRange {
        bound: u32,
    },
    /// The end lies above the highest tested level.
    AboveRange {
        bound: u32,
    },
}

/// An interval as text, its ends joined by `join`; `None` unless both ends exist.
pub fn interval_text(lower: &Option<Bound>, upper: &Option<Bound>, join: &str) -> Option<String> {
    match (lower, upper) {
        (Some(l), Some(u)) => Some(format!("{}{join}{}", l.display(), u.display())),
        _ => None,
    }
}

impl Bound {
    pub fn display(&self) -> String {
        match self {
            Bound::Value { spp } => format!("{spp:.1}"),
            Bound::BelowRange { bound } => format!("< {bound}"),
            Bound::AboveRange { bound } => format!("> {bound}"),
        }
    }

    pub fn kind(&self) -> &'static str {
        match self {
            Bound::Value { .. } => "value",
            Bound::BelowRange { .. } => "below_range",
            Bound::AboveRange { .. } => "above_range",
        }
    }

    pub fn spp(&self) -> Option<f64> {
        match self {
            Bound::Value { spp } => Some(*spp),
            _ => None,
        }
    }

    fn from_ln(x: f64, curve: &Curve) -> Bound {
        let first = curve.points.first().map_or(1, |p| p.level);
        let last = curve.points.last().map_or(1, |p| p.level);
        if x == f64::NEG_INFINITY {
            Bound::BelowRange { bound: first }
        } else if x == f64::INFINITY {
            Bound::AboveRange { bound: last }
        } else {
            Bound::Value { spp: x.exp() }
        }
    }
}

/// What the bootstrap found for one fit.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BootstrapResult {
    pub resamples: usize,
    pub confidence: f64,
    /// The JND interval; `None` when no replicate had a threshold.
    pub ci_lower: Option<Bound>,
    pub ci_upper: Option<Bound>,
    /// Replicates whose threshold was read from a step fit (an interval or a step through a
    /// level).
    pub step_replicates: usize,
    /// Deviance of the original fit and the share of replicates at least as large
    /// ((1 + count) / (1 + resamples)).
    pub deviance: f64,
    pub deviance_p: f64,
}

/// Binomial counts drawn from `p` at the curve's levels for resample `r`.
pub fn resample(curve: &Curve, p: &[f64], seed: u64, group: u64, r: u64) -> Curve {
    Curve {
        points: curve
            .points
            .iter()
            .zip(p)
            .enumerate()
            .map(|(i, (c, &pi))| {
                let correct = (0..c.trials)
                    .filter(|&j| unit_f64(hash(seed, &[group, r, i as u64, j as u64])) < pi)
                    .count() as u32;
                LevelCount {
                    level: c.level,
                    correct,
                    trials: c.trials,
                }
            })
            .collect(),
    }
}

/// Bootstrap a fit. `group` keys the random stream (e.g. [`crate::data::GroupKey::id`]).
pub fn bootstrap(fit: &Fit, group: u64, s: &BootstrapSettings) -> BootstrapResult {
    let warm = fit.warm_start();
    let replicates: Vec<(Threshold, f64)> = (0..s.resamples as u64)
        .into_par_iter()
        .map(|r| {
            let data = resample(&fit.curve, &fit.fitted, s.seed, group, r);
            let f = fit_with(&data, &fit.settings, warm.as_ref());
            (model_threshold(&f, s.target), f.deviance)
        })
        .collect();
    summarize(fit, &replicates, s)
}

fn summarize(fit: &Fit, replicates: &[(Threshold, f64)], s: &BootstrapSettings) -> BootstrapResult {
    let mut lows = Vec::with_capacity(replicates.len());
    let mut highs = Vec::with_capacity(replicates.len());
    let mut steps = 0;
    for (t, _) in replicates {
        if let Some((lo, hi)) = t.ln_bounds() {
            lows.push(lo);
            highs.push(hi);
        }
        steps += matches!(t, Threshold::Between { .. } | Threshold::AtLevel { .. }) as usize;
    }
    lows.sort_by(f64::total_cmp);
    highs.sort_by(f64::total_cmp);
    // Nearest-rank percentiles: with R replicates the k-th smallest lower end and the k-th
    // largest upper end, k = floor(R (1 - confidence) / 2) (0-based), e.g. 50 of 2000.
    let (ci_lower, ci_upper) = if lows.is_empty() {
        (None, None)
    } else {
        let k = ((lows.len() as f64) * (1.0 - s.confidence) / 2.0).floor() as usize;
        let k = k.min(lows.len() - 1);
        (
            Some(Bound::from_ln(lows[k], &fit.curve)),
            Some(Bound::from_ln(highs[highs.len() - 1 - k], &fit.curve)),
        )
    };
    let exceed = replicates
        .iter()
        .filter(|(_, d)| *d >= fit.deviance)
        .count();
    BootstrapResult {
        resamples: replicates.len(),
        confidence: s.confidence,
        ci_lower,
        ci_upper,
        step_replicates: steps,
        deviance: fit.deviance,
        deviance_p: (1 + exceed) as f64 / (1 + replicates.len()) as f64,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::psychometric::{FitSettings, fit};

    fn pooled() -> Curve {
        Curve::from_counts([
            (1, 47, 48),
            (8, 44, 48),
            (27, 39, 48),
            (64, 30, 48),
            (125, 27, 48),
            (216, 25, 48),
            (343, 24, 48),
            (512, 25, 48),
        ])
    }

    fn settings(resamples: usize) -> BootstrapSettings {
        BootstrapSettings {
            resamples,
            seed: 7,
            target: 0.75,
            confidence: 0.95,
        }
    }

    #[test]
    fn resampling_is_deterministic_and_keyed() {
        let c = pooled();
        let p = vec![0.8; c.points.len()];
        assert_eq!(resample(&c, &p, 1, 2, 3), resample(&c, &p, 1, 2, 3));
        assert_ne!(resample(&c, &p, 1, 2, 3), resample(&c, &p, 1, 2, 4));
        assert_ne!(resample(&c, &p, 1, 2, 3), resample(&c, &p, 1, 5, 3));
    }

    #[test]
    fn interval_brackets_the_estimate_and_is_thread_count_independent() {
        let f = fit(&pooled(), &FitSettings::default());
        let jnd = match model_threshold(&f, 0.75) {
            Threshold::Value { spp } => spp,
            t => panic!("{t:?}"),
        };
        let a = bootstrap(&f, 11, &settings(200));
        let lo = a.ci_lower.as_ref().and_then(Bound::spp).unwrap();
        let hi = a.ci_upper.as_ref().and_then(Bound::spp).unwrap();
        assert!(lo < jnd && jnd < hi, "{lo} {jnd} {hi}");
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| bootstrap(&f, 11, &settings(200)));
        assert_eq!(a, one);
        assert!(a.deviance_p > 0.0 && a.deviance_p <= 1.0);
    }

    #[test]
    fn non_monotone_data_is_flagged_by_the_deviance_p_value() {
        // Rises then falls: a monotone function cannot follow it.
        let c = Curve::from_counts([
            (1, 26, 48),
            (8, 46, 48),
            (27, 25, 48),
            (64, 46, 48),
            (125, 24, 48),
            (216, 45, 48),
        ]);
        let f = fit(&c, &FitSettings::default());
        let b = bootstrap(&f, 3, &settings(200));
        assert!(b.deviance_p < 0.05, "{b:?}");
        assert!(b.ci_lower.is_some() && b.ci_upper.is_some());
    }

    #[test]
    fn all_correct_data_gives_an_above_range_interval_end() {
        let c = Curve::from_counts([(1, 48, 48), (8, 48, 48), (27, 48, 48)]);
        let f = fit(&c, &FitSettings::default());
        let b = bootstrap(&f, 3, &settings(50));
        assert_eq!(b.ci_upper, Some(Bound::AboveRange { bound: 27 }));
        assert_eq!(b.ci_lower, Some(Bound::AboveRange { bound: 27 }));
        assert_eq!(b.deviance_p, 1.0);
    }
}
