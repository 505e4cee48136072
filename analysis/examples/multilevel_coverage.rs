//! Coverage and bias of the multilevel model's population-JND interval, against the pooled
//! fit's parametric bootstrap, and the size and power of its TOST, by simulating the thesis
//! design through the real session machine (`analysis::plan::replicate`, the same as `plan`).
//!
//! The observer is the thesis's (logistic, slope 1.5, plane 40 and spheres 100 spp) with
//! Hammersley's thresholds a factor e^0.2 higher and the given subject spread (uniform in ln
//! spp over a range this wide, the observer file's `subject_spread`). Per replication: the
//! conditions plane/poisson (true JND 40) and spheres/stratified (100) are fitted by the
//! multilevel model (Wald interval) and by the pooled fit with 39 bootstrap resamples (an
//! interval of exactly 95% nominal coverage, docs/analysis.md); the point-set pairs
//! hammersley-poisson (true difference 0.2 = the margin: the TOST's size) and
//! poisson-stratified (no difference: its power) are compared in one model each.
//!
//! `cargo run -p analysis --example multilevel_coverage -- <replications> <spreads, e.g.
//! 0.3,0.9> [subjects] [coverage|tost] [first replication] [levels] [all|informative]
//! [subject resamples] [source=session|model] [offsets=normal|uniform] [tost=yes|no] [nodes=15]
//! [repeats=4]`
//!
//! Per condition the table gives the coverage of each interval of [`INTERVALS`] (the model's
//! Wald interval, the same with its SE scaled by sqrt(n / (n - 1)), the cluster-robust CR1
//! interval, the subject bootstrap with the given resamples (0, the default: not run), the
//! pooled bootstrap, the profile-likelihood interval), the mean ln error, the mean estimated
//! between-subject SD and slope, and how often sigma sat at its bound; every replication is
//! also written to stderr as CSV lines (`row,...`, see [`row`]) as it finishes.
//!
//! `source=model` bypasses the session machine: each condition's subjects are drawn from the
//! multilevel model's own generative process (ln thresholds normal with SD `spread` around the
//! truth, the same offset in both conditions, logistic slope 1.5, guess 1/2, no lapse, the
//! design's repeats at each of its levels but the reference's), so the estimator is measured
//! where the model is right (no pooled bootstrap, no TOST); `repeats=N` replaces the design's
//! repeats there, and `offsets=uniform` draws the offsets uniform with SD `spread` instead (the
//! session machine's shape, without the session machine). `tost=no` skips the TOST's two two-group fits per replication in a coverage
//! run; `nodes=N` sets the quadrature's nodes per subject (15, the default of `analyze`).
//!
//! `levels` replaces the design's levels (`thesis`, or a list such as
//! `1,8,27,64,125,216,343,512,729,1000`; the reference stays the highest level). With
//! `informative` (the default, as `analyze`) the multilevel model leaves out the trials where
//! test and reference are the same video (`Dataset::same_video_levels`: the highest level), at
//! which the simulated observer answers at chance whatever its threshold; with `all` it fits
//! them too, as the first three passes did (the pooled bootstrap keeps them either way: it is
//! `plan`'s).
//!
//! Replications run from the first index (0) on, so a long run can be split into chunks
//! (`100 0.9 12 coverage 500` is replications 500-599) whose rates add up weighted by count.
//!
//! With `tost` only the TOST's size and power are measured (no condition fits, no pooled
//! bootstraps): at the subject counts where the TOST has power (48, 96, ...) the coverage part
//! would cost most of the time and is not what is asked there.

use analysis::bootstrap::Bound;
use analysis::data::{Curve, Dataset, Grouping};
use analysis::multilevel::compare::{difference, tost};
use analysis::multilevel::profile::threshold_interval;
use analysis::multilevel::{Context, MultilevelSettings, estimate, group_model, t_quantile};
use analysis::plan::replicate::{ReplicationSettings, replicate};
use analysis::psychometric::{GUESS, Model};
use analysis::report::Settings;
use analysis::sigmoid::Sigmoid;
use analysis::simulate::simulate_curve;
use experiment::{Design, Observer};
use rayon::prelude::*;
use renderer::hash::{hash, unit_f64};
use std::path::Path;

