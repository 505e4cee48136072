//! `blurlab analyze <sessions dir or files...> --out <report dir>`: the analysis's flags. They
//! only map onto `analysis::analyze::AnalyzeOptions`, whose defaults they repeat (a test checks
//! that they agree).

use super::named::named;
use analysis::analyze::{AnalyzeOptions, ModelKind, run_report};
use analysis::comparisons::Unit;
use analysis::psychometric::LapseMode;
use analysis::report::Preset;
use analysis::sigmoid::Sigmoid;
use analysis::ttest::TestKind;
use anyhow::Result;
use clap::Args;
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
    #[arg(
        long,
        default_value_t = 0.75,
        conflicts_with = "preset",
        allow_negative_numbers = true
    )]
    pub target: f64,
    /// Guess rate: the lower asymptote, 1/m for m alternatives. Default: the task of --design,
    /// else 0.5 for session logs (the two-pair task); counts tables need --guess or --design.
    #[arg(long, allow_negative_numbers = true)]
    pub guess: Option<f64>,
    /// The study's design file: its task gives the guess rate and its factor order the pair
    /// order of the t-tests; its hash must match the logs'.
    #[arg(long)]
    pub design: Option<PathBuf>,
    /// Sigmoid of the psychometric function (in ln spp).
    #[arg(long, value_parser = named::<Sigmoid>(), default_value = "logistic")]
    pub sigmoid: Sigmoid,
    /// Lapse rate fixed at 0 or free in [0, 0.06].
    #[arg(long, value_parser = named::<LapseMode>(), default_value = "fixed")]
    pub lapse: LapseMode,
    /// Parametric bootstrap resamples per pooled fit (at least 1000 for a reported interval).
    #[arg(long, default_value_t = 2000, value_parser = renderer::limits::resamples(1000),
          allow_hyphen_values = true)]
    pub bootstrap: usize,
    /// Master seed of the bootstrap.
    #[arg(long, default_value_t = 1, value_parser = renderer::limits::parse_seed,
          allow_hyphen_values = true)]
    pub seed: u64,
    /// Levels (spp) of the t-tests.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "27,64,125",
        conflicts_with = "preset",
        value_parser = renderer::limits::parse_spp,
        allow_hyphen_values = true
    )]
    pub levels: Vec<u32>,
    /// Extra levels for the between-scene tests (the thesis's Table 1 added 216).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "216",
        conflicts_with = "preset",
        value_parser = renderer::limits::parse_spp,
        allow_hyphen_values = true
    )]
    pub scene_levels: Vec<u32>,
    /// Which t-test.
    #[arg(long, value_parser = named::<TestKind>(), default_value = "paired", conflicts_with = "preset")]
    pub test: TestKind,
    /// Significance level.
    #[arg(
        long,
        default_value_t = 0.05,
        conflicts_with = "preset",
        allow_negative_numbers = true
    )]
    pub alpha: f64,
    /// Unit of observation of the t-tests: one value per subject (pooled over the other
    /// factors), or per subject x other-factor cell as the thesis did (cells of one subject are
    /// not independent: more df, smaller p).
    #[arg(long, value_parser = named::<Unit>(), default_value = "subject", conflicts_with = "preset")]
    pub unit: Unit,
    /// Leave subjects out: `s03,s07`, or with reasons `s03=fell asleep,s07=did not finish`
    /// (a reason cannot hold a comma). Listed in the report.
    #[arg(long, value_delimiter = ',')]
    pub exclude: Vec<String>,
    /// Lay the analysis out as a publication did: `thesis` fixes --unit cell, --test paired,
    /// --alpha 0.05 (no correction), --levels 27,64,125, --scene-levels 216, --target 0.75,
    /// the thesis's pair order, and writes its Tables 1 and 2 (`thesis_tables.csv`).
    #[arg(long, value_parser = named::<Preset>())]
    pub preset: Option<Preset>,
    /// The model across subjects: `pooled` (the pooled fits only) or `multilevel` (also a
    /// multilevel model: subjects' thresholds as normal random effects in ln spp, the
    /// population JND with intervals that include the between-subject variance, model-based
    /// comparisons; see docs/analysis.md) [default: pooled, multilevel with --equivalence].
    #[arg(long, value_parser = named::<ModelKind>())]
    pub model: Option<ModelKind>,
    /// Equivalence margin in ln JND (0.2: a ratio within 0.82-1.22): two one-sided tests for
    /// every point-set and time-filter pair from the multilevel model (implies --model
    /// multilevel).
    #[arg(long, allow_negative_numbers = true)]
    pub equivalence: Option<f64>,
    /// Subject-bootstrap resamples of the multilevel model (whole subjects resampled and the
    /// model refitted; 0: none; at least 200).
    #[arg(long, default_value_t = 200, value_parser = renderer::limits::resamples(0),
          allow_hyphen_values = true)]
    pub subject_bootstrap: usize,
    /// Warn about main trials with more than N dropped frames (frames the display skipped:
    /// the subject did not see all of the stimulus), naming each; with --exclude-dropped
    /// leave them out. See docs/analysis.md.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(0..=1_000_000),
          allow_hyphen_values = true)]
    pub max_dropped_frames: Option<u32>,
    /// Leave out the trials over --max-dropped-frames.
    #[arg(long, requires = "max_dropped_frames")]
    pub exclude_dropped: bool,
    /// Name every subject whose share of main trials over --max-dropped-frames is above this.
    #[arg(long, default_value_t = 0.2,
          value_parser = renderer::limits::real(0.0, 1.0, false, "a share of trials"),
          allow_hyphen_values = true)]
    pub max_dropped_share: f64,
    #[command(flatten)]
    pub screening: ScreeningArgs,
}

