//! The report's tidy rows: `jnd.csv`, `fits.csv`, `ttests.csv` and the same rows in
//! `report.json`, one per fit or test.

use super::{GroupResult, Report};
use crate::bootstrap::{BootstrapResult, Bound, interval_text};
use crate::jnd::Threshold;
use crate::psychometric::{Fit, LapseMode, Shape};
use serde::Serialize;

/// A row of `jnd.csv`.
#[derive(Clone, Debug, Default, Serialize)]
pub struct JndRow {
    pub grouping: &'static str,
    pub label: String,
    /// `pooled` or the subject id.
    pub subject: String,
    pub fit_kind: &'static str,
    /// value | between | below_range | above_range | undefined
    pub threshold_kind: &'static str,
    pub threshold_spp: Option<f64>,
    /// Tested level the threshold is known to be above (between / above_range).
    pub threshold_above_level: Option<u32>,
    /// Tested level the threshold is known to be below (between / below_range).
    pub threshold_below_level: Option<u32>,
    pub threshold: String,
    pub ci_lower_kind: Option<&'static str>,
    pub ci_lower_spp: Option<f64>,
    pub ci_upper_kind: Option<&'static str>,
    pub ci_upper_spp: Option<f64>,
    pub ci: String,
    pub empirical_kind: &'static str,
    pub empirical_spp: Option<f64>,
    pub empirical: String,
    /// Pooled rows: the crossing of the mean of per-subject proportions (the thesis's reading
    /// of its figures); subject rows: the subject's empirical crossing.
    pub mean_crossing_spp: Option<f64>,
    pub mean_crossing: String,
    pub deviance: f64,
    pub deviance_p: Option<f64>,
    pub poor_fit: Option<bool>,
    pub trials: u32,
}

/// A row of `fits.csv`.
#[derive(Clone, Debug, Default, Serialize)]
pub struct FitRow {
    pub grouping: &'static str,
    pub label: String,
    pub subject: String,
    pub sigmoid: &'static str,
    pub lapse_mode: &'static str,
    pub kind: &'static str,
    pub alpha_ln_spp: Option<f64>,
    pub beta: Option<f64>,
    pub lapse: Option<f64>,
    /// Step fits: tested levels on the upper plateau.
    pub step_plateau_levels: Option<usize>,
    pub log_likelihood: f64,
    pub deviance: f64,
    pub deviance_p: Option<f64>,
    pub poor_fit: Option<bool>,
    pub location_at_bound: bool,
    pub levels: usize,
    pub trials: u32,
    pub note: String,
}

/// A row of `ttests.csv`.
#[derive(Clone, Debug, Default, Serialize)]
pub struct TTestRow {
    pub family: &'static str,
    pub a: String,
    pub b: String,
    pub level: u32,
    pub test: &'static str,
    /// `subject` or `cell`: what one observation of the test is.
    pub unit: &'static str,
    pub n_a: usize,
    pub n_b: usize,
    pub mean_a: f64,
    pub mean_b: f64,
    pub t: Option<f64>,
    pub df: Option<f64>,
    pub p: Option<f64>,
    pub p_holm: Option<f64>,
    pub alpha: f64,
    pub significant: Option<bool>,
    pub significant_holm: Option<bool>,
    pub cohens_d: Option<f64>,
    pub effect_size: &'static str,
    pub undefined_reason: String,
}

pub(super) fn threshold_cols(t: &Threshold) -> (Option<f64>, Option<u32>, Option<u32>) {
    match t {
        Threshold::Value { spp } => (Some(*spp), None, None),
        Threshold::Between { lower, upper } => (None, Some(*lower), Some(*upper)),
        Threshold::AtLevel {
            level,
            lower,
            upper,
        } => (Some(*level as f64), Some(*lower), Some(*upper)),
        Threshold::BelowRange { bound } => (None, None, Some(*bound)),
        Threshold::AboveRange { bound } => (None, Some(*bound), None),
        Threshold::Undefined { .. } => (None, None, None),
    }
}

pub(super) fn ci_text(b: &BootstrapResult) -> String {
    interval_text(&b.ci_lower, &b.ci_upper, ", ").map_or("none".into(), |i| format!("[{i}]"))
}

