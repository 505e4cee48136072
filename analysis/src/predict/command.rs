//! `blurlab predict <stimulus set>`: the command line over [`super::stimuli::predict`],
//! [`super::output::write`] and [`super::calibrate`]; `blurlab predict validate modelfest DIR`
//! over [`super::validate`].

use super::calibrate::{Calibration, calibrate, cells, markdown};
use super::decision::DEFAULT_K;
use super::output::{Files, write};
use super::stage::Stage;
use super::stimuli::{PredictSettings, Prediction, predict, with_k};
use crate::data::Dataset;
use anyhow::{Result, bail};
use clap::{Args, Subcommand};
use experiment::Design;
use experiment::display::DisplaySpec;
use renderer::progress::terminal::{Look, Terminal};
use std::path::{Path, PathBuf};

/// `blurlab predict`: a stimulus set's prediction, or a validation subcommand.
#[derive(Args, Clone, Debug)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct PredictCli {
    #[command(subcommand)]
    pub command: Option<PredictCommand>,
    #[command(flatten)]
    pub args: Option<PredictArgs>,
}

#[derive(Subcommand, Clone, Debug)]
pub enum PredictCommand {
    /// Run the model on human detection data, fit its free parameters (k, the pooling
    /// exponents) and report the error per stimulus, per family, overall and leave-one-out.
    Validate {
        #[command(subcommand)]
        data: ValidateData,
    },
    /// Combine predictions of single frames spread over one video (each a `predicted.csv` of
    /// `blurlab predict`, or its folder) into the video's JNDs: d' pooled over the frames with
    /// the model's time exponent, and the most visible frame.
    Frames(FramesArgs),
    /// Show where the model sees one pair's difference, frame by frame: where the aperture
    /// lands, the luminance, clipping and difference there, and how the pooled difference
    /// splits over luminance and clipped pixels.
    Explain(ExplainArgs),
}

#[derive(Args, Clone, Debug)]
pub struct ExplainArgs {
    /// The stimulus set: its manifest file or the folder holding it.
    pub stimuli: PathBuf,
    /// The test stimulus's id.
    #[arg(long)]
    pub test: String,
    /// The reference stimulus's id.
    #[arg(long)]
    pub reference: String,
    /// A design whose `display` block to use [default: the thesis's display].
    #[arg(long)]
    pub design: Option<PathBuf>,
    /// Viewing distance in metres, over the design's or the default display.
    #[arg(long, value_parser = renderer::limits::real(0.0, 1000.0, true, "a viewing distance in metres"),
          allow_hyphen_values = true)]
    pub distance_m: Option<f64>,
    /// A browser session's log (`blurlab serve`): predict at that subject's own pixels per
    /// degree (its logged screen scale and viewing distance) instead of the design's display.
    #[arg(long, value_name = "LOG", conflicts_with = "distance_m")]
    pub viewer: Option<PathBuf>,
    /// Also write the table to this file (Markdown).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Explain one pair; returns the table.
pub fn explain(args: &ExplainArgs) -> Result<String> {
    let design = args.design.as_deref().map(Design::load).transpose()?;
    let display = display_spec(design.as_ref(), args.distance_m, args.viewer.as_deref())?;
    let table = super::explain::pair(&args.stimuli, &args.test, &args.reference, &display)?;
    if let Some(out) = &args.out {
        renderer::atomic::write_atomic(out, table.as_bytes())?;
    }
    Ok(table)
}

/// The design's display block (or the default display), at `--distance-m` if given, or at the
/// geometry the `--viewer` log holds.
fn display_spec(
    design: Option<&Design>,
    distance_m: Option<f64>,
    viewer: Option<&Path>,
) -> Result<DisplaySpec> {
    let mut d: DisplaySpec = design
        .and_then(|d| d.file.display.clone())
        .unwrap_or_default();
    if let Some(m) = distance_m {
        d.distance_m = m;
    }
    match viewer {
        Some(log) => super::viewer::display_for_session(log, &d),
        None => Ok(d),
    }
}

#[derive(Args, Clone, Debug)]
pub struct FramesArgs {
    /// The frames' predictions (predicted.csv files or the folders holding them).
    #[arg(required = true, num_args = 1..)]
    pub predictions: Vec<PathBuf>,
    /// Minkowski exponent over frames [default: the model's fitted time exponent].
    #[arg(long, default_value_t = super::pooling::FITTED.space, allow_hyphen_values = true,
          value_parser = renderer::limits::real(1.0, f64::INFINITY, false,
              "a Minkowski exponent over frames (inf: the most visible frame)"))]
    pub exponent: f64,
    /// Also write the table to this file (Markdown).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Combine single-frame predictions; returns the table.
pub fn combine_frames(args: &FramesArgs) -> Result<String> {
    let frames = super::frames::load_all(&args.predictions)?;
    let jnds = super::frames::combine(&frames, args.exponent)?;
    let table = super::frames::markdown(&frames, &jnds, args.exponent);
    if let Some(out) = &args.out {
        renderer::atomic::write_atomic(out, table.as_bytes())?;
    }
    Ok(table)
}

#[derive(Subcommand, Clone, Debug)]
pub enum ValidateData {
    /// ModelFest's 43 stimuli and 16 observers' thresholds (analysis/tests/data/modelfest).
    Modelfest(ModelfestArgs),
}