const MARGIN: f64 = 0.2;

/// The intervals compared, in the table's order.
const INTERVALS: [&str; 6] = [
    "Wald t",
    "Wald t, SE x sqrt(n/(n-1))",
    "robust (CR1) t",
    "subject bootstrap",
    "pooled bootstrap",
    "profile t",
];

/// The conditions whose JND is checked: group label, true JND (spp).
const CONDITIONS: [(&str, f64); 2] = [
    ("plane/poisson/truncated_box", 40.0),
    ("spheres/stratified/truncated_box", 100.0),
];

/// One condition of one replication.
#[derive(Default, Clone, Copy)]
struct Cell {
    /// Whether each of [`INTERVALS`] covers the truth (the subject bootstrap's and the pooled
    /// bootstrap's only when run).
    covers: [bool; 6],
    /// ln estimate - ln truth.
    error: f64,
    /// The between-subject SD's and the slope's estimates.
    sigma: f64,
    slope: f64,
    /// Sigma at its lower bound (0.001: no spread detected).
    at_bound: bool,
}

/// What one replication found.
#[derive(Default, Clone, Copy)]
struct Outcome {
    cells: [Cell; 2],
    /// TOST shown equivalent: at the margin, at no difference.
    at_margin: bool,
    at_zero: bool,
}

fn observer(spread: f64) -> Observer {
    let h = MARGIN.exp();
    let text = format!(
        r#"{{"format": "blurlab-observer/1", "name": "coverage", "slope": 1.5, "lapse": 0.0,
        "subject_spread": {spread}, "seed": 2013, "thresholds": [
        {{"scene": "plane", "point_set": "hammersley", "spp": {}}},
        {{"scene": "plane", "spp": 40}},
        {{"scene": "spheres", "point_set": "hammersley", "spp": {}}},
        {{"scene": "spheres", "spp": 100}}]}}"#,
        40.0 * h,
        100.0 * h
    );
    Observer::parse(Path::new("coverage.json"), &text).expect("a valid observer")
}

fn ln_interval(lo: &Option<Bound>, hi: &Option<Bound>) -> (f64, f64) {
    let end = |b: &Option<Bound>, out: f64| match b {
        Some(Bound::Value { spp }) => spp.ln(),
        Some(Bound::BelowRange { .. }) => f64::NEG_INFINITY,
        Some(Bound::AboveRange { .. }) => f64::INFINITY,
        None => out,
    };
    (end(lo, f64::INFINITY), end(hi, f64::NEG_INFINITY))
}

/// What a run varies besides the spread.
#[derive(Clone, Copy)]
struct Run {
    subjects: usize,
    coverage: bool,
    /// Leave the highest level (test = reference) out of the multilevel fits.
    informative: bool,
    /// Subject-bootstrap resamples per condition (0: none).
    subject_resamples: usize,
    /// Data from the model's own process instead of the session machine.
    model_source: bool,
    /// Fit the TOST's pairs in a coverage run.
    tost: bool,
    /// Gauss-Hermite nodes per subject.
    nodes: usize,
    /// Trials per level of the model source.
    repeats: u32,
    /// The model source's offsets uniform (with the same SD) instead of normal.
    uniform: bool,
}

/// Whether column k of [`INTERVALS`] is measured in this run.
fn measured(k: usize, run: Run) -> bool {
    match k {
        3 => run.subject_resamples > 0,
        4 => !run.model_source,
        _ => true,
    }
}