impl Report {
    pub fn jnd_rows(&self) -> Vec<JndRow> {
        let mut rows = Vec::new();
        for g in &self.groups {
            let (spp, above, below) = threshold_cols(&g.threshold);
            rows.push(JndRow {
                grouping: g.key.grouping.name(),
                label: g.key.label.clone(),
                subject: "pooled".into(),
                fit_kind: g.pooled.kind(),
                threshold_kind: g.threshold.kind(),
                threshold_spp: spp,
                threshold_above_level: above,
                threshold_below_level: below,
                threshold: g.threshold.display(),
                ci_lower_kind: g.bootstrap.ci_lower.as_ref().map(Bound::kind),
                ci_lower_spp: g.bootstrap.ci_lower.as_ref().and_then(Bound::spp),
                ci_upper_kind: g.bootstrap.ci_upper.as_ref().map(Bound::kind),
                ci_upper_spp: g.bootstrap.ci_upper.as_ref().and_then(Bound::spp),
                ci: ci_text(&g.bootstrap),
                empirical_kind: g.empirical.kind(),
                empirical_spp: threshold_cols(&g.empirical).0,
                empirical: g.empirical.display(),
                mean_crossing_spp: threshold_cols(&g.mean_crossing).0,
                mean_crossing: g.mean_crossing.display(),
                deviance: g.pooled.deviance,
                deviance_p: Some(g.bootstrap.deviance_p),
                poor_fit: Some(g.poor_fit),
                trials: g.pooled.curve.total_trials(),
            });
            for s in &g.subjects {
                let (spp, above, below) = threshold_cols(&s.threshold);
                rows.push(JndRow {
                    grouping: g.key.grouping.name(),
                    label: g.key.label.clone(),
                    subject: s.subject.clone(),
                    fit_kind: s.fit.kind(),
                    threshold_kind: s.threshold.kind(),
                    threshold_spp: spp,
                    threshold_above_level: above,
                    threshold_below_level: below,
                    threshold: s.threshold.display(),
                    ci_lower_kind: None,
                    ci_lower_spp: None,
                    ci_upper_kind: None,
                    ci_upper_spp: None,
                    ci: String::new(),
                    empirical_kind: s.empirical.kind(),
                    empirical_spp: threshold_cols(&s.empirical).0,
                    empirical: s.empirical.display(),
                    mean_crossing_spp: threshold_cols(&s.empirical).0,
                    mean_crossing: s.empirical.display(),
                    deviance: s.fit.deviance,
                    deviance_p: None,
                    poor_fit: None,
                    trials: s.fit.curve.total_trials(),
                });
            }
        }
        rows
    }

    pub fn fit_rows(&self) -> Vec<FitRow> {
        let row = |g: &GroupResult, subject: &str, f: &Fit, boot: Option<&BootstrapResult>| {
            let (alpha, beta, lapse, plateau, note) = match &f.shape {
                Shape::Finite(m) => (
                    Some(m.alpha),
                    Some(m.beta),
                    Some(m.lapse),
                    None,
                    String::new(),
                ),
                Shape::Step(s) => (
                    None,
                    None,
                    Some(s.lapse),
                    Some(s.plateau_levels),
                    "likelihood maximised by a step (infinite slope)".to_string(),
                ),
                Shape::Unidentified { reason } => (None, None, None, None, reason.clone()),
            };
            FitRow {
                grouping: g.key.grouping.name(),
                label: g.key.label.clone(),
                subject: subject.to_string(),
                sigmoid: f.settings.sigmoid.name(),
                lapse_mode: match f.settings.lapse {
                    LapseMode::Fixed => "fixed",
                    LapseMode::Free => "free",
                },
                kind: f.kind(),
                alpha_ln_spp: alpha,
                beta,
                lapse,
                step_plateau_levels: plateau,
                log_likelihood: f.log_likelihood,
                deviance: f.deviance,
                deviance_p: boot.map(|b| b.deviance_p),
                poor_fit: boot.map(|_| g.poor_fit),
                location_at_bound: f.location_at_bound,
                levels: f.curve.points.len(),
                trials: f.curve.total_trials(),
                note,
            }
        };
        let mut rows = Vec::new();
        for g in &self.groups {
            rows.push(row(g, "pooled", &g.pooled, Some(&g.bootstrap)));
            for s in &g.subjects {
                rows.push(row(g, &s.subject, &s.fit, None));
            }
        }
        rows
    }

    pub fn ttest_rows(&self) -> Vec<TTestRow> {
        self.comparisons
            .iter()
            .map(|c| {
                let st = c.test.result.as_ref().ok();
                TTestRow {
                    family: c.family.name(),
                    a: c.a.clone(),
                    b: c.b.clone(),
                    level: c.level,
                    test: c.test.kind.name(),
                    unit: self.settings.comparisons.unit.name(),
                    n_a: c.test.n1,
                    n_b: c.test.n2,
                    mean_a: c.test.mean1,
                    mean_b: c.test.mean2,
                    t: st.map(|s| s.t),
                    df: st.map(|s| s.df),
                    p: st.map(|s| s.p),
                    p_holm: c.p_holm,
                    alpha: self.settings.comparisons.alpha,
                    significant: c.significant,
                    significant_holm: c.significant_holm,
                    cohens_d: st.map(|s| s.d),
                    effect_size: c.test.kind.effect_size_name(),
                    undefined_reason: c.test.result.as_ref().err().cloned().unwrap_or_default(),
                }
            })
            .collect()
    }
}
