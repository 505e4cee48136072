//! The analysis of a whole study and its report: `jnd.csv`, `fits.csv`, `ttests.csv` (tidy,
//! one row per fit or test), `report.json` (the same rows, format `blurlab-report/1`) and
//! `report.md` tying tables and figures together with the methods stated.

use crate::bootstrap::{BootstrapResult, BootstrapSettings, bootstrap};
use crate::comparisons::{Comparison, ComparisonSettings, compare};
use crate::data::{Dataset, Exclusion, Group, GroupKey, Grouping, Source};
use crate::jnd::{Threshold, crossing, empirical_threshold, model_threshold};
use crate::multilevel::compare::compare_models;
use crate::multilevel::{Context, MultilevelSettings, group_models};
use crate::psychometric::{Fit, FitSettings, fit};
use serde::Serialize;

mod markdown;
mod multilevel;
mod rows;
mod thesis;
pub use multilevel::MultilevelReport;
pub use rows::{FitRow, JndRow, TTestRow};
pub use thesis::{ThesisRow, display_name, format_p, format_t};

/// The format tag of `report.json`.
pub const REPORT_FORMAT: &str = "blurlab-report/1";

/// Everything that shapes the analysis.
#[derive(Clone, Debug, Serialize)]
pub struct Settings {
    pub fit: FitSettings,
    pub target: f64,
    pub bootstrap: BootstrapSettings,
    pub comparisons: ComparisonSettings,
    /// Deviance bootstrap p below this flags a poor fit.
    pub poor_fit_p: f64,
    /// A report laid out like a publication's (`--preset`).
    pub preset: Option<Preset>,
    /// The multilevel model across subjects (`--model multilevel`), if asked for.
    pub multilevel: Option<MultilevelSettings>,
}

/// Analyses laid out as a publication did them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Preset {
    /// The thesis's Chapter V: t-tests per subject x other-factor cell, two-sided, alpha 0.05,
    /// no correction, at 27, 64, 125 spp (scenes also 216), its pair order and sign; Tables 1
    /// and 2 as printed (`report.md`, `thesis_tables.csv`); its JND reading beside the fit.
    Thesis,
}

renderer::named!(Preset, "preset", [Thesis => "thesis"]);

/// Mean and standard error over subjects at one level.
#[derive(Clone, Debug, Serialize)]
pub struct LevelSummary {
    pub level: u32,
    pub mean: f64,
    /// `None` with fewer than two subjects.
    pub sem: Option<f64>,
    pub subjects: usize,
}

/// One subject's fit in one group.
#[derive(Clone, Debug, Serialize)]
pub struct SubjectResult {
    pub subject: String,
    pub fit: Fit,
    pub threshold: Threshold,
    pub empirical: Threshold,
}

/// Everything computed for one group.
#[derive(Clone, Debug, Serialize)]
pub struct GroupResult {
    pub key: GroupKey,
    pub pooled: Fit,
    pub threshold: Threshold,
    pub empirical: Threshold,
    /// The thesis's reading of its figures: where the mean over subjects of the per-subject
    /// proportions (the plotted points), joined by straight lines in ln spp, first falls
    /// through the target. Equals `empirical` when every subject has the same trials.
    pub mean_crossing: Threshold,
    pub bootstrap: BootstrapResult,
    pub poor_fit: bool,
    pub subjects: Vec<SubjectResult>,
    pub levels: Vec<LevelSummary>,
}

/// The analyzed study.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub settings: Settings,
    pub design: String,
    pub design_hash: String,
    pub subjects: Vec<String>,
    pub files: Vec<String>,
    pub trials: usize,
    pub warnings: Vec<String>,
    pub source: Source,
    /// Subjects left out (`--exclude`), with the reasons given.
    pub excluded: Vec<Exclusion>,
    /// Session logs per header `mode` (`gui`, `web`, `simulated`).
    pub sessions_by_mode: std::collections::BTreeMap<String, usize>,
    pub groups: Vec<GroupResult>,
    pub comparisons: Vec<Comparison>,
    /// The multilevel model's groups and comparisons (`--model multilevel`).
    pub multilevel: Option<MultilevelReport>,
}

impl Report {
    /// The results of one grouping, in the report's order.
    pub fn groups_of(&self, grouping: Grouping) -> impl Iterator<Item = &GroupResult> {
        self.groups
            .iter()
            .filter(move |g| g.key.grouping == grouping)
    }
}

/// Fit, bootstrap and test everything.
pub fn analyze(ds: &Dataset, s: &Settings) -> Report {
    let groups = ds.groups.iter().map(|g| analyze_group(ds, g, s)).collect();
    Report {
        settings: s.clone(),
        design: ds.design.clone(),
        design_hash: ds.design_hash.clone(),
        subjects: ds.subjects.clone(),
        files: ds.files.iter().map(|f| f.display().to_string()).collect(),
        trials: ds.trials,
        warnings: ds.warnings.clone(),
        source: ds.source,
        excluded: ds.excluded.clone(),
        sessions_by_mode: ds.sessions_by_mode.clone(),
        groups,
        comparisons: compare(ds, &s.comparisons),
        multilevel: s.multilevel.as_ref().map(|m| {
            let cx = Context {
                fit: &s.fit,
                target: s.target,
                settings: m,
                same_video_levels: &ds.same_video_levels,
            };
            MultilevelReport {
                same_video_levels: ds.same_video_levels.clone(),
                groups: group_models(ds, &cx),
                comparisons: compare_models(ds, &s.comparisons.order, &cx),
            }
        }),
    }
}

fn analyze_group(ds: &Dataset, g: &Group, s: &Settings) -> GroupResult {
    let pooled = fit(&g.pooled, &s.fit);
    let boot = bootstrap(&pooled, g.key.id(), &s.bootstrap);
    let subjects = g
        .per_subject
        .iter()
        .zip(&ds.subjects)
        .filter(|(c, _)| !c.points.is_empty())
        .map(|(c, name)| {
            let f = fit(c, &s.fit);
            SubjectResult {
                subject: name.clone(),
                threshold: model_threshold(&f, s.target),
                empirical: empirical_threshold(c, s.target),
                fit: f,
            }
        })
        .collect();
    let levels = level_summaries(g);
    let means: Vec<(u32, f64)> = levels.iter().map(|l| (l.level, l.mean)).collect();
    GroupResult {
        key: g.key.clone(),
        threshold: model_threshold(&pooled, s.target),
        empirical: empirical_threshold(&g.pooled, s.target),
        mean_crossing: crossing(&means, s.target),
        poor_fit: boot.deviance_p < s.poor_fit_p,
        bootstrap: boot,
        pooled,
        subjects,
        levels,
    }
}

/// Mean over subjects of per-subject proportions, with the standard error of that mean.
pub fn level_summaries(g: &Group) -> Vec<LevelSummary> {
    g.pooled
        .levels()
        .into_iter()
        .map(|level| {
            let p: Vec<f64> = g
                .subject_proportions(level)
                .into_iter()
                .map(|x| x.1)
                .collect();
            let n = p.len();
            let mean = p.iter().sum::<f64>() / n as f64;
            let sem = (n >= 2).then(|| {
                let v = p.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
                (v / n as f64).sqrt()
            });
            LevelSummary {
                level,
                mean,
                sem,
                subjects: n,
            }
        })
        .collect()
}
