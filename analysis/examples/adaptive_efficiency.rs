//! The efficiency of the adaptive procedures against the thesis's constant stimuli (issue 27):
//! simulated observers (the thesis observer without spread between subjects, so each
//! condition's true JND is known: 40 spp on the plane, 100 on the spheres) answer whole
//! sessions through the real session machine into logs kept in memory
//! (`experiment::simulate::simulate_subject_in_memory`, the bytes a log file holds); each
//! subject's condition is fitted and bootstrapped exactly as `analyze` does it (logistic, lapse
//! free within its default bound, 95% percentile interval). Per procedure and trial count:
//! the median ratio upper / lower of the per-subject, per-condition JND interval (an end outside
//! the tested levels counts as infinitely wide), the share of intervals with both ends inside,
//! the coverage of the true JND, and the bias of the fitted JND (median and mean of
//! JND / true - 1 over the fits with a value). Beside it, for every procedure alike, the
//! QUEST+ model's posterior from the same trials (the default prior of
//! `experiment::design::procedure::QuestPlusSpec`; for a QUEST+ session exactly its own estimate): the
//! median ratio of its 95% interval, its coverage and the median bias of its posterior mean.
//!
//! ```text
//! nice -n 10 cargo run -p analysis --release --example adaptive_efficiency -- \
//!     scenes/thesis/design.json scenes/thesis/observer.json 1000 200 > efficiency.md
//! ```
//! (arguments: constant-stimuli design, observer, replications, bootstrap resamples (0: fits
//! and posteriors only, the interval columns of the fits left empty), optionally a text the
//! procedures' names must contain, e.g. `QUEST+` (comma-separated: any of them), and optionally the names of the QUEST+ priors
//! to run, comma-separated (`priors`; default: `default`), and optionally the QUEST+ trial
//! counts per condition, comma-separated (default `8,10,11,16,24,32`)). With a prior, the QUEST+ sessions use
//! it and every procedure's posterior is computed with it, so the intervals compared are the
//! same kind (one grid, one prior). Each
//! replication r reseeds the design and the observer as `plan` does (`plan::replicate::seeded`).

use analysis::bootstrap::{Bound, bootstrap};
use analysis::data::{Dataset, Grouping};
use analysis::plan::replicate::seeded;
use analysis::psychometric::fit;
use analysis::report::Settings;
use anyhow::{Context, Result};
use experiment::design::procedure::{
    ProcedureSpec, QuestGoal, QuestPlusSpec, SlopePrior, StairRule, StaircaseSpec, ThresholdRange,
};
use experiment::log::SessionLog;
use experiment::procedure;
use experiment::procedure::interleave::Track;
use experiment::procedure::quest_plus::QuestPlus;
use experiment::simulate::simulate_subject_in_memory;
use experiment::{Design, Observer};
use rayon::prelude::*;
use std::path::PathBuf;

/// One subject's condition: interval (ln lower, ln upper; infinite outside the levels), the
/// fitted JND, and the QUEST+ posterior mean with its 95% interval (spp).
#[derive(Clone, Debug)]
struct Cell {
    truth: f64,
    lower: f64,
    upper: f64,
    jnd: Option<f64>,
    own: Option<(f64, f64, f64)>,
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: adaptive_efficiency <design> <observer> <replications> <resamples>";
    let design = Design::load(&PathBuf::from(args.first().context(usage)?))?;
    let mut observer = Observer::load(&PathBuf::from(args.get(1).context(usage)?))?;
    observer.file.subject_spread = 0.0;
    let reps: u64 = args.get(2).context(usage)?.parse()?;
    let resamples: usize = args.get(3).context(usage)?.parse()?;
    let only = args.get(4).cloned().unwrap_or_default();
    let wanted = args.get(5).map_or("default", String::as_str);
    let counts: Vec<u32> = args
        .get(6)
        .map_or("8,10,11,16,24,32", String::as_str)
        .split(',')
        .map(|n| {
            n.parse()
                .context("trial counts: expected whole numbers, e.g. 12,14")
        })
        .collect::<Result<_>>()?;
    let chosen: Vec<(&str, QuestPlusSpec)> = priors()
        .into_iter()
        .filter(|p| wanted.split(',').any(|w| w == p.0))
        .collect();
    if chosen.is_empty() {
        anyhow::bail!(
            "priors {wanted:?}: expected names from {:?}",
            priors().iter().map(|p| p.0).collect::<Vec<_>>()
        );
    }
    println!(
        "| procedure | trials per subject (mean) | median interval upper/lower | both ends inside | \
         coverage | bias median | bias mean (fits with a value) | posterior: median upper/lower, coverage, bias median | \
         next trial known while answering |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for (prior_name, prior) in &chosen {
        for (name, spec) in procedures(prior, &counts)
            .into_iter()
            .filter(|p| only.split(',').any(|o| p.0.contains(o)))
        {
            let name = format!("{name} [prior {prior_name}]");
            let mut d = design.clone();
            d.file.procedure = spec;
            let t0 = std::time::Instant::now();
            let (trials, known, cells) = run(&d, &observer, prior, reps, resamples)?;
            println!("{} {:.3} |", row(&name, trials, &cells), known);
            eprintln!("{name}: {:.0} s", t0.elapsed().as_secs_f64());
        }
    }
    Ok(())
}

