//! The analysis of a whole study and its report: `jnd.csv`, `fits.csv`, `ttests.csv` (tidy,
//! one row per fit or test), `report.json` (the same rows, format `blurlab-report/1`) and
//! `report.md` tying tables and figures together with the methods stated.

use crate::bootstrap::{BootstrapResult, BootstrapSettings, Bound, bootstrap, interval_text};
use crate::comparisons::{Comparison, ComparisonSettings, compare};
use crate::data::{Dataset, Exclusion, Group, GroupKey, Grouping, Source};
use crate::jnd::{Threshold, crossing, empirical_threshold, model_threshold};
use crate::psychometric::{Fit, FitSettings, LAPSE_MAX, LapseMode, Shape, fit};
use anyhow::Result;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;

mod thesis;
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
}

/// Analyses laid out as a publication did them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
pub enum Preset {
    /// The thesis's Chapter V: t-tests per subject x other-factor cell, two-sided, alpha 0.05,
    /// no correction, at 27, 64, 125 spp (scenes also 216), its pair order and sign; Tables 1
    /// and 2 as printed (`report.md`, `thesis_tables.csv`); its JND reading beside the fit.
    Thesis,
}

impl Default for Settings {
    /// The `analyze` command's defaults (logistic, lapse 0, target 0.75, 2000 resamples,
    /// paired tests at 27, 64, 125 and 216 spp for scenes, alpha 0.05).
    fn default() -> Self {
        crate::cli::AnalyzeArgs::new(Vec::new(), std::path::PathBuf::new())
            .settings()
            .expect("the command's defaults are valid")
    }
}

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
    pub groups: Vec<GroupResult>,
    pub comparisons: Vec<Comparison>,
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
        groups,
        comparisons: compare(ds, &s.comparisons),
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

