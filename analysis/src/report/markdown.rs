//! `report.md`: the tables and figures of a report with the methods stated.

use super::rows::ci_text;
use super::{GroupResult, Preset, Report};
use crate::comparisons::Comparison;
use crate::data::Grouping;
use crate::psychometric::{LAPSE_MAX, LapseMode};
use std::fmt::Write as _;

impl Report {
    /// "Sessions: 3 lab (`gui`), 2 web, 12 simulated": where the answers come from.
    pub fn sessions_line(&self) -> String {
        let parts: Vec<String> = self
            .sessions_by_mode
            .iter()
            .map(|(mode, n)| match mode.as_str() {
                "gui" => format!("{n} lab (`gui`)"),
                "web" => format!("{n} web (`blurlab serve`)"),
                other => format!("{n} {other}"),
            })
            .collect();
        format!("Sessions: {}.", parts.join(", "))
    }

    /// The Markdown report, linking `figures` (paths relative to the report folder).
    pub(crate) fn markdown(&self, figures: &[String]) -> String {
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
        if !self.sessions_by_mode.is_empty() {
            let _ = writeln!(md, "{}\n", self.sessions_line());
        }
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
        if let Some(m) = &s.multilevel {
            self.multilevel_section(&mut md, m);
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
            let groups: Vec<&GroupResult> = self.groups_of(grouping).collect();
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
