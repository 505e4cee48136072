//! `analyze <sessions dir or files...> --out <report dir>`: the command line of the analysis.
//! The umbrella binary wires [`AnalyzeArgs`] and [`run`] into `blurlab analyze`; the crate's
//! own `analyze` binary does the same alone.

use crate::bootstrap::BootstrapSettings;
use crate::comparisons::ComparisonSettings;
use crate::data::Dataset;
use crate::psychometric::{FitSettings, LapseMode};
use crate::report::{Report, Settings, analyze};
use crate::sigmoid::Sigmoid;
use crate::ttest::TestKind;
use anyhow::{Result, bail};
use clap::Args;
use std::path::PathBuf;

/// Fit psychometric functions, JNDs with bootstrap intervals and t-tests from session logs.
#[derive(Args, Clone, Debug)]
pub struct AnalyzeArgs {
    /// A sessions folder (every *.jsonl in it) or session log files.
    #[arg(required = true)]
    pub inputs: Vec<PathBuf>,
    /// Report folder (created; files in it are replaced atomically).
    #[arg(long)]
    pub out: PathBuf,
    /// Proportion correct defining the JND, in (0.5, 0.9].
    #[arg(long, default_value_t = 0.75)]
    pub target: f64,
    /// Sigmoid of the psychometric function (in ln spp).
    #[arg(long, value_enum, default_value_t = Sigmoid::Logistic)]
    pub sigmoid: Sigmoid,
    /// Lapse rate fixed at 0 or free in [0, 0.06].
    #[arg(long, value_enum, default_value_t = LapseMode::Fixed)]
    pub lapse: LapseMode,
    /// Parametric bootstrap resamples per pooled fit (at least 1000 for a reported interval).
    #[arg(long, default_value_t = 2000)]
    pub bootstrap: usize,
    /// Master seed of the bootstrap.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Levels (spp) of the t-tests.
    #[arg(long, value_delimiter = ',', default_value = "27,64,125")]
    pub levels: Vec<u32>,
    /// Extra levels for the between-scene tests (the thesis's Table 1 added 216).
    #[arg(long, value_delimiter = ',', default_value = "216")]
    pub scene_levels: Vec<u32>,
    /// Which t-test.
    #[arg(long, value_enum, default_value_t = TestKind::Paired)]
    pub test: TestKind,
    /// Significance level.
    #[arg(long, default_value_t = 0.05)]
    pub alpha: f64,
}

impl AnalyzeArgs {
    /// Validated analysis settings.
    pub fn settings(&self) -> Result<Settings> {
        if !(self.target > 0.5 && self.target <= 0.9) {
            bail!(
                "--target is {}; expected a proportion correct in (0.5, 0.9] (0.5 is chance, and \
                 above 0.9 a free lapse of up to 0.06 could keep the function from reaching it)",
                self.target
            );
        }
        if !(self.alpha > 0.0 && self.alpha < 1.0) {
            bail!("--alpha is {}; expected a level in (0, 1)", self.alpha);
        }
        if self.bootstrap < 1000 {
            bail!(
                "--bootstrap is {}; expected at least 1000 resamples for a 95% interval",
                self.bootstrap
            );
        }
        if self.levels.contains(&0) || self.scene_levels.contains(&0) {
            bail!("--levels / --scene-levels: spp must be >= 1");
        }
        Ok(Settings {
            fit: FitSettings {
                sigmoid: self.sigmoid,
                lapse: self.lapse,
            },
            target: self.target,
            bootstrap: BootstrapSettings {
                resamples: self.bootstrap,
                seed: self.seed,
                target: self.target,
                confidence: 0.95,
            },
            comparisons: ComparisonSettings {
                kind: self.test,
                levels: self.levels.clone(),
                scene_extra_levels: self.scene_levels.clone(),
                alpha: self.alpha,
            },
            poor_fit_p: 0.05,
        })
    }
}

impl AnalyzeArgs {
    /// The command's defaults for these inputs and report folder (exactly what `analyze
    /// <inputs> --out <out>` would use), for callers that set a few fields and keep the rest.
    pub fn new(inputs: Vec<PathBuf>, out: PathBuf) -> Self {
        #[derive(clap::Parser)]
        struct Defaults {
            #[command(flatten)]
            args: AnalyzeArgs,
        }
        // The inputs are set afterwards: parsing needs one (it is required) and must not read
        // a path as an option.
        let argv = ["analyze", "--out", "out", "--", "input"];
        let parsed = <Defaults as clap::Parser>::try_parse_from(argv);
        AnalyzeArgs {
            inputs,
            out,
            ..parsed.expect("the command's defaults parse").args
        }
    }
}

/// Read the logs, analyze, write the report files and figures; returns the report (e.g. for
/// [`Report::summary`]). Tolerated problems (torn last lines) are printed as warnings.
pub fn run_report(args: &AnalyzeArgs) -> Result<Report> {
    let settings = args.settings()?;
    let ds = Dataset::read(&args.inputs)?;
    for w in &ds.warnings {
        eprintln!("warning: {w}");
    }
    let report = analyze(&ds, &settings);
    report.write(&args.out)?;
    Ok(report)
}

/// The `analyze` command: [`run_report`], then a short summary on stderr.
pub fn run(args: AnalyzeArgs) -> Result<()> {
    let report = run_report(&args)?;
    eprintln!(
        "analyzed {} trials of {} subjects ({} groups, {} t-tests) -> {}\n{}",
        report.trials,
        report.subjects.len(),
        report.groups.len(),
        report.comparisons.len(),
        args.out.join("report.md").display(),
        report.summary()
    );
    Ok(())
}