/// The QUEST+ priors compared (docs/benchmarks/adaptive.md, "Priors", says where each
/// comes from). `quest`'s slope: Watson & Pelli's (1983) Weibull beta 3.5 per ln contrast for
/// 2AFC contrast detection, halved because Monte Carlo noise's amplitude goes as spp^(-1/2), and
/// times 4 ln 2 / 2 = 1.386 to turn a Weibull's slope at its midpoint into a logistic's: 2.43
/// per ln spp (the simulated observer's is 1.5, so this prior is centred off the truth). `truth`
/// is centred on the simulated observer's own slope: it flatters QUEST+. The range 8-343 spp is
/// the rendered levels without their ends: the levels were chosen to bracket the thresholds.
/// `-lapse0` variants fix the model's lapse at the simulated observer's own 0 instead of 0.02:
/// the most a free lapse could gain (learning it can only do worse than knowing it).
fn priors() -> Vec<(&'static str, QuestPlusSpec)> {
    let slope = |median, sd_ln| SlopePrior { median, sd_ln };
    let range = Some(ThresholdRange {
        lowest: 8.0,
        highest: 343.0,
    });
    let with = |slope, threshold| QuestPlusSpec {
        slope,
        threshold,
        ..QuestPlusSpec::default()
    };
    let lapse0 = |q: QuestPlusSpec| QuestPlusSpec { lapse: 0.0, ..q };
    vec![
        ("default", QuestPlusSpec::default()),
        ("truth", with(slope(1.5, 0.25), None)),
        ("quest", with(slope(2.43, 0.25), None)),
        ("range", with(SlopePrior::default(), range.clone())),
        ("range-quest", with(slope(2.43, 0.25), range.clone())),
        ("range-truth", with(slope(1.5, 0.25), range.clone())),
        (
            "range-quest-lapse0",
            lapse0(with(slope(2.43, 0.25), range.clone())),
        ),
        ("range-truth-lapse0", lapse0(with(slope(1.5, 0.25), range))),
    ]
}

fn procedures(prior: &QuestPlusSpec, counts: &[u32]) -> Vec<(String, ProcedureSpec)> {
    let mut out = vec![(
        "constant stimuli".to_string(),
        ProcedureSpec::ConstantStimuli,
    )];
    for (goal, label) in [
        (QuestGoal::Joint, ""),
        (QuestGoal::Threshold, " (threshold goal)"),
    ] {
        for &n in counts {
            out.push((
                format!("QUEST+{label} {n} per condition"),
                ProcedureSpec::QuestPlus(QuestPlusSpec {
                    trials: n,
                    goal,
                    ..prior.clone()
                }),
            ));
        }
    }
    for (rule, label) in [
        (StairRule::OneUpTwoDown, "1-up/2-down"),
        (StairRule::OneUpThreeDown, "1-up/3-down"),
        (StairRule::Weighted { target: 0.75 }, "weighted 0.75"),
    ] {
        for n in [8, 16] {
            out.push((
                format!("staircase {label}, 2 x {n} per condition"),
                ProcedureSpec::Staircase(StaircaseSpec {
                    rule,
                    interleaved: 2,
                    trials: n,
                    step: 1.0,
                }),
            ));
        }
    }
    out
}

/// The mean trials per subject, the share of main trials whose successor the app could load
/// while the subject answers (`Procedure::after_current`), and every replication's cells.
fn run(
    d: &Design,
    o: &Observer,
    prior: &QuestPlusSpec,
    reps: u64,
    resamples: usize,
) -> Result<(f64, f64, Vec<Cell>)> {
    let per: Vec<(usize, usize, Vec<Cell>)> = (0..reps)
        .into_par_iter()
        .map(|r| replication(d, o, prior, r, resamples))
        .collect::<Result<_>>()?;
    let trials = per.iter().map(|p| p.0).sum::<usize>() as f64;
    let known = per.iter().map(|p| p.1).sum::<usize>() as f64;
    Ok((
        trials / reps as f64,
        known / trials,
        per.into_iter().flat_map(|p| p.2).collect(),
    ))
}

/// Main trials of the log whose successor was known before the answer (the last one has none).
fn known_next(d: &Design, log: &SessionLog) -> usize {
    let mut p = procedure::start(d, "s01");
    let mut known = 0;
    for t in log.main_trials() {
        known += p.after_current().is_some() as usize;
        p.answer(t.correct);
    }
    known
}

