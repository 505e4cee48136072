//! One replication of a study: the design and the observer reseeded for replication r (trial
//! orders from design master seed + r, subjects and answers from observer seed + r, bootstrap
//! seed + r), simulated subjects through the experiment's session machine into logs kept in
//! memory (`experiment::simulate::simulate_in_memory`: the bytes `blurlab simulate` writes, no
//! temporary files), read back by the analysis (`Dataset::from_logs`, the checks of
//! `Dataset::read`), pooled fits with bootstrap intervals and the t-tests. The parameter
//! recovery tests (`tests/recovery.rs`) run exactly this function.

use crate::bootstrap::{BootstrapResult, bootstrap};
use crate::comparisons::{Comparison, compare};
use crate::data::{Dataset, GroupKey, Grouping};
use crate::psychometric::fit;
use crate::report::Settings;
use anyhow::Result;
use experiment::simulate::simulate_in_memory;
use experiment::{Design, Observer};

/// What a replication analyses.
#[derive(Clone, Debug)]
pub struct ReplicationSettings {
    /// Fit, bootstrap (resamples; its seed is the base of replication seeds) and tests.
    pub analysis: Settings,
    /// Which pooled groups get a fit and an interval.
    pub groupings: Vec<Grouping>,
}

/// The outcome of one replication.
#[derive(Clone, Debug)]
pub struct Replication {
    pub subjects: usize,
    pub index: u64,
    pub trials: usize,
    pub pooled: Vec<(GroupKey, BootstrapResult)>,
    pub comparisons: Vec<Comparison>,
}

/// The design and observer of replication `r`.
pub fn seeded(design: &Design, observer: &Observer, r: u64) -> (Design, Observer) {
    let mut d = design.clone();
    d.file.seed.master = d.file.seed.master.wrapping_add(r);
    let mut o = observer.clone();
    o.file.seed = o.file.seed.wrapping_add(r);
    (d, o)
}

/// Replication `r` with `subjects` subjects; also returns its dataset.
pub fn replicate(
    design: &Design,
    observer: &Observer,
    subjects: usize,
    r: u64,
    s: &ReplicationSettings,
) -> Result<(Replication, Dataset)> {
    let (design, observer) = seeded(design, observer, r);
    let ds = Dataset::from_logs(&simulate_in_memory(&design, &observer, subjects)?)?;
    let mut analysis = s.analysis.clone();
    analysis.bootstrap.seed = analysis.bootstrap.seed.wrapping_add(r);
    let pooled = ds
        .groups
        .iter()
        .filter(|g| s.groupings.contains(&g.key.grouping))
        .map(|g| {
            let f = fit(&g.pooled, &analysis.fit);
            (
                g.key.clone(),
                bootstrap(&f, g.key.id(), &analysis.bootstrap),
            )
        })
        .collect();
    let comparisons = compare(&ds, &analysis.comparisons);
    Ok((
        Replication {
            subjects,
            index: r,
            trials: ds.trials,
            pooled,
            comparisons,
        },
        ds,
    ))
}
