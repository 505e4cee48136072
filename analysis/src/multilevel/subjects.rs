//! The subject bootstrap: resample whole subjects with replacement and refit the multilevel
//! model, so the interval needs no assumption on the distribution of the subjects' thresholds.
//! Resample r draws subject j as `hash(seed, [key, r, j])`, so the replicates do not depend on
//! the thread count or on which other groups are analyzed.

use super::{Context, Estimate, bound_of, fit_informative};
use crate::bootstrap::Bound;
use crate::data::Curve;
use rayon::prelude::*;
use renderer::hash::{hash, unit_f64};
use serde::Serialize;

/// A percentile interval of a statistic over subject resamples.
#[derive(Clone, Debug, Serialize)]
pub struct SubjectBootstrap {
    pub resamples: usize,
    /// Resamples whose model could be fitted (a resample of fewer than two distinct subjects
    /// with data cannot).
    pub fitted: usize,
    /// Nearest-rank percentile ends of the statistic (ln spp).
    pub ln_lower: f64,
    pub ln_upper: f64,
    /// Standard deviation of the replicates.
    pub sd: f64,
    /// The ends as spp, never extrapolated (a JND; unset for a difference).
    pub ci_lower: Option<Bound>,
    pub ci_upper: Option<Bound>,
}

impl SubjectBootstrap {
    pub(super) fn with_bounds(mut self, lo: f64, hi: f64, levels: (u32, u32)) -> Self {
        self.ci_lower = Some(bound_of(self.ln_lower, lo, hi, levels));
        self.ci_upper = Some(bound_of(self.ln_upper, lo, hi, levels));
        self
    }
}

/// Resample `r` of the subjects `with_data`: as many draws, with replacement.
pub fn resample_subjects(with_data: &[usize], seed: u64, key: u64, r: u64) -> Vec<usize> {
    let n = with_data.len();
    (0..n as u64)
        .map(|j| with_data[((unit_f64(hash(seed, &[key, r, j])) * n as f64) as usize).min(n - 1)])
        .collect()
}

/// The statistic `stat` of the model of `curves` (without their same-video levels) over subject
/// resamples, refitted from `warm`.
pub fn replicates(
    curves: &[&[Curve]],
    shared_threshold: bool,
    cx: &Context,
    warm: &[f64],
    key: u64,
    stat: impl Fn(&Estimate) -> f64 + Sync,
) -> Vec<f64> {
    let with_data = super::model::Counts::new(curves).subjects;
    (0..cx.settings.resamples as u64)
        .into_par_iter()
        .filter_map(|r| {
            let pick = resample_subjects(&with_data, cx.settings.seed, key, r);
            let drawn: Vec<Vec<Curve>> = curves
                .iter()
                .map(|c| pick.iter().map(|&s| c[s].clone()).collect())
                .collect();
            let refs: Vec<&[Curve]> = drawn.iter().map(|c| c.as_slice()).collect();
            fit_informative(&refs, shared_threshold, cx, Some(warm)).map(|(e, _)| stat(&e))
        })
        .collect()
}

/// Summarise replicates: nearest-rank percentiles at the settings' confidence; `None` when no
/// resample could be fitted.
pub fn summarize(
    mut reps: Vec<f64>,
    resamples: usize,
    confidence: f64,
) -> Option<SubjectBootstrap> {
    reps.sort_by(f64::total_cmp);
    let n = reps.len();
    if n == 0 {
        return None;
    }
    let k = ((n as f64) * (1.0 - confidence) / 2.0).floor() as usize;
    let mean = reps.iter().sum::<f64>() / n.max(1) as f64;
    let var = reps.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n.max(2) - 1) as f64;
    Some(SubjectBootstrap {
        resamples,
        fitted: n,
        ln_lower: reps[k.min(n - 1)],
        ln_upper: reps[n.saturating_sub(1 + k)],
        sd: var.sqrt(),
        ci_lower: None,
        ci_upper: None,
    })
}

/// The subject bootstrap of a one-group model's population ln JND.
pub(super) fn bootstrap_group(
    curves: &[&[Curve]],
    cx: &Context,
    warm: &[f64],
    key: u64,
) -> Option<SubjectBootstrap> {
    let reps = replicates(curves, false, cx, warm, key, |e| e.params.thresholds[0]);
    summarize(reps, cx.settings.resamples, cx.settings.confidence)
}
