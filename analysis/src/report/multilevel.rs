//! `report.md`'s section on the multilevel model (`--model multilevel`): the population JNDs
//! with both intervals and the between-subject SD, the model's comparisons beside the
//! t-tests, the equivalence tests, and the shrunken per-subject JNDs.

use super::Report;
use crate::bootstrap::interval_text;
use crate::data::Grouping;
use crate::multilevel::compare::{ModelComparison, TOST_ALPHA};
use crate::multilevel::{GroupModel, MultilevelSettings};
use serde::Serialize;
use std::fmt::Write as _;

/// The multilevel model's results.
#[derive(Clone, Debug, Serialize)]
pub struct MultilevelReport {
    /// Levels left out of the model: every trial there showed the reference against itself.
    pub same_video_levels: Vec<u32>,
    pub groups: Vec<GroupModel>,
    pub comparisons: Vec<ModelComparison>,
}

impl Report {
    pub(super) fn multilevel_section(&self, md: &mut String, s: &MultilevelSettings) {
        let Some(ml) = &self.multilevel else { return };
        let conf = 100.0 * s.confidence;
        let _ = writeln!(
            md,
            "## Across subjects: multilevel model\n\n\
             Per group a population threshold and slope; each subject's threshold is normal in \
             ln spp around the population's (between-subject SD sigma); guess rate and lapse as \
             above. Maximum likelihood with adaptive Gauss-Hermite quadrature ({} nodes) over \
             each subject's offset. The population JND is the typical subject's (offset 0). \
             Profile interval (the reported one): the ln JNDs whose profile deviance is at most \
             the square of the Student t quantile with subjects - 1 df; Wald interval: the same \
             t on ln JND; subject bootstrap: {} \
             resamples of whole subjects (seed {}), nearest-rank percentiles. sigma's interval \
             is Wald on ln sigma (none when sigma is at its lower bound 0.001: no spread \
             detected).\n",
            s.nodes, s.resamples, s.seed
        );
        if !ml.same_video_levels.is_empty() {
            let levels: Vec<String> = ml.same_video_levels.iter().map(u32::to_string).collect();
            let _ = writeln!(
                md,
                "Left out of the model: the trials at {} spp, where test and reference were the \
                 same video (chance whatever the threshold).\n",
                levels.join(", ")
            );
        }
        let _ = writeln!(
            md,
            "| grouping | group | subjects | JND | {conf:.0}% CI (profile) | {conf:.0}% CI (Wald) | \
             {conf:.0}% CI (subject bootstrap) | sigma (ln spp) | {conf:.0}% CI | slope | lapse |"
        );
        let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|");
        for g in &ml.groups {
            let profile = interval_text(&g.ci_lower, &g.ci_upper, ", ").map_or("none".into(), br);
            let wald = interval_text(&g.wald_lower, &g.wald_upper, ", ").map_or("none".into(), br);
            let boot = g
                .bootstrap
                .as_ref()
                .and_then(|b| interval_text(&b.ci_lower, &b.ci_upper, ", "))
                .map_or("none".into(), br);
            let sigma_ci = g
                .sigma_ci
                .map_or("none".into(), |(a, b)| format!("[{a:.3}, {b:.3}]"));
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {profile} | {wald} | {boot} | {:.3} | {sigma_ci} | {:.3} | {:.3} |",
                g.key.grouping.name(),
                g.key.label,
                g.subjects,
                g.jnd.display(),
                g.sigma,
                g.slope,
                g.lapse
            );
        }
        let _ = writeln!(md);
        self.model_comparisons(md, ml, s);
        if let Some(margin) = s.equivalence {
            equivalence_table(md, ml, margin);
        }
        shrunken_tables(md, ml);
    }

    fn model_comparisons(&self, md: &mut String, ml: &MultilevelReport, s: &MultilevelSettings) {
        if ml.comparisons.is_empty() {
            return;
        }
        let conf = 100.0 * s.confidence;
        let _ = writeln!(
            md,
            "### Comparisons from the model\n\n\
             Each pair in one model with each subject's offset shared by both groups (the model \
             assumes no subject x group interaction; the subject bootstrap does not). \
             Difference = ln JND(a) - ln JND(b) (> 0: a needs more spp; ratio = exp). Wald: \
             Student t with subjects - 1 df; LR: against one threshold for both, chi-square 1 \
             df. The thesis-style t-tests above are unchanged.\n"
        );
        let _ = writeln!(
            md,
            "| family | pair | subjects | difference | ratio | {conf:.0}% CI (Wald) | Wald p | LR | \
             LR p | {conf:.0}% CI (subject bootstrap) |"
        );
        let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|");
        for c in &ml.comparisons {
            let ci = c
                .ci_lower
                .zip(c.ci_upper)
                .map_or("none".into(), |(a, b)| format!("[{a:.3}, {b:.3}]"));
            let boot = c.bootstrap.as_ref().map_or("none".into(), |b| {
                format!("[{:.3}, {:.3}]", b.ln_lower, b.ln_upper)
            });
            let _ = writeln!(
                md,
                "| {} | {} vs {} | {} | {:.3} | {:.3} | {ci} | {} | {:.2} | {:.3e} | {boot} |",
                c.family.name(),
                c.a,
                c.b,
                c.subjects,
                c.difference,
                c.difference.exp(),
                c.wald_p.map_or("-".into(), |p| format!("{p:.3e}")),
                c.lr,
                c.lr_p
            );
        }
        let _ = writeln!(md);
    }
}

