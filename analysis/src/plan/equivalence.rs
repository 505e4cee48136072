//! `plan --equivalence MARGIN`: how many subjects the TOST of the multilevel model
//! ([`crate::multilevel::compare::tost`]) needs to show point sets (and time filters)
//! equivalent. Each replication is [`super::replicate::replicate`] (simulated subjects through
//! the session machine, read back as logs) without pooled fits; every point-set and
//! time-filter pair is compared in one two-group model. The rate at which a pair is shown
//! equivalent is the TOST's power where the observer's true difference is inside the margin,
//! and its size (false "equivalent") where the difference is at or beyond it.

use super::replicate::{ReplicationSettings, replicate};
use super::{TestRow, cells_of};
use crate::data::{Dataset, Group, Grouping};
use crate::multilevel::compare::{difference, tost};
use crate::multilevel::{Context, MultilevelSettings, estimate};
use crate::report::Settings;
use anyhow::{Result, bail};
use experiment::{Design, Observer};
use rayon::prelude::*;
use renderer::progress::Progress;
use serde::Serialize;
use std::fmt::Write as _;

/// One pair at one subject count.
#[derive(Clone, Debug, Serialize)]
pub struct EquivalenceRow {
    pub subjects: usize,
    pub family: Grouping,
    pub a: String,
    pub b: String,
    /// The observer's difference in mean ln JND over the pair's cells (a - b).
    pub true_difference: f64,
    /// Rate shown equivalent (TOST p < 0.05).
    pub equivalent: f64,
    /// Rate of replications whose model had no covariance (counted as not shown).
    pub undefined: f64,
}

/// Simulate `replications` studies at each subject count and run the TOST on each pair.
pub fn run(
    design: &Design,
    observer: &Observer,
    subjects: &[usize],
    replications: u64,
    margin: f64,
    progress: &dyn Progress,
) -> Result<Vec<EquivalenceRow>> {
    if !(margin > 0.0 && margin < 5.0) {
        bail!("--equivalence is {margin}; expected a margin in ln JND in (0, 5), e.g. 0.2");
    }
    if let Some(n) = subjects.iter().find(|&&n| n < 2) {
        bail!(
            "the equivalence tests' subject counts (--equivalence-subjects, else --subjects) \
             include {n}; expected at least 2 subjects per study (the TOST's t has subjects - 1 \
             degrees of freedom)"
        );
    }
    use renderer::limits::{MAX_REPLICATIONS, MAX_SUBJECTS, check_count};
    for &n in subjects {
        check_count(
            "an equivalence subject count",
            n as u64,
            2,
            MAX_SUBJECTS as u64,
        )?;
    }
    check_count("replications", replications, 1, MAX_REPLICATIONS)?;
    observer.check_covers(design)?;
    let s = ReplicationSettings {
        analysis: Settings::default(),
        groupings: Vec::new(),
    };
    let jobs: Vec<(usize, u64)> = subjects
        .iter()
        .flat_map(|&n| (0..replications).map(move |r| (n, r)))
        .collect();
    progress.start(jobs.len() as u64);
    progress.message("simulating studies for the equivalence tests");
    let outcomes: Vec<(usize, Vec<PairOutcome>)> = jobs
        .par_iter()
        .map(|&(n, r)| {
            let (_, ds) = replicate(design, observer, n, r, &s)?;
            progress.advance(1);
            Ok((n, pairs(&ds, &s.analysis, margin)))
        })
        .collect::<Result<_>>()?;
    progress.finish();
    Ok(summarise(design, observer, subjects, &outcomes))
}

/// (family, a, b, shown equivalent, defined) of one replication.
type PairOutcome = (Grouping, String, String, bool, bool);

fn pairs(ds: &Dataset, s: &Settings, margin: f64) -> Vec<PairOutcome> {
    let ml = MultilevelSettings {
        resamples: 0,
        equivalence: Some(margin),
        ..MultilevelSettings::default()
    };
    let cx = Context {
        fit: &s.fit,
        target: s.target,
        settings: &ml,
        same_video_levels: &ds.same_video_levels,
    };
    let mut out = Vec::new();
    for family in [Grouping::PointSet, Grouping::TimeFilter] {
        let groups: Vec<&Group> = ds.groups_of(family).collect();
        for i in 0..groups.len() {
            for j in i + 1..groups.len() {
                let curves = [
                    groups[i].per_subject.as_slice(),
                    groups[j].per_subject.as_slice(),
                ];
                let shown = estimate(&curves, false, &cx, None).and_then(|(e, c)| {
                    let (d, se) = difference(&e);
                    se.map(|se| tost(d, se, (c.subjects.len() - 1) as f64, margin).equivalent)
                });
                out.push((
                    family,
                    groups[i].key.label.clone(),
                    groups[j].key.label.clone(),
                    shown == Some(true),
                    shown.is_some(),
                ));
            }
        }
    }
    out
}