fn replication(
    d: &Design,
    o: &Observer,
    prior: &QuestPlusSpec,
    r: u64,
    resamples: usize,
) -> Result<(usize, usize, Vec<Cell>)> {
    let (d, o) = seeded(d, o, r);
    let log = simulate_subject_in_memory(&d, &o, "s01")?;
    let ds = Dataset::from_logs(std::slice::from_ref(&log))?;
    let mut s = Settings::default();
    s.bootstrap.resamples = resamples;
    s.bootstrap.seed = r;
    let mut cells = Vec::new();
    for g in ds
        .groups
        .iter()
        .filter(|g| g.key.grouping == Grouping::Condition)
    {
        let f = fit(&g.per_subject[0], &s.fit);
        let b = (resamples > 0).then(|| bootstrap(&f, g.key.id(), &s.bootstrap));
        let c = g.condition.as_ref().context("a condition group")?;
        let truth = own_condition_truth(&o, &d, c)?;
        let own = Some(posterior(&d, prior, &log, c));
        cells.push(Cell {
            truth,
            lower: b.as_ref().map_or(f64::NAN, |b| {
                ln_bound(b.ci_lower.as_ref(), f64::NEG_INFINITY)
            }),
            upper: b
                .as_ref()
                .map_or(f64::NAN, |b| ln_bound(b.ci_upper.as_ref(), f64::INFINITY)),
            jnd: analysis::jnd::model_threshold(&f, s.target).spp(),
            own,
        });
    }
    Ok((ds.trials, known_next(&d, &log), cells))
}

fn own_condition_truth(o: &Observer, d: &Design, c: &[String; 3]) -> Result<f64> {
    let cond = experiment::trials::conditions(d)
        .into_iter()
        .find(|x| x.scene == c[0] && x.point_set.to_string() == c[1])
        .context("condition")?;
    o.threshold(&cond).context("the observer has no threshold")
}

/// The QUEST+ model's posterior (under `prior`) from the log's trials of condition `c`: mean
/// threshold and 95% interval in spp.
fn posterior(
    d: &Design,
    prior: &QuestPlusSpec,
    log: &SessionLog,
    c: &[String; 3],
) -> (f64, f64, f64) {
    let mut levels = d.file.levels.clone();
    levels.sort_unstable();
    let mut q = QuestPlus::new(&levels, prior);
    for t in log.main_trials().filter(|t| {
        t.scene == c[0] && t.point_set.to_string() == c[1] && t.time_filter.to_string() == c[2]
    }) {
        q.update(levels.partition_point(|&l| l < t.level), t.correct);
    }
    let (mean, lo, hi) = q.ln_threshold();
    (mean.exp(), lo.exp(), hi.exp())
}

fn ln_bound(b: Option<&Bound>, outside: f64) -> f64 {
    match b {
        Some(Bound::Value { spp }) => spp.ln(),
        _ => outside,
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return f64::NAN;
    }
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn row(name: &str, trials: f64, cells: &[Cell]) -> String {
    let n = cells.len() as f64;
    let width = median(cells.iter().map(|c| c.upper - c.lower).collect()).exp();
    let inside = cells
        .iter()
        .filter(|c| (c.upper - c.lower).is_finite())
        .count() as f64
        / n;
    let covered = cells
        .iter()
        .filter(|c| c.lower <= c.truth.ln() && c.truth.ln() <= c.upper)
        .count() as f64
        / n;
    let bias: Vec<f64> = cells
        .iter()
        .filter_map(|c| c.jnd.map(|j| j / c.truth - 1.0))
        .collect();
    let mean_bias = bias.iter().sum::<f64>() / bias.len() as f64;
    let own: Vec<(f64, f64, f64, f64)> = cells
        .iter()
        .filter_map(|c| c.own.map(|(e, l, u)| (c.truth, e, l, u)))
        .collect();
    let own_text = if own.is_empty() {
        "-".to_string()
    } else {
        let w = median(own.iter().map(|o| (o.3 / o.2).ln()).collect()).exp();
        let cov = own.iter().filter(|o| o.2 <= o.0 && o.0 <= o.3).count() as f64 / own.len() as f64;
        let b = median(own.iter().map(|o| o.1 / o.0 - 1.0).collect());
        format!("{w:.2}, {cov:.3}, {b:+.3}")
    };
    let intervals = if cells.iter().any(|c| c.lower.is_nan()) {
        "- | - | -".to_string()
    } else {
        format!("{width:.2} | {inside:.3} | {covered:.3}")
    };
    format!(
        "| {name} | {trials:.1} | {intervals} | {:+.3} | {mean_bias:+.3} ({} of {}) | {own_text} |",
        median(bias.clone()),
        bias.len(),
        cells.len()
    )
}
