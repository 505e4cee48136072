//! `blurlab demo`: the whole study on built-in defaults, end to end and small.
//!
//! 1. render the demo stimulus set (`scenes/demo/job.json`: both scenes, the thesis's three
//!    point sets, levels 1..125, a reference per scene) into `stimuli/demo/` — resumable, so a
//!    second run reuses every finished frame;
//! 2. check it the way a session would (preflight of `scenes/demo/design.json`);
//! 3. predict from the stimuli how visible each one's noise is (`blurlab predict`, into
//!    `results/demo/predict/`), and run simulated subjects who answer from that prediction
//!    (`--observer FILE` instead: typed-in thresholds, e.g. `scenes/thesis/observer.json`, the
//!    thesis's JNDs) through that design into `results/demo/sessions/`;
//! 4. analyze them into `results/demo/report/` (fits, JNDs, t-tests, figures) and tabulate the
//!    stimuli's speed against error beside them (`results/demo/report/convergence/`);
//! 5. write `results/demo/summary.md` and print where everything is.

use anyhow::{Context, Result, bail};
use renderer::manifest::Manifest;
use renderer::progress::{NoProgress, Progress};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The demo's inputs, relative to the project root.
const JOB: &str = "scenes/demo/job.json";
const DESIGN: &str = "scenes/demo/design.json";

/// What the demo is asked to do (`blurlab demo`'s flags map onto it).
#[derive(Clone, Debug, PartialEq)]
pub struct DemoOptions {
    /// Project root holding `scenes/`; `None`: the current folder if it holds the demo job,
    /// else the source checkout.
    pub root: Option<PathBuf>,
    /// Results folder; `None`: <root>/results/demo.
    pub out: Option<PathBuf>,
    /// Number of simulated subjects (the thesis had 12).
    pub subjects: usize,
    /// Parametric bootstrap resamples per pooled fit.
    pub bootstrap: usize,
    /// Simulated subjects answer from this observer file instead of the prediction.
    pub observer: Option<PathBuf>,
}

impl Default for DemoOptions {
    fn default() -> Self {
        Self {
            root: None,
            out: None,
            subjects: 12,
            bootstrap: 2000,
            observer: None,
        }
    }
}

/// Where the demo's long steps report: rendering (samples) and predicting (steps).
#[derive(Clone, Copy)]
pub struct DemoProgress<'a> {
    pub render: &'a dyn Progress,
    pub predict: &'a dyn Progress,
}

impl DemoProgress<'static> {
    /// Reported nowhere.
    pub const NONE: Self = Self {
        render: &NoProgress,
        predict: &NoProgress,
    };
}

/// Where the demo put its files.
#[derive(Clone, Debug)]
pub struct DemoOutput {
    pub stimuli: PathBuf,
    pub sessions: PathBuf,
    pub report: PathBuf,
    pub convergence: PathBuf,
    pub summary: PathBuf,
    /// Frames rendered by this run and frames reused from an earlier one.
    pub frames_rendered: u64,
    pub frames_reused: u64,
    /// The analysis's summary (JND per scene and point set, test counts), for printing.
    pub jnd_summary: analysis::summary::Summary,
    /// The scene JNDs beside the thesis's, and why a small demo may differ (the summary's
    /// "Beside the thesis").
    pub beside_thesis: Option<String>,
    /// The prediction from the stimuli (`results/demo/predict/`).
    pub prediction: analysis::predict::stimuli::Prediction,
    /// The observer's JND next to the recovered one, per pooled group.
    pub side_by_side: Vec<analysis::predict::compare::JndPair>,
    /// The simulated subjects' observer: `predicted.csv` or the given file.
    pub observer: PathBuf,
    /// The analysis step's warnings (printed as they come); none on a clean run.
    pub warnings: Vec<String>,
}

