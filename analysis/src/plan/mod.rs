//! `blurlab plan`: how many subjects a study needs, answered before booking any, by simulating
//! the study many times with a known observer (typed-in thresholds or a prediction from the
//! stimuli) and analysing each simulation exactly as a real study would be analysed.
//!
//! For each subject count and replication ([`replicate`]): the probability that each pooled
//! JND's 95% interval is narrower than a factor F in spp (both ends inside the tested levels
//! and upper / lower < F); the rate at which each scene, point-set (and time-filter) t-test is
//! significant, which is its power where the observer's population has a true difference and
//! its false-positive rate where it has none; the session's duration from the design's timing.
//! Replications run in parallel; each is a pure function of (subject count, index), and
//! replication r uses the same seeds at every subject count (common random numbers: the first
//! subjects of a larger study are the subjects of a smaller one).

pub mod duration;
pub mod equivalence;
pub mod output;
pub mod replicate;
pub mod study;

use crate::bootstrap::Bound;
use crate::data::{GroupKey, Grouping};
use anyhow::{Result, bail};
use experiment::trials::{Condition, conditions};
use experiment::{Design, Observer};
use rayon::prelude::*;
use renderer::progress::Progress;
use replicate::{Replication, ReplicationSettings};
use serde::Serialize;
use std::collections::BTreeMap;

/// A t-test's identity: family, the two groups, the level.
type TestKey = (Grouping, String, String, u32);

/// What to plan.
#[derive(Clone, Debug)]
pub struct PlanSettings {
    pub subjects: Vec<usize>,
    pub replications: u64,
    /// Interval width criterion: upper / lower < factor.
    pub factor: f64,
    pub replication: ReplicationSettings,
    /// Keep every replication's outcome (for tests and deeper analysis).
    pub keep_replications: bool,
}

/// One pooled group at one subject count.
#[derive(Clone, Debug, Serialize)]
pub struct IntervalRow {
    pub group: GroupKey,
    /// P(both ends inside the levels and upper / lower < factor).
    pub narrow: f64,
    /// P(both ends inside the levels).
    pub finite: f64,
}

/// One t-test at one subject count.
#[derive(Clone, Debug, Serialize)]
pub struct TestRow {
    pub family: Grouping,
    pub a: String,
    pub b: String,
    pub level: u32,
    /// The population's mean proportion correct of a minus b (0: no true difference).
    pub true_difference: f64,
    /// Rate significant at alpha (unadjusted): power, or the false-positive rate at 0.
    pub significant: f64,
    /// Rate significant after Holm's correction within the family.
    pub significant_holm: f64,
    /// Rate of undefined tests (zero variance).
    pub undefined: f64,
}

impl TestRow {
    /// Below this the observer's difference counts as none (rounding of the population means).
    pub const NO_DIFFERENCE: f64 = 1e-9;

    pub fn has_difference(&self) -> bool {
        self.true_difference.abs() > Self::NO_DIFFERENCE
    }
}

/// Everything at one subject count.
#[derive(Clone, Debug, Serialize)]
pub struct CountSummary {
    pub subjects: usize,
    pub intervals: Vec<IntervalRow>,
    pub tests: Vec<TestRow>,
}

/// The plan.
#[derive(Clone, Debug)]
pub struct Plan {
    pub design: String,
    pub observer: String,
    pub replications: u64,
    pub factor: f64,
    pub alpha: f64,
    pub counts: Vec<CountSummary>,
    pub kept: Vec<Replication>,
    pub wall_seconds: f64,
}