/// The exclusion criteria (docs/analysis.md, "Exclusions"); each replaces the design's
/// `exclusion` field of the same name.
#[derive(Args, Clone, Debug, Default)]
pub struct ScreeningArgs {
    /// Exclude a subject whose share of catch trials answered correctly is below this.
    #[arg(long, value_parser = renderer::limits::real(0.0, 1.0, false, "a share of catch trials"),
          allow_hyphen_values = true)]
    pub min_catch_accuracy: Option<f64>,
    /// Exclude a subject whose share of frames dropped or late is above this.
    #[arg(long, value_parser = renderer::limits::real(0.0, 1.0, false, "a share of frames"),
          allow_hyphen_values = true)]
    pub max_bad_frames: Option<f64>,
    /// A response faster than this (ms after the last video) is too fast to have watched.
    #[arg(long, value_parser = renderer::limits::real(0.0, 60000.0, false, "milliseconds"),
          allow_hyphen_values = true)]
    pub min_rt_ms: Option<f64>,
    /// Exclude a subject whose share of fast responses is above this (default 0.2).
    #[arg(long, value_parser = renderer::limits::real(0.0, 1.0, false, "a share of responses"),
          allow_hyphen_values = true)]
    pub max_fast_share: Option<f64>,
    /// Exclude subjects who did not finish every main trial.
    #[arg(long)]
    pub require_finished: bool,
    /// Exclude a subject whose pixels per degree were outside LOW,HIGH.
    #[arg(long, value_name = "LOW,HIGH", value_parser = parse_range, allow_hyphen_values = true)]
    pub pixels_per_degree: Option<[f64; 2]>,
    /// Exclude a subject whose viewing distance (mm) was outside LOW,HIGH.
    #[arg(long, value_name = "LOW,HIGH", value_parser = parse_range, allow_hyphen_values = true)]
    pub viewing_distance_mm: Option<[f64; 2]>,
    /// Exclude a subject whose refresh rate (Hz) was outside LOW,HIGH.
    #[arg(long, value_name = "LOW,HIGH", value_parser = parse_range, allow_hyphen_values = true)]
    pub refresh_hz: Option<[f64; 2]>,
    /// Name the subjects the criteria exclude, but keep them in the fits.
    #[arg(long)]
    pub keep_excluded: bool,
}

/// `LOW,HIGH`: two numbers, 0 <= LOW <= HIGH.
fn parse_range(s: &str) -> Result<[f64; 2], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let nums: Vec<f64> = parts.iter().filter_map(|p| p.parse().ok()).collect();
    match nums[..] {
        [lo, hi]
            if parts.len() == 2 && lo.is_finite() && hi.is_finite() && 0.0 <= lo && lo <= hi =>
        {
            Ok([lo, hi])
        }
        _ => Err(format!(
            "{s:?}: expected LOW,HIGH, two numbers with 0 <= LOW <= HIGH (e.g. 20,80)"
        )),
    }
}

impl ScreeningArgs {
    fn criteria(&self) -> experiment::design::online::Exclusion {
        experiment::design::online::Exclusion {
            min_catch_accuracy: self.min_catch_accuracy,
            max_bad_frames: self.max_bad_frames,
            min_rt_ms: self.min_rt_ms,
            max_fast_share: self.max_fast_share,
            require_finished: self.require_finished,
            display: experiment::design::online::DisplayRanges {
                pixels_per_degree: self.pixels_per_degree,
                viewing_distance_mm: self.viewing_distance_mm,
                refresh_hz: self.refresh_hz,
            },
        }
    }
}