#[derive(Args, Clone, Debug)]
pub struct ModelfestArgs {
    /// The ModelFest folder (stimuli.json, thresholds.csv, stimuli/*.png).
    pub dir: PathBuf,
    /// Also write the report to this file (Markdown).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Hide the progress bar.
    #[arg(long)]
    pub no_progress: bool,
}

/// Validate against ModelFest; returns the report (its last line the RMS error).
pub fn validate_modelfest(args: &ModelfestArgs) -> Result<String> {
    let stimuli = super::modelfest::load(&args.dir)?;
    let bar = Terminal::new(Look::Steps, !args.no_progress);
    let r = super::validate::responses(
        &stimuli,
        &super::validate::grid(),
        &super::validate::shapes(),
        &bar,
    )?;
    let report = super::validate::markdown(&super::validate::validate(&stimuli, &r)?);
    if let Some(out) = &args.out {
        renderer::atomic::write_atomic(out, format!("{report}\n").as_bytes())?;
    }
    Ok(report)
}

/// Predict how visible each stimulus's noise is, from its display frames.
#[derive(Args, Clone, Debug)]
pub struct PredictArgs {
    /// The stimulus set: its manifest file or the folder holding it.
    pub stimuli: PathBuf,
    /// A design over the set: its trials' (test, reference) pairs and its `display` block are
    /// used [default: every test stimulus against its scene's reference, the thesis's display].
    #[arg(long)]
    pub design: Option<PathBuf>,
    /// Output folder [default: results/<job>/predict].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Sensitivity constant k (d' = k Q) [default: the fit to ModelFest].
    #[arg(long, default_value_t = DEFAULT_K, allow_hyphen_values = true)]
    pub sensitivity: f64,
    /// Viewing distance in metres, over the design's display block or the default display
    /// (e.g. 0.7, the distance of the manifest's FLIP measurement).
    #[arg(long, value_parser = renderer::limits::real(0.0, 1000.0, true, "a viewing distance in metres"),
          allow_hyphen_values = true)]
    pub distance_m: Option<f64>,
    /// A browser session's log (`blurlab serve`): predict at that subject's own pixels per
    /// degree (its logged screen scale and viewing distance) instead of the design's display.
    #[arg(long, value_name = "LOG", conflicts_with = "distance_m")]
    pub viewer: Option<PathBuf>,
    /// How the observer compares test and reference: `side-by-side` (how noisy each video
    /// looks, with masking and Weber-like discrimination) or `difference` (T - R at each
    /// place: an overlay or flicker comparison) [default: as the design's layout shows the
    /// pairs: side by side; docs/predict.md].
    #[arg(long, value_enum)]
    pub decision: Option<Decision>,
    /// Fit k to these sessions (folders or logs) by maximum likelihood, report the
    /// leave-one-condition-out error, and write the prediction with the fitted k.
    #[arg(long, num_args = 1..)]
    pub calibrate: Vec<PathBuf>,
    /// Hide the progress bar.
    #[arg(long)]
    pub no_progress: bool,
}

/// `--decision`: the command line's names of [`super::video::Comparison`].
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Decision {
    Difference,
    SideBySide,
}

impl From<Decision> for super::video::Comparison {
    fn from(d: Decision) -> Self {
        match d {
            Decision::Difference => Self::Difference,
            Decision::SideBySide => Self::SideBySide,
        }
    }
}

/// What the command produced.
pub struct Outcome {
    pub prediction: Prediction,
    pub files: Files,
    pub calibration: Option<Calibration>,
}

pub fn run(args: &PredictArgs) -> Result<Outcome> {
    if !(args.sensitivity.is_finite() && args.sensitivity > 0.0) {
        bail!(
            "--sensitivity is {}; expected a positive number",
            args.sensitivity
        );
    }
    let design = args.design.as_deref().map(Design::load).transpose()?;
    let settings = PredictSettings {
        display: display_spec(design.as_ref(), args.distance_m, args.viewer.as_deref())?,
        k: args.sensitivity,
        stage: match args.decision {
            Some(d) => Stage::given(d.into()),
            None => Stage::for_layout(design.as_ref().map(|d| d.file.layout)),
        },
    };
    let bar = Terminal::new(Look::Steps, !args.no_progress);
    let mut prediction = predict(&args.stimuli, design.as_ref(), &settings, &bar)?;
    let out = args.out.clone().unwrap_or_else(|| {
        PathBuf::from("results")
            .join(&prediction.job)
            .join("predict")
    });
    let mut calibration = None;
    if !args.calibrate.is_empty() {
        let ds = Dataset::read(&args.calibrate)?;
        let c = calibrate(cells(&prediction, &ds)?);
        std::fs::create_dir_all(&out)?;
        renderer::atomic::write_atomic(
            &out.join("calibration.md"),
            markdown(&c, args.sensitivity).as_bytes(),
        )?;
        renderer::atomic::write_atomic(
            &out.join("calibration.json"),
            serde_json::to_string_pretty(&c)?.as_bytes(),
        )?;
        prediction = with_k(&prediction, c.k);
        calibration = Some(c);
    }
    let files = write(&prediction, &out)?;
    Ok(Outcome {
        prediction,
        files,
        calibration,
    })
}