/// Run every replication at every subject count and summarise; `progress` counts replications.
pub fn run(
    design: &Design,
    observer: &Observer,
    s: &PlanSettings,
    progress: &dyn Progress,
) -> Result<Plan> {
    let t0 = std::time::Instant::now();
    if s.subjects.is_empty() || s.subjects.contains(&0) {
        bail!(
            "subject counts {:?}: expected at least one count, each >= 1",
            s.subjects
        );
    }
    use renderer::limits::{MAX_REPLICATIONS, MAX_SUBJECTS, check_count};
    for &n in &s.subjects {
        check_count("a subject count", n as u64, 1, MAX_SUBJECTS as u64)?;
    }
    check_count("replications", s.replications, 1, MAX_REPLICATIONS)?;
    observer.check_covers(design)?;
    let jobs: Vec<(usize, u64)> = s
        .subjects
        .iter()
        .flat_map(|&n| (0..s.replications).map(move |r| (n, r)))
        .collect();
    progress.start(jobs.len() as u64);
    progress.message("simulating studies");
    let reps: Vec<Replication> = jobs
        .par_iter()
        .map(|&(n, r)| {
            let out =
                replicate::replicate(design, observer, n, r, &s.replication).map(|(mut rep, _)| {
                    // A test at a level the design does not show has no data: not a result.
                    rep.comparisons
                        .retain(|c| design.file.levels.contains(&c.level));
                    rep
                });
            progress.advance(1);
            out
        })
        .collect::<Result<_>>()?;
    progress.finish();
    let truths = true_differences(design, observer, &reps);
    let counts = s
        .subjects
        .iter()
        .map(|&n| {
            let mine: Vec<&Replication> = reps.iter().filter(|r| r.subjects == n).collect();
            summarise(n, &mine, s.factor, &truths)
        })
        .collect();
    Ok(Plan {
        design: design.name().to_string(),
        observer: observer.file.name.clone(),
        replications: s.replications,
        factor: s.factor,
        alpha: s.replication.analysis.comparisons.alpha,
        counts,
        kept: if s.keep_replications {
            reps
        } else {
            Vec::new()
        },
        wall_seconds: t0.elapsed().as_secs_f64(),
    })
}

/// The design cells a pooled group holds (scene, point set, time filter or condition label).
pub fn cells_of(design: &Design, family: Grouping, label: &str) -> Vec<Condition> {
    conditions(design)
        .into_iter()
        .filter(|c| match family {
            Grouping::Scene => c.scene == label,
            Grouping::PointSet => c.point_set.name() == label,
            Grouping::TimeFilter => c.time_filter.name() == label,
            Grouping::Condition => {
                format!("{}/{}/{}", c.scene, c.point_set, c.time_filter) == label
            }
        })
        .collect()
}

/// The population's difference in mean proportion correct for every test (family, a, b, level).
fn true_differences(
    design: &Design,
    observer: &Observer,
    reps: &[Replication],
) -> BTreeMap<TestKey, f64> {
    let mut out = BTreeMap::new();
    let mean = |family, label: &str, level: u32| {
        let cells = cells_of(design, family, label);
        cells
            .iter()
            .map(|c| observer.p_population(c, level as f64).unwrap_or(f64::NAN))
            .sum::<f64>()
            / cells.len().max(1) as f64
    };
    for r in reps.iter().take(1) {
        for c in &r.comparisons {
            let d = mean(c.family, &c.a, c.level) - mean(c.family, &c.b, c.level);
            out.insert((c.family, c.a.clone(), c.b.clone(), c.level), d);
        }
    }
    out
}

fn summarise(
    n: usize,
    reps: &[&Replication],
    factor: f64,
    truths: &BTreeMap<TestKey, f64>,
) -> CountSummary {
    let total = reps.len().max(1) as f64;
    let mut intervals: BTreeMap<GroupKey, (usize, usize)> = BTreeMap::new();
    let mut tests: BTreeMap<TestKey, (usize, usize, usize)> = BTreeMap::new();
    for r in reps {
        for (key, b) in &r.pooled {
            let e = intervals.entry(key.clone()).or_default();
            if let (Some(Bound::Value { spp: lo }), Some(Bound::Value { spp: hi })) =
                (&b.ci_lower, &b.ci_upper)
            {
                e.1 += 1;
                e.0 += (hi / lo < factor) as usize;
            }
        }
        for c in &r.comparisons {
            let e = tests
                .entry((c.family, c.a.clone(), c.b.clone(), c.level))
                .or_default();
            e.0 += (c.significant == Some(true)) as usize;
            e.1 += (c.significant_holm == Some(true)) as usize;
            e.2 += c.test.result.is_err() as usize;
        }
    }
    CountSummary {
        subjects: n,
        intervals: intervals
            .into_iter()
            .map(|(group, (narrow, finite))| IntervalRow {
                group,
                narrow: narrow as f64 / total,
                finite: finite as f64 / total,
            })
            .collect(),
        tests: tests
            .into_iter()
            .map(|(key, (sig, holm, undefined))| TestRow {
                true_difference: truths.get(&key).copied().unwrap_or(f64::NAN),
                family: key.0,
                a: key.1,
                b: key.2,
                level: key.3,
                significant: sig as f64 / total,
                significant_holm: holm as f64 / total,
                undefined: undefined as f64 / total,
            })
            .collect(),
    }
}