impl AnalyzeArgs {
    /// The options these flags ask for.
    pub fn options(&self) -> AnalyzeOptions {
        AnalyzeOptions {
            inputs: self.inputs.clone(),
            lenient: self.lenient,
            out: self.out.clone(),
            target: self.target,
            guess: self.guess,
            design: self.design.clone(),
            sigmoid: self.sigmoid,
            lapse: self.lapse,
            bootstrap: self.bootstrap,
            seed: self.seed,
            levels: self.levels.clone(),
            scene_levels: self.scene_levels.clone(),
            test: self.test,
            alpha: self.alpha,
            unit: self.unit,
            exclude: self.exclude.clone(),
            preset: self.preset,
            model: self.model.unwrap_or(ModelKind::Pooled),
            equivalence: self.equivalence,
            subject_bootstrap: self.subject_bootstrap,
            max_dropped_frames: self.max_dropped_frames,
            exclude_dropped: self.exclude_dropped,
            max_dropped_share: self.max_dropped_share,
            criteria: self.screening.criteria(),
            keep_excluded: self.screening.keep_excluded,
        }
    }
}

/// The `analyze` command: [`run_report`], then a short summary on stderr.
pub fn run(args: AnalyzeArgs) -> Result<()> {
    if let (Some(ModelKind::Pooled), Some(m)) = (args.model, args.equivalence) {
        anyhow::bail!(
            "--equivalence {m} asks for the multilevel model's TOST, but --model pooled was \
             given; drop --model pooled or give --model multilevel"
        );
    }
    let args = args.options();
    let report = run_report(&args)?;
    for w in &report.warnings {
        eprintln!("warning: {w}");
    }
    let excluded = match report.excluded.len() {
        0 => String::new(),
        n => format!(", {n} excluded"),
    };
    if !report.sessions_by_mode.is_empty() {
        eprintln!("{}", report.sessions_line());
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_flags_defaults_are_the_options_defaults() {
        let cli = crate::cli::try_parse::<AnalyzeArgs>(&["analyze", "--out", "o", "logs"]).unwrap();
        let want = AnalyzeOptions::new(vec!["logs".into()], "o".into());
        assert_eq!(cli.options(), want);
    }

    #[test]
    fn choices_parse_by_name() {
        let argv = [
            "analyze",
            "--out",
            "o",
            "--sigmoid",
            "weibull",
            "--lapse",
            "free",
        ];
        let argv: Vec<&str> = argv
            .into_iter()
            .chain(["--test", "welch", "--unit", "cell", "x"])
            .collect();
        let cli = crate::cli::try_parse::<AnalyzeArgs>(&argv);
        let o = cli.unwrap().options();
        assert_eq!(
            (o.sigmoid, o.lapse, o.test, o.unit),
            (
                Sigmoid::Weibull,
                LapseMode::Free,
                TestKind::Welch,
                Unit::Cell
            )
        );
        let preset = crate::cli::try_parse::<AnalyzeArgs>(&[
            "analyze", "--out", "o", "--preset", "thesis", "x",
        ]);
        assert_eq!(preset.unwrap().options().preset, Some(Preset::Thesis));
        assert!(
            crate::cli::try_parse::<AnalyzeArgs>(&[
                "analyze",
                "--out",
                "o",
                "--sigmoid",
                "probit",
                "x"
            ])
            .is_err()
        );
    }

    #[test]
    fn exclusion_flags_map_and_bad_ones_are_named() {
        let cli = crate::cli::try_parse::<AnalyzeArgs>(&[
            "analyze",
            "--out",
            "o",
            "--min-catch-accuracy",
            "0.75",
            "--pixels-per-degree",
            "20,80",
            "--keep-excluded",
            "x",
        ])
        .unwrap()
        .options();
        assert_eq!(cli.criteria.min_catch_accuracy, Some(0.75));
        assert_eq!(cli.criteria.display.pixels_per_degree, Some([20.0, 80.0]));
        assert!(cli.keep_excluded);
        for (flag, value) in [
            ("--min-catch-accuracy", "1.5"),
            ("--pixels-per-degree", "80,20"),
            ("--refresh-hz", "60"),
            ("--max-fast-share", "-0.1"),
        ] {
            let e =
                crate::cli::try_parse::<AnalyzeArgs>(&["analyze", "--out", "o", flag, value, "x"])
                    .unwrap_err()
                    .to_string();
            assert!(e.contains(flag), "{flag}: {e}");
        }
    }

    #[test]
    fn the_options_the_thesis_preset_fixes_cannot_be_given_beside_it() {
        for extra in [
            ["--unit", "subject"],
            ["--test", "welch"],
            ["--alpha", "0.01"],
            ["--levels", "64"],
            ["--target", "0.8"],
        ] {
            let argv = [
                "analyze", "--preset", "thesis", extra[0], extra[1], "--out", "o", "in",
            ];
            assert!(
                crate::cli::try_parse::<AnalyzeArgs>(&argv).is_err(),
                "{extra:?}"
            );
        }
    }
}