fn summarise(
    design: &Design,
    observer: &Observer,
    subjects: &[usize],
    outcomes: &[(usize, Vec<PairOutcome>)],
) -> Vec<EquivalenceRow> {
    let mut rows = Vec::new();
    for &n in subjects {
        let mine: Vec<&Vec<PairOutcome>> =
            outcomes.iter().filter(|o| o.0 == n).map(|o| &o.1).collect();
        let total = mine.len().max(1) as f64;
        let Some(first) = mine.first() else { continue };
        for (k, (family, a, b, _, _)) in first.iter().enumerate() {
            let rate = |f: fn(&PairOutcome) -> bool| {
                mine.iter().filter(|o| f(&o[k])).count() as f64 / total
            };
            rows.push(EquivalenceRow {
                subjects: n,
                family: *family,
                a: a.clone(),
                b: b.clone(),
                true_difference: mean_ln_jnd(design, observer, *family, a)
                    - mean_ln_jnd(design, observer, *family, b),
                equivalent: rate(|o| o.3),
                undefined: rate(|o| !o.4),
            });
        }
    }
    rows
}

/// The observer's mean ln JND over a group's cells (NaN if it has none for some cell).
fn mean_ln_jnd(design: &Design, observer: &Observer, family: Grouping, label: &str) -> f64 {
    let cells = cells_of(design, family, label);
    cells
        .iter()
        .map(|c| observer.threshold(c).map_or(f64::NAN, f64::ln))
        .sum::<f64>()
        / cells.len().max(1) as f64
}

/// The table and the recommendation: the smallest subject count at which every pair whose
/// true difference lies inside the margin (by more than the rounding [`TestRow::NO_DIFFERENCE`])
/// is shown equivalent with probability >= `probability`.
pub fn markdown(rows: &[EquivalenceRow], margin: f64, probability: f64) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "## Equivalence (TOST of the multilevel model, margin {margin} in ln JND)\n\n\
         | subjects | family | pair | true difference (ln JND) | P(shown equivalent) | no covariance |\n\
         |---|---|---|---|---|---|"
    );
    for r in rows {
        let _ = writeln!(
            md,
            "| {} | {} | {} vs {} | {:.3} | {:.3} | {:.3} |",
            r.subjects,
            r.family.name(),
            r.a,
            r.b,
            r.true_difference,
            r.equivalent,
            r.undefined
        );
    }
    let inside = |r: &&EquivalenceRow| r.true_difference.abs() < margin - TestRow::NO_DIFFERENCE;
    let mut counts: Vec<usize> = rows.iter().map(|r| r.subjects).collect();
    counts.dedup();
    let enough = counts.into_iter().find(|&n| {
        let mine: Vec<&EquivalenceRow> = rows
            .iter()
            .filter(|r| r.subjects == n)
            .filter(inside)
            .collect();
        !mine.is_empty() && mine.iter().all(|r| r.equivalent >= probability)
    });
    let _ = writeln!(
        md,
        "\n{}",
        match enough {
            Some(n) => format!(
                "Equivalence: {n} subjects show every pair whose true difference lies inside the \
                 margin equivalent with probability >= {probability}."
            ),
            None => format!(
                "Equivalence: none of the subject counts tried shows every pair inside the margin \
                 equivalent with probability >= {probability}; try more subjects \
                 (`--equivalence-subjects`) or repeats."
            ),
        }
    );
    md
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(subjects: usize, d: f64, eq: f64) -> EquivalenceRow {
        EquivalenceRow {
            subjects,
            family: Grouping::PointSet,
            a: "a".into(),
            b: "b".into(),
            true_difference: d,
            equivalent: eq,
            undefined: 0.0,
        }
    }

    #[test]
    fn the_recommendation_is_the_first_count_with_enough_power_inside_the_margin() {
        // A pair at the margin (its rate is the size) never drives the recommendation.
        let rows = [
            row(8, 0.0, 0.5),
            row(8, 0.2, 0.04),
            row(16, 0.0, 0.85),
            row(16, 0.2, 0.05),
        ];
        let md = markdown(&rows, 0.2, 0.8);
        assert!(md.contains("Equivalence: 16 subjects"), "{md}");
        let md = markdown(&rows[..2], 0.2, 0.8);
        assert!(md.contains("none of the subject counts"), "{md}");
    }
}