fn threshold_cols(t: &Threshold) -> (Option<f64>, Option<u32>, Option<u32>) {
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

fn ci_text(b: &BootstrapResult) -> String {
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

    /// Write the CSV, JSON and Markdown files (and the figures) into `dir`, each atomically.
    pub fn write(&self, dir: &Path) -> Result<()> {
        write_csv(&dir.join("jnd.csv"), &self.jnd_rows())?;
        write_csv(&dir.join("fits.csv"), &self.fit_rows())?;
        write_csv(&dir.join("ttests.csv"), &self.ttest_rows())?;
        let json = serde_json::json!({
            "format": REPORT_FORMAT,
            "design": self.design,
            "design_hash": self.design_hash,
            "subjects": self.subjects,
            "files": self.files,
            "trials": self.trials,
            "warnings": self.warnings,
            "source": self.source,
            "excluded": self.excluded,
            "settings": self.settings,
            "jnd": self.jnd_rows(),
            "fits": self.fit_rows(),
            "ttests": self.ttest_rows(),
        });
        renderer::atomic::write_atomic(
            &dir.join("report.json"),
            (serde_json::to_string_pretty(&json)? + "\n").as_bytes(),
        )?;
        let thesis_csv = dir.join("thesis_tables.csv");
        if self.settings.preset == Some(Preset::Thesis) {
            write_csv(&thesis_csv, &self.thesis_rows())?;
        } else if thesis_csv.is_file() {
            // A preset run's tables left in this folder would no longer match the report.
            std::fs::remove_file(&thesis_csv)?;
        }
        let figures = crate::figures::draw_all(self, &dir.join("figures"))?;
        renderer::atomic::write_atomic(&dir.join("report.md"), self.markdown(&figures).as_bytes())
    }

    fn markdown(&self, figures: &[String]) -> String {
        let s = &self.settings;
        let mut md = String::new();
        let _ = writeln!(md, "# JND report: design `{}`\n", self.design);
        let _ = writeln!(
            md,
            "{} subjects, {} main trials from {} session logs (design hash `{}`). Practice \
             trials are excluded.\n",
            self.subjects.len(),
            self.trials,
            self.files.len(),
            self.design_hash
        );
        for w in &self.warnings {
            let _ = writeln!(md, "- warning: {w}");
        }
        if !self.excluded.is_empty() {
            let _ = writeln!(md, "Excluded subjects (not in any table, fit or figure):\n");
            for e in &self.excluded {
                let _ = writeln!(
                    md,
                    "- {}: {} ({} main trials)",
                    e.subject, e.reason, e.trials
                );
            }
            let _ = writeln!(md);
        }
        let _ = writeln!(md, "## Methods\n");
        if s.preset == Some(Preset::Thesis) {
            let _ = writeln!(
                md,
                "Preset `thesis`: the t-tests as the thesis ran them (Chapter V, Tables 1 and \
                 2): paired over subject x other-factor cells, two-sided Student t, alpha = {}, \
                 no correction for multiple tests, its pair order and sign (t > 0 when the first \
                 named has the higher proportion correct). The cells of one subject are not \
                 independent, so these degrees of freedom overstate the evidence; the default \
                 analysis (`--unit subject`) tests one value per subject.\n",
                s.comparisons.alpha
            );
        }
        let _ = writeln!(
            md,
            "- Psychometric function for a forced-choice task with guess rate g = {}: \
             p(x) = g + (1 - g - lapse) S(beta (alpha - x)), x = ln spp; S: {}; lapse {}.\n\
             - Maximum likelihood on the binomial counts, pooled over subjects per group, and \
             per subject. When the likelihood is maximised by an infinitely steep function (a \
             step) the threshold is reported as the interval between two tested levels, never as \
             a number; a step through a tested level (its proportion strictly between the \
             plateaus) crosses the target at that level, shown as `level [bracket]`.\n\
             - JND: the spp where the fitted function crosses p = {}; beyond the tested levels it \
             is reported as below/above range, never extrapolated. Beside it, the thesis's \
             reading: where the observed proportions (joined linearly in ln spp) first fall \
             through the target.\n\
             - {:.0}% confidence interval: parametric bootstrap, {} resamples (seed {}), \
             nearest-rank percentiles of the replicates' thresholds (an interval replicate \
             contributes its lower end to the lower percentile and its upper end to the upper).\n\
             - Goodness of fit: deviance against the saturated model; its p-value is the share \
             of bootstrap replicates with a deviance at least as large. p < {} is flagged as a \
             poor fit.\n\
             - t-tests ({}) on proportions correct per {} at {:?} spp (scenes also at {:?}); \
             two-sided p from the t distribution's survival function; decision at alpha = {}; \
             Cohen's {}; Holm's step-down correction within each family (scenes, point sets) \
             in `ttests.csv`.\n",
            s.fit.guess,
            s.fit.sigmoid.name(),
            match s.fit.lapse {
                LapseMode::Fixed => "fixed at 0".to_string(),
                LapseMode::Free => format!("free in [0, {LAPSE_MAX}]"),
            },
            s.target,
            100.0 * s.bootstrap.confidence,
            s.bootstrap.resamples,
            s.bootstrap.seed,
            s.poor_fit_p,
            s.comparisons.kind.name(),
            match s.comparisons.unit {
                crate::comparisons::Unit::Subject => "subject (pooled over the other factors)",
                crate::comparisons::Unit::Cell => "subject x other-factor cell",
            },
            s.comparisons.levels,
            s.comparisons.scene_extra_levels,
            s.comparisons.alpha,
            s.comparisons.kind.effect_size_name(),
        );
        let _ = writeln!(md, "## Pooled JNDs (spp at p = {})\n", s.target);
        let _ = writeln!(
            md,
            "| grouping | group | fit | JND | {:.0}% CI | empirical crossing | deviance | GOF p | |",
            100.0 * s.bootstrap.confidence
        );
        let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|");
        for g in &self.groups {
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {} | {} | {:.2} | {:.3} | {} |",
                g.key.grouping.name(),
                g.key.label,
                g.pooled.kind(),
                g.threshold.display(),
                ci_text(&g.bootstrap),
                g.empirical.display(),
                g.pooled.deviance,
                g.bootstrap.deviance_p,
                if g.poor_fit { "**poor fit**" } else { "" }
            );
        }
        let thesis = s.preset == Some(Preset::Thesis);
        if thesis {
            self.thesis_jnd_table(&mut md);
        }
        self.subject_tables(&mut md);
        if thesis {
            self.thesis_tables(&mut md);
            self.ttest_tables(&mut md, &[Grouping::TimeFilter]);
        } else {
            self.ttest_tables(
                &mut md,
                &[Grouping::Scene, Grouping::PointSet, Grouping::TimeFilter],
            );
        }
        let _ = writeln!(md, "## Figures\n");
        for f in figures {
            let _ = writeln!(md, "![{f}](figures/{f}.svg) ([PNG](figures/{f}.png))\n");
        }
        md
    }

    fn subject_tables(&self, md: &mut String) {
        let _ = writeln!(
            md,
            "\n## Per-subject thresholds\n\nModel threshold per subject (empirical crossing in \
             parentheses). `a-b` means the likelihood is maximised by a step between the tested \
             levels a and b: the subject's threshold lies in that interval and is not a number. \
             Inference rests on the pooled fits and the per-subject proportions correct. \
             Per-subject thresholds of each condition are in `jnd.csv`.\n"
        );
        for grouping in [Grouping::Scene, Grouping::PointSet] {
            let groups: Vec<&GroupResult> = self
                .groups
                .iter()
                .filter(|g| g.key.grouping == grouping)
                .collect();
            if groups.is_empty() {
                continue;
            }
            let _ = write!(md, "| subject |");
            for g in &groups {
                let _ = write!(md, " {} |", g.key.label);
            }
            let _ = write!(md, "\n|---|");
            for _ in &groups {
                let _ = write!(md, "---|");
            }
            let _ = writeln!(md);
            for subject in &self.subjects {
                let _ = write!(md, "| {subject} |");
                for g in &groups {
                    match g.subjects.iter().find(|s| &s.subject == subject) {
                        Some(s) => {
                            let _ = write!(
                                md,
                                " {} ({}) |",
                                s.threshold.display(),
                                s.empirical.display()
                            );
                        }
                        None => {
                            let _ = write!(md, " - |");
                        }
                    }
                }
                let _ = writeln!(md);
            }
            let _ = writeln!(md);
        }
    }

    fn ttest_tables(&self, md: &mut String, families: &[Grouping]) {
        let s = &self.settings.comparisons;
        for (family, title) in [
            (Grouping::Scene, "Between scenes (thesis Table 1)"),
            (Grouping::PointSet, "Between point sets (thesis Table 2)"),
            (Grouping::TimeFilter, "Between time filters"),
        ] {
            if !families.contains(&family) {
                continue;
            }
            let rows: Vec<&Comparison> = self
                .comparisons
                .iter()
                .filter(|c| c.family == family)
                .collect();
            if rows.is_empty() {
                continue;
            }
            let _ = writeln!(md, "## {title}\n");
            let _ = writeln!(
                md,
                "| test | spp | n | mean a | mean b | t | df | p | Holm p | significant (alpha = {}) | d |",
                s.alpha
            );
            let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|");
            for c in rows {
                let _ = write!(
                    md,
                    "| {} vs {} | {} | {} | {:.3} | {:.3} |",
                    c.a, c.b, c.level, c.test.n1, c.test.mean1, c.test.mean2
                );
                match &c.test.result {
                    Ok(st) => {
                        let _ = writeln!(
                            md,
                            " {:.3} | {:.2} | {:.3e} | {:.3e} | {} (Holm: {}) | {:.2} |",
                            st.t,
                            st.df,
                            st.p,
                            c.p_holm.unwrap_or(1.0),
                            yes_no(c.significant),
                            yes_no(c.significant_holm),
                            st.d
                        );
                    }
                    Err(reason) => {
                        let _ = writeln!(md, " undefined: {reason} | | | | | |");
                    }
                }
            }
            let _ = writeln!(md);
        }
    }
}

fn yes_no(b: Option<bool>) -> &'static str {
    match b {
        Some(true) => "yes",
        Some(false) => "no",
        None => "-",
    }
}

/// A tidy CSV: a header line, then one line per row. With no rows the header comes from a
/// default row, so that an empty table (e.g. no t-tests with a single scene and point set)
/// still names its columns.
fn write_csv<T: Serialize + Default>(path: &Path, rows: &[T]) -> Result<()> {
    renderer::atomic::write_atomic_with(path, |w| {
        if rows.is_empty() {
            let mut probe = csv::Writer::from_writer(Vec::new());
            probe.serialize(T::default())?;
            let text = probe.into_inner().map_err(|e| anyhow::anyhow!("{e}"))?;
            let header = text.split(|&b| b == b'\n').next().unwrap_or_default();
            w.write_all(header)?;
            w.write_all(b"\n")?;
            return Ok(());
        }
        let mut c = csv::Writer::from_writer(w);
        for r in rows {
            c.serialize(r)?;
        }
        c.flush()?;
        Ok(())
    })
}