fn br(s: String) -> String {
    format!("[{s}]")
}

fn equivalence_table(md: &mut String, ml: &MultilevelReport, margin: f64) {
    let _ = writeln!(
        md,
        "### Equivalence (TOST, margin {margin} in ln JND: ratio within [{:.3}, {:.3}])\n\n\
         Two one-sided Wald tests at {TOST_ALPHA} each: equivalence is shown when the 90% \
         interval of the difference lies inside (-{margin}, {margin}); \"not shown\" is no \
         evidence of a difference.\n",
        (-margin).exp(),
        margin.exp()
    );
    // Every point-set and time-filter pair gets a row, tested or not, so that nothing is
    // skipped without a word (issue 42: all-correct logs gave a header and no row).
    let pairs: Vec<_> = ml
        .comparisons
        .iter()
        .filter(|c| c.family != Grouping::Scene)
        .collect();
    if pairs.is_empty() {
        let _ = writeln!(
            md,
            "No pair to test: the data hold one point set and one time filter (or the model \
             could not be fitted to any pair).\n"
        );
        return;
    }
    let _ = writeln!(
        md,
        "| family | pair | difference | 90% CI | TOST p | result |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|");
    for c in pairs {
        let Some(e) = &c.equivalence else {
            let _ = writeln!(
                md,
                "| {} | {} vs {} | {:.3} | none | - | not tested: the model gives the difference \
                 no standard error (thresholds at or beyond the tested levels) |",
                c.family.name(),
                c.a,
                c.b,
                c.difference
            );
            continue;
        };
        let _ = writeln!(
            md,
            "| {} | {} vs {} | {:.3} | [{:.3}, {:.3}] | {:.3e} | {} |",
            c.family.name(),
            c.a,
            c.b,
            c.difference,
            e.lower,
            e.upper,
            e.p,
            if e.equivalent {
                "equivalent"
            } else {
                "not shown"
            }
        );
    }
    let _ = writeln!(md);
}

fn shrunken_tables(md: &mut String, ml: &MultilevelReport) {
    let _ = writeln!(
        md,
        "### Shrunken per-subject JNDs\n\n\
         exp(population ln JND + the subject's posterior mean offset), as the population's: \
         `> top` / `< bottom` level beyond the tested range, never extrapolated. Interval: \
         +-1.96 times the posterior SD combined with the population JND's standard error \
         (approximate: the uncertainty of sigma and the slope is not included). All in \
         `report.json` under `multilevel`.\n"
    );
    for grouping in [Grouping::Scene, Grouping::PointSet] {
        let groups: Vec<&GroupModel> = ml
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
        let _ = writeln!(md, "\n|---|{}", "---|".repeat(groups.len()));
        let mut names: Vec<&String> = groups
            .iter()
            .flat_map(|g| g.shrunken.iter().map(|s| &s.subject))
            .collect();
        names.sort();
        names.dedup();
        for name in names {
            let _ = write!(md, "| {name} |");
            for g in &groups {
                match g.shrunken.iter().find(|s| &s.subject == name) {
                    Some(s) => {
                        let _ = write!(
                            md,
                            " {} [{}, {}] |",
                            s.jnd.display(),
                            s.lower.display(),
                            s.upper.display()
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
