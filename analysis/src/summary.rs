//! The pooled JND per scene and per point set (with its interval and the thesis-style
//! empirical crossing) and how many t-tests came out significant, as a few lines for a
//! terminal (`Display`: `demo` and `analyze` print it) and as the study summary's Markdown
//! section.

use crate::bootstrap::{Bound, interval_text};
use crate::data::Grouping;
use crate::jnd::Threshold;
use crate::report::Report;
use serde::Serialize;
use std::fmt::{self, Write as _};

/// One group's pooled JND.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SummaryRow {
    pub grouping: Grouping,
    pub label: String,
    /// The fitted function's threshold (a number only inside the tested levels).
    pub jnd: Threshold,
    pub ci_lower: Option<Bound>,
    pub ci_upper: Option<Bound>,
    /// The thesis's reading: where the observed proportions first fall through the target.
    pub empirical: Threshold,
    /// The deviance's bootstrap p-value was below the poor-fit level.
    pub poor_fit: bool,
}

impl SummaryRow {
    /// The interval as text, its ends joined by `join`; `None` without an interval.
    pub fn interval(&self, join: &str) -> Option<String> {
        interval_text(&self.ci_lower, &self.ci_upper, join)
    }
}

/// The summary of a [`Report`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Summary {
    pub target: f64,
    pub confidence: f64,
    /// Scenes, then point sets, then time filters (when several), each sorted by label.
    pub rows: Vec<SummaryRow>,
    /// Defined t-tests, and how many were significant on the raw and on the Holm p.
    pub tests: usize,
    pub significant: usize,
    pub significant_holm: usize,
    pub alpha: f64,
}

impl Report {
    /// The pooled JND per scene, per point set (and per time filter when there are several).
    pub fn summary(&self) -> Summary {
        let mut rows = Vec::new();
        for grouping in [Grouping::Scene, Grouping::PointSet, Grouping::TimeFilter] {
            for g in self.groups_of(grouping) {
                rows.push(SummaryRow {
                    grouping,
                    label: g.key.label.clone(),
                    jnd: g.threshold.clone(),
                    ci_lower: g.bootstrap.ci_lower.clone(),
                    ci_upper: g.bootstrap.ci_upper.clone(),
                    empirical: g.empirical.clone(),
                    poor_fit: g.poor_fit,
                });
            }
        }
        let defined = self.comparisons.iter().filter(|c| c.test.result.is_ok());
        Summary {
            target: self.settings.target,
            confidence: self.settings.bootstrap.confidence,
            rows,
            tests: defined.clone().count(),
            significant: defined
                .clone()
                .filter(|c| c.significant == Some(true))
                .count(),
            significant_holm: defined.filter(|c| c.significant_holm == Some(true)).count(),
            alpha: self.settings.comparisons.alpha,
        }
    }
}

impl Summary {
    /// The same rows as a Markdown section (the study summary's; `report.md` has the fuller
    /// table with each fit's kind, deviance and goodness of fit).
    pub fn markdown(&self) -> String {
        let mut s = format!(
            "## JND (spp at p = {}, pooled over subjects)\n\n\
             | grouping | label | JND | {:.0}% CI | empirical crossing | fit |\n|---|---|---|---|---|---|\n",
            self.target,
            100.0 * self.confidence
        );
        for r in &self.rows {
            let ci = r.interval(" to ").unwrap_or_else(|| "none".into());
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} |",
                r.grouping.name(),
                r.label,
                r.jnd.display(),
                ci,
                r.empirical.display(),
                if r.poor_fit { "poor" } else { "ok" }
            );
        }
        let _ = writeln!(
            s,
            "\nt-tests: {} of {} significant at alpha = {} ({} after Holm's correction).\n",
            self.significant, self.tests, self.alpha, self.significant_holm
        );
        s
    }
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "JND (spp at p = {}; pooled fit, {:.0}% CI, thesis-style empirical crossing):",
            self.target,
            100.0 * self.confidence
        )?;
        let width = self.rows.iter().map(|r| r.label.len()).max().unwrap_or(0);
        for r in &self.rows {
            let ci = r
                .interval(", ")
                .map_or("no interval".into(), |i| format!("[{i}]"));
            writeln!(
                f,
                "  {:<11} {:<width$}  {:>9}  {:<16} empirical {}{}",
                r.grouping.name(),
                r.label,
                r.jnd.display(),
                ci,
                r.empirical.display(),
                if r.poor_fit { "  (poor fit)" } else { "" }
            )?;
        }
        write!(
            f,
            "t-tests: {} of {} significant at alpha = {} ({} after Holm's correction)",
            self.significant, self.tests, self.alpha, self.significant_holm
        )
    }
}