fn one(design: &Design, obs: &Observer, spread: f64, r: u64, run: Run) -> Outcome {
    if run.model_source {
        return from_model(design, spread, r, run);
    }
    let Run {
        subjects, coverage, ..
    } = run;

    let mut analysis = Settings::default();
    analysis.bootstrap.resamples = 39;
    let s = ReplicationSettings {
        analysis,
        groupings: if coverage {
            vec![Grouping::Condition]
        } else {
            Vec::new()
        },
    };
    let (rep, ds) = replicate(design, obs, subjects, r, &s).expect("a replication");
    let ml = MultilevelSettings {
        resamples: run.subject_resamples,
        nodes: run.nodes,
        ..MultilevelSettings::default()
    };
    let fit = s.analysis.fit;
    let cx = Context {
        fit: &fit,
        target: 0.75,
        settings: &ml,
        same_video_levels: if run.informative {
            &ds.same_video_levels
        } else {
            &[]
        },
    };
    let mut out = Outcome::default();
    let cells = if coverage { 2 } else { 0 };
    for (i, &(label, truth)) in CONDITIONS.iter().take(cells).enumerate() {
        let g = ds.groups.iter().find(|g| g.key.label == label).unwrap();
        let (_, b) = rep.pooled.iter().find(|(k, _)| k.label == label).unwrap();
        let t = truth.ln();
        let pooled = ln_interval(&b.ci_lower, &b.ci_upper);
        let pooled = pooled.0 <= t && t <= pooled.1;
        let subject_boot = (run.subject_resamples > 0).then(|| {
            let m = group_model(&ds, g, &cx).expect("identified");
            let sb = m.bootstrap.expect("resamples > 0");
            let (lo, hi) = ln_interval(&sb.ci_lower, &sb.ci_upper);
            lo <= t && t <= hi
        });
        out.cells[i] = cell(&g.per_subject, &cx, t, subject_boot, pooled);
    }
    if coverage && !run.tost {
        return out;
    }
    let tost_of = |a: &str, b: &str| {
        let curves: Vec<&[Curve]> = [a, b]
            .iter()
            .map(|l| group(&ds, l).per_subject.as_slice())
            .collect();
        let (e, c) = estimate(&curves, false, &cx, None).expect("identified");
        let (d, se) = difference(&e);
        tost(
            d,
            se.expect("a covariance"),
            (c.subjects.len() - 1) as f64,
            MARGIN,
        )
        .equivalent
    };
    out.at_margin = tost_of("hammersley", "poisson");
    out.at_zero = tost_of("poisson", "stratified");
    out
}

/// One condition's cell from its subjects' curves: the model's intervals (Wald, its
/// sqrt(n / (n - 1)) variant, CR1, profile) against the truth `t` (ln spp), with the bootstrap
/// verdicts computed by the caller. Ends beyond the tested range count as unbounded (as the
/// report's "above range"): the truths lie inside it, so the raw ln ends decide alike.
fn cell(curves: &[Curve], cx: &Context, t: f64, subject_boot: Option<bool>, pooled: bool) -> Cell {
    let (e, counts) = estimate(&[curves], false, cx, None).expect("identified");
    let n = counts.subjects.len() as f64;
    let tq = t_quantile(0.975, n - 1.0);
    let est = e.params.thresholds[0];
    let inside = |(lo, hi): (f64, f64)| lo <= t && t <= hi;
    let around = |se: Option<f64>| se.map_or((1.0, 0.0), |s| (est - tq * s, est + tq * s));
    let se = e.se(0);
    Cell {
        covers: [
            inside(around(se)),
            inside(around(se.map(|s| s * (n / (n - 1.0)).sqrt()))),
            inside(around(e.robust_se(0))),
            subject_boot.unwrap_or(false),
            pooled,
            inside(threshold_interval(&e, &counts, cx, 0, tq)),
        ],
        error: est - t,
        sigma: e.params.sigma,
        slope: e.params.slopes[0],
        at_bound: e.layout.at_bound(&e.vector, &e.bounds)[e.layout.sigma_index()],
    }
}

