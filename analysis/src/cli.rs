//! `analyze <sessions dir or files...> --out <report dir>`: the command line of the analysis.
//! The umbrella binary wires [`AnalyzeArgs`] and [`run`] into `blurlab analyze`; the crate's
//! own `analyze` binary does the same alone.

use crate::bootstrap::BootstrapSettings;
use crate::comparisons::{ComparisonSettings, PairOrder, Unit};
use crate::data::{Dataset, Source};
use crate::psychometric::{FitSettings, GUESS, LapseMode};
use crate::report::{Preset, Report, Settings, analyze};
use crate::sigmoid::Sigmoid;
use crate::ttest::TestKind;
use anyhow::{Result, bail};
use clap::Args;
use experiment::Design;
use std::path::PathBuf;

/// Fit psychometric functions, JNDs with bootstrap intervals and t-tests from session logs.
#[derive(Args, Clone, Debug)]
pub struct AnalyzeArgs {
    /// A sessions folder (every *.jsonl in it) or session log files.
    #[arg(required = true)]
    pub inputs: Vec<PathBuf>,
    /// Leave out main trials that fail the log checks (answer fields, indices, mode, and the
    /// design's plan with --design), with a warning each, instead of stopping at the first.
    #[arg(long)]
    pub lenient: bool,
    /// Report folder (created; files in it are replaced atomically).
    #[arg(long)]
    pub out: PathBuf,
    /// Proportion correct defining the JND, in (guess rate, 0.9].
    #[arg(long, default_value_t = 0.75, conflicts_with = "preset")]
    pub target: f64,
    /// Guess rate: the lower asymptote, 1/m for m alternatives. Default: the task of --design,
    /// else 0.5 for session logs (the two-pair task); counts tables need --guess or --design.
    #[arg(long)]
    pub guess: Option<f64>,
    /// The study's design file: its task gives the guess rate and its factor order the pair
    /// order of the t-tests; its hash must match the logs'.
    #[arg(long)]
    pub design: Option<PathBuf>,
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
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "27,64,125",
        conflicts_with = "preset"
    )]
    pub levels: Vec<u32>,
    /// Extra levels for the between-scene tests (the thesis's Table 1 added 216).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "216",
        conflicts_with = "preset"
    )]
    pub scene_levels: Vec<u32>,
    /// Which t-test.
    #[arg(long, value_enum, default_value_t = TestKind::Paired, conflicts_with = "preset")]
    pub test: TestKind,
    /// Significance level.
    #[arg(long, default_value_t = 0.05, conflicts_with = "preset")]
    pub alpha: f64,
    /// Unit of observation of the t-tests: one value per subject (pooled over the other
    /// factors), or per subject x other-factor cell as the thesis did (cells of one subject are
    /// not independent: more df, smaller p).
    #[arg(long, value_enum, default_value_t = Unit::Subject, conflicts_with = "preset")]
    pub unit: Unit,
    /// Leave subjects out: `s03,s07`, or with reasons `s03=fell asleep,s07=did not finish`
    /// (a reason cannot hold a comma). Listed in the report.
    #[arg(long, value_delimiter = ',')]
    pub exclude: Vec<String>,
    /// Lay the analysis out as a publication did: `thesis` fixes --unit cell, --test paired,
    /// --alpha 0.05 (no correction), --levels 27,64,125, --scene-levels 216, --target 0.75,
    /// the thesis's pair order, and writes its Tables 1 and 2 (`thesis_tables.csv`).
    #[arg(long, value_enum)]
    pub preset: Option<Preset>,
}

impl AnalyzeArgs {
    /// Validated analysis settings, the guess rate from --guess or 0.5 (see
    /// [`AnalyzeArgs::settings_for`] for the default from the data and the design).
    pub fn settings(&self) -> Result<Settings> {
        self.settings_with_guess(self.guess.unwrap_or(GUESS))
    }

    /// Validated settings for this data: the guess rate from --guess, else the task of
    /// `design`, else 0.5 for session logs; the pair order from the design's factors, else
    /// the preset's.
    pub fn settings_for(&self, ds: &Dataset, design: Option<&Design>) -> Result<Settings> {
        let guess = match (self.guess, design) {
            (Some(g), _) => g,
            (None, Some(d)) => d.file.task.guess_rate(),
            (None, None) if ds.source == Source::CountsTables => bail!(
                "counts tables do not say the task: give --guess (1/m for m alternatives) or \
                 --design (its `task`)"
            ),
            (None, None) => GUESS,
        };
        let mut s = self.settings_with_guess(guess)?;
        if let Some(d) = design {
            let f = &d.file.factors;
            s.comparisons.order = PairOrder {
                scenes: f.scenes.clone(),
                point_sets: f.point_sets.clone(),
                time_filters: f.time_filters.clone(),
            };
        }
        Ok(s)
    }