/// Run the demo.
pub fn run(args: &DemoOptions, progress: DemoProgress) -> Result<DemoOutput> {
    let root = resolve_root(args.root.as_deref())?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| root.join("results").join("demo"));
    let t0 = Instant::now();

    eprintln!("[1/5] rendering stimuli ({JOB})");
    let (stimuli, manifest, frames_rendered, frames_reused) = render(&root, progress.render)?;
    let t_render = t0.elapsed().as_secs_f64();

    eprintln!("[2/5] checking the stimuli against the design ({DESIGN})");
    let design = experiment::Design::load(&root.join(DESIGN))?;
    let checks = experiment::preflight::PreflightOptions { check_hashes: true };
    experiment::preflight::preflight(&design, checks, &NoProgress).into_result()?;

    eprintln!("[3/5] predicting visibility from the stimuli");
    let predicted = analysis::predict::run::run_predict(
        &analysis::predict::run::PredictOptions {
            design: Some(root.join(DESIGN)),
            out: Some(out.join("predict")),
            // decision None: the stage the demo design's layout gets (sequential: the
            // side-by-side stage, analysis::predict::stage_choice).
            ..analysis::predict::run::PredictOptions::new(stimuli.clone())
        },
        progress.predict,
    )?;
    let observer_path = match &args.observer {
        Some(p) => p.clone(),
        None => predicted.files.predicted_csv.clone(),
    };
    eprintln!(
        "[4/5] simulating {} subjects ({})",
        args.subjects,
        observer_path.display()
    );
    let observer = experiment::Observer::load(&observer_path)?;
    let sessions = out.join("sessions");
    clear_logs(&sessions)?;
    experiment::simulate::simulate(&design, &observer, args.subjects, &sessions)?;

    eprintln!("[5/5] analyzing");
    let report = out.join("report");
    let mut analyze =
        analysis::analyze::AnalyzeOptions::new(vec![sessions.clone()], report.clone());
    analyze.bootstrap = args.bootstrap;
    // The design the sessions ran, so the trials are checked against its plan (and the
    // analysis does not warn "no --design" about the demo's own step).
    analyze.design = Some(root.join(DESIGN));
    let analysis_report = analysis::analyze::run_report(&analyze)?;
    // The library no longer prints; tolerated problems (torn last lines) are shown here, as
    // `analyze` shows them.
    for w in &analysis_report.warnings {
        eprintln!("warning: {w}");
    }
    let convergence = report.join("convergence");
    renderer::convergence::write_report(&stimuli, &convergence)?;

    let jnd_summary = analysis_report.summary();
    let beside_thesis = crate::summary::beside_thesis(&jnd_summary, &manifest);
    let side_by_side =
        analysis::predict::compare::side_by_side(&analysis_report, &design, &observer);
    let summary = out.join("summary.md");
    let text = crate::summary::markdown(&crate::summary::Inputs {
        manifest: &manifest,
        stimuli: &stimuli,
        report: &report,
        convergence: &convergence,
        jnd: &jnd_summary,
        prediction: Some(crate::summary::PredictionInputs {
            prediction: &predicted.prediction,
            side_by_side: &side_by_side,
            observer: &observer.file.name,
        }),
        render_seconds: t_render,
        total_seconds: t0.elapsed().as_secs_f64(),
    })?;
    renderer::atomic::write_atomic(&summary, text.as_bytes())?;
    Ok(DemoOutput {
        stimuli,
        sessions,
        report,
        convergence,
        summary,
        frames_rendered,
        frames_reused,
        jnd_summary,
        beside_thesis,
        prediction: predicted.prediction,
        side_by_side,
        observer: observer_path,
        warnings: analysis_report.warnings.clone(),
    })
}

/// The project root: given, or the current folder when it holds the demo job, or the checkout
/// this program was built from.
fn resolve_root(given: Option<&Path>) -> Result<PathBuf> {
    let candidates: Vec<PathBuf> = match given {
        Some(p) => vec![p.to_path_buf()],
        None => vec![
            PathBuf::from("."),
            PathBuf::from(env!("CARGO_MANIFEST_DIR")),
        ],
    };
    for c in &candidates {
        if c.join(JOB).is_file() {
            return Ok(c.clone());
        }
    }
    bail!(
        "cannot find {JOB} under {}; run the demo from the blurlab folder or pass --root",
        candidates
            .iter()
            .map(|c| c.display().to_string())
            .collect::<Vec<_>>()
            .join(" or ")
    )
}

/// Render (or finish rendering) the demo job; returns its stimulus folder, its manifest and the
/// frames rendered and reused.
fn render(root: &Path, progress: &dyn Progress) -> Result<(PathBuf, Manifest, u64, u64)> {
    let job = renderer::job::Job::load(&root.join(JOB))?;
    let opts = renderer::job::RunOptions::new(root.join("stimuli"));
    let done = renderer::job::run(&job, &opts, progress)?;
    eprintln!(
        "      {} frames rendered, {} reused from an earlier run",
        done.frames_rendered, done.frames_skipped
    );
    let Some(manifest) = done.manifest else {
        bail!(
            "{}: the stimulus set is incomplete ({} frames missing)",
            done.job_dir.display(),
            done.frames_missing
        );
    };
    Ok((
        done.job_dir,
        manifest,
        done.frames_rendered,
        done.frames_skipped,
    ))
}

/// Remove earlier simulated logs so that a changed subject count leaves no stale subject.
fn clear_logs(sessions: &Path) -> Result<()> {
    let Ok(entries) = std::fs::read_dir(sessions) else {
        return Ok(());
    };
    for e in entries {
        let p = e?.path();
        if p.extension().is_some_and(|x| x == "jsonl") {
            std::fs::remove_file(&p).with_context(|| format!("cannot remove {}", p.display()))?;
        }
    }
    Ok(())
}