/// Replication `r` with data from the model's own process (`source=model`): subject s's
/// offset sigma z, z standard normal (or uniform over +-sqrt(3)) from `hash(seed, [r, s])`, the
/// same in both conditions.
fn from_model(design: &Design, sigma: f64, r: u64, run: Run) -> Outcome {
    const SEED: u64 = 0x0de1;
    let top = design.file.levels.iter().copied().max().unwrap_or(0);
    let levels: Vec<u32> = (design.file.levels.iter().copied())
        .filter(|&l| l != top)
        .collect();
    let offsets: Vec<f64> = (0..run.subjects as u64)
        .map(|s| {
            let p = unit_f64(hash(SEED, &[r, s])).max(1e-12);
            let z = if run.uniform {
                12f64.sqrt() * (p - 0.5)
            } else {
                Sigmoid::Normal.inverse(p)
            };
            sigma * z
        })
        .collect();
    let fit = Settings::default().fit;
    let ml = MultilevelSettings {
        resamples: 0,
        nodes: run.nodes,
        ..MultilevelSettings::default()
    };
    let cx = Context {
        fit: &fit,
        target: 0.75,
        settings: &ml,
        same_video_levels: &[],
    };
    let mut out = Outcome::default();
    for (i, &(_, truth)) in CONDITIONS.iter().enumerate() {
        let curves: Vec<Curve> = (offsets.iter().enumerate())
            .map(|(s, u)| {
                let m = Model {
                    sigmoid: Sigmoid::Logistic,
                    // With g = 1/2 the logistic's alpha is its 0.75 point.
                    alpha: truth.ln() + u,
                    beta: 1.5,
                    lapse: 0.0,
                    guess: GUESS,
                };
                let coords = [r, i as u64, s as u64];
                simulate_curve(&m, &levels, run.repeats, SEED, &coords)
            })
            .collect();
        out.cells[i] = cell(&curves, &cx, truth.ln(), None, false);
    }
    out
}

fn group<'a>(ds: &'a Dataset, label: &str) -> &'a analysis::data::Group {
    ds.groups_of(Grouping::PointSet)
        .find(|g| g.key.label == label)
        .unwrap()
}

fn main() {
    let (options, args): (Vec<String>, Vec<String>) =
        std::env::args().partition(|a| a.contains('='));
    let option = |key: &str, default: &str| -> String {
        (options.iter())
            .find_map(|o| o.strip_prefix(&format!("{key}=")).map(str::to_string))
            .unwrap_or_else(|| default.to_string())
    };
    let reps: u64 = args.get(1).map_or(100, |a| a.parse().unwrap());
    let spreads: Vec<f64> = args
        .get(2)
        .map_or("0.3,0.9", |a| a.as_str())
        .split(',')
        .map(|s| s.parse().unwrap())
        .collect();
    let subjects: usize = args.get(3).map_or(12, |a| a.parse().unwrap());
    let coverage = args.get(4).is_none_or(|a| a != "tost");
    let first: u64 = args.get(5).map_or(0, |a| a.parse().unwrap());
    let runs = first..first + reps;
    let mut design =
        Design::load(Path::new("scenes/thesis/design.json")).expect("the thesis design");
    if let Some(l) = args.get(6).filter(|a| *a != "thesis") {
        design.file.levels = l.split(',').map(|v| v.parse().unwrap()).collect();
    }
    let run = Run {
        subjects,
        coverage,
        informative: args.get(7).is_none_or(|a| a != "all"),
        subject_resamples: args.get(8).map_or(0, |a| a.parse().unwrap()),
        model_source: option("source", "session") == "model",
        tost: option("tost", "yes") == "yes",
        uniform: option("offsets", "normal") == "uniform",
        nodes: option("nodes", "15").parse().expect("nodes=N"),
        repeats: (option("repeats", &design.file.repeats.to_string()))
            .parse()
            .expect("repeats=N"),
    };
    if !coverage {
        return tost_only(&design, runs, &spreads, run);
    }
    let columns: Vec<&str> = (INTERVALS.iter().enumerate())
        .filter(|&(k, _)| measured(k, run))
        .map(|(_, name)| *name)
        .collect();
    println!(
        "| spread (SD) | replications | condition | {} | mean ln JND error | ratio | mean sigma | sigma at bound | mean slope | TOST at margin (size) | TOST at 0 (power) | CPU s |",
        columns.join(" | ")
    );
    println!("|{}", "---|".repeat(columns.len() + 11));
    for spread in spreads {
        let obs = observer(spread);
        let t0 = cpu_seconds();
        let outs: Vec<Outcome> = runs
            .clone()
            .into_par_iter()
            .map(|r| {
                let o = one(&design, &obs, spread, r, run);
                row(spread, r, &o);
                o
            })
            .collect();
        let cpu = cpu_seconds() - t0;
        let n = outs.len() as f64;
        let size = outs.iter().filter(|o| o.at_margin).count() as f64 / n;
        let power = outs.iter().filter(|o| o.at_zero).count() as f64 / n;
        for (i, label) in ["plane/poisson (40)", "spheres/stratified (100)"]
            .iter()
            .enumerate()
        {
            let rates: Vec<String> = (0..INTERVALS.len())
                .filter(|&k| measured(k, run))
                .map(|k| {
                    let covered = outs.iter().filter(|o| o.cells[i].covers[k]).count();
                    format!("{:.3}", covered as f64 / n)
                })
                .collect();
            let bias = outs.iter().map(|o| o.cells[i].error).sum::<f64>() / n;
            let mean = |f: fn(&Cell) -> f64| outs.iter().map(|o| f(&o.cells[i])).sum::<f64>() / n;
            let sigma = mean(|c| c.sigma);
            let slope = mean(|c| c.slope);
            let bound = mean(|c| f64::from(u8::from(c.at_bound)));
            // The model source's spread is the SD itself, the session's a uniform width.
            let sd = if run.model_source {
                spread
            } else {
                spread / 12f64.sqrt()
            };
            println!(
                "| {spread} ({sd:.3}) | {reps} | {label} | {} | {bias:+.4} | {:.3} | {sigma:.3} | {bound:.3} | {slope:.3} | {size:.3} | {power:.3} | {cpu:.0} |",
                rates.join(" | "),
                bias.exp()
            );
        }
    }
}