    /// `--exclude` as (subject, reason) pairs.
    pub fn exclusions(&self) -> Vec<(String, Option<String>)> {
        self.exclude
            .iter()
            .map(|e| match e.split_once('=') {
                Some((id, reason)) => (id.trim().to_string(), Some(reason.trim().to_string())),
                None => (e.trim().to_string(), None),
            })
            .filter(|(id, _)| !id.is_empty())
            .collect()
    }

    fn settings_with_guess(&self, guess: f64) -> Result<Settings> {
        let thesis = self.preset == Some(Preset::Thesis);
        // The preset's values; clap refuses the options it fixes, so these replace defaults.
        let (target, alpha, kind, unit) = if thesis {
            (0.75, 0.05, TestKind::Paired, Unit::Cell)
        } else {
            (self.target, self.alpha, self.test, self.unit)
        };
        let (levels, scene_levels) = if thesis {
            (vec![27, 64, 125], vec![216])
        } else {
            (self.levels.clone(), self.scene_levels.clone())
        };
        if !(guess > 0.0 && guess < 1.0) {
            bail!("--guess is {guess}; expected a proportion in (0, 1), 1/m for m alternatives");
        }
        if !(target > guess && target <= 0.9) {
            bail!(
                "--target is {target}; expected a proportion correct in ({guess}, 0.9] (the guess \
                 rate {guess} is chance, and above 0.9 a free lapse of up to 0.06 could keep the \
                 function from reaching it)"
            );
        }
        if !(alpha > 0.0 && alpha < 1.0) {
            bail!("--alpha is {alpha}; expected a level in (0, 1)");
        }
        if self.bootstrap < 1000 {
            bail!(
                "--bootstrap is {}; expected at least 1000 resamples for a 95% interval",
                self.bootstrap
            );
        }
        if levels.contains(&0) || scene_levels.contains(&0) {
            bail!("--levels / --scene-levels: spp must be >= 1");
        }
        Ok(Settings {
            fit: FitSettings {
                sigmoid: self.sigmoid,
                lapse: self.lapse,
                guess,
            },
            target,
            bootstrap: BootstrapSettings {
                resamples: self.bootstrap,
                seed: self.seed,
                target,
                confidence: 0.95,
            },
            comparisons: ComparisonSettings {
                kind,
                levels,
                scene_extra_levels: scene_levels,
                alpha,
                unit,
                order: if thesis {
                    PairOrder::thesis()
                } else {
                    PairOrder::default()
                },
            },
            poor_fit_p: 0.05,
            preset: self.preset,
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
    if args.guess.is_some() || args.design.is_none() {
        // Refuse bad options before reading any data (with a design the guess rate, and so
        // the valid targets, come from its task).
        args.settings()?;
    }
    let design = args.design.as_deref().map(Design::load).transpose()?;
    let mut ds = Dataset::read_checked(&args.inputs, design.as_ref(), args.lenient)?;
    if let Some(d) = &design {
        check_design(d, &ds)?;
    }
    ds.exclude(&args.exclusions())?;
    let settings = args.settings_for(&ds, design.as_ref())?;
    for w in &ds.warnings {
        eprintln!("warning: {w}");
    }
    let report = analyze(&ds, &settings);
    report.write(&args.out)?;
    Ok(report)
}

/// Session logs must come from `design` (same hash); counts tables carry no hash.
fn check_design(design: &Design, ds: &Dataset) -> Result<()> {
    if ds.source == Source::SessionLogs && ds.design_hash != design.hash {
        bail!(
            "--design {} has design hash {:?}, but the session logs ({}) carry {:?} (design \
             {:?}); give the design the logs were recorded with",
            design.path.display(),
            design.hash,
            ds.files
                .first()
                .map_or(String::new(), |f| f.display().to_string()),
            ds.design_hash,
            ds.design
        );
    }
    Ok(())
}

/// The `analyze` command: [`run_report`], then a short summary on stderr.
pub fn run(args: AnalyzeArgs) -> Result<()> {
    let report = run_report(&args)?;
    let excluded = match report.excluded.len() {
        0 => String::new(),
        n => format!(", {n} excluded"),
    };
    eprintln!(
        "analyzed {} trials of {} subjects{excluded} ({} groups, {} t-tests) -> {}\n{}",
        report.trials,
        report.subjects.len(),
        report.groups.len(),
        report.comparisons.len(),
        args.out.join("report.md").display(),
        report.summary()
    );
    Ok(())
}