/// One replication as CSV lines on stderr, one per condition, as it finishes (a long run
/// stopped early still leaves its finished replications): spread, replication, condition,
/// each interval's 0/1 in [`INTERVALS`]' order, ln error, sigma, slope, sigma at its bound
/// (0/1), TOST at margin, at zero.
fn row(spread: f64, r: u64, o: &Outcome) {
    for (i, c) in o.cells.iter().enumerate() {
        let covers: Vec<&str> = c
            .covers
            .iter()
            .map(|&b| if b { "1" } else { "0" })
            .collect();
        eprintln!(
            "row,{spread},{r},{i},{},{:.6},{:.6},{:.6},{},{},{}",
            covers.join(","),
            c.error,
            c.sigma,
            c.slope,
            u8::from(c.at_bound),
            u8::from(o.at_margin),
            u8::from(o.at_zero)
        );
    }
}

/// The TOST's size at the margin and power at no difference, with their binomial SDs.
fn tost_only(design: &Design, runs: std::ops::Range<u64>, spreads: &[f64], run: Run) {
    let subjects = run.subjects;
    let reps = runs.end - runs.start;
    println!(
        "| subjects | spread | replications | TOST at margin (size) | SD | TOST at 0 (power) | SD | CPU s |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for &spread in spreads {
        let obs = observer(spread);
        let t0 = cpu_seconds();
        let outs: Vec<Outcome> = runs
            .clone()
            .into_par_iter()
            .map(|r| one(design, &obs, spread, r, run))
            .collect();
        let cpu = cpu_seconds() - t0;
        let n = outs.len() as f64;
        let rate = |f: fn(&Outcome) -> bool| outs.iter().filter(|o| f(o)).count() as f64 / n;
        let sd = |p: f64| (p * (1.0 - p) / n).sqrt();
        let (size, power) = (rate(|o| o.at_margin), rate(|o| o.at_zero));
        println!(
            "| {subjects} | {spread} | {reps} | {size:.3} | {:.4} | {power:.3} | {:.4} | {cpu:.0} |",
            sd(size),
            sd(power)
        );
    }
}

/// CPU time of the process (all threads), seconds.
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let fields: Vec<&str> = stat
        .rsplit(')')
        .next()
        .unwrap_or("")
        .split_whitespace()
        .collect();
    let ticks = |i: usize| {
        fields
            .get(i)
            .and_then(|v| v.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    // utime and stime are fields 14 and 15 of /proc/pid/stat (11 and 12 after the name).
    (ticks(11) + ticks(12)) / 100.0
}
