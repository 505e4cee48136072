//! What `blurlab predict` is asked to do, as plain options with their defaults written out (the
//! command's flags map onto them): a stimulus set's prediction ([`PredictOptions`],
//! [`run_predict`]: [`super::stimuli::predict`], [`super::calibrate`], [`super::output::write`]),
//! one pair explained ([`ExplainOptions`]), single-frame predictions combined
//! ([`FramesOptions`]), and the validation against ModelFest ([`validate_modelfest`]).

use super::calibrate::{Calibration, calibrate, cells, markdown};
use super::output::{Files, write};
use super::stage_choice::StageChoice;
use super::stimuli::{PredictSettings, Prediction, predict, with_k};
use crate::data::Dataset;
use crate::observer::datasets::{meese, modelfest};
use crate::observer::model::decision_stage::DecisionStage;
use crate::observer::model::pooling::FITTED;
use crate::observer::model::proportion_correct::DEFAULT_K;
use anyhow::{Result, bail};
use experiment::Design;
use experiment::display::DisplaySpec;
use renderer::progress::Progress;
use std::path::{Path, PathBuf};

/// One pair explained, frame by frame (`blurlab predict explain`).
#[derive(Clone, Debug, PartialEq)]
pub struct ExplainOptions {
    /// The stimulus set: its manifest file or the folder holding it.
    pub stimuli: PathBuf,
    /// The test stimulus's id.
    pub test: String,
    /// The reference stimulus's id.
    pub reference: String,
    /// A design whose `display` block to use; `None`: the thesis's display.
    pub design: Option<PathBuf>,
    /// Viewing distance in metres, over the design's or the default display.
    pub distance_m: Option<f64>,
    /// A browser session's log: the display at that subject's own pixels per degree.
    pub viewer: Option<PathBuf>,
    /// Also write the table to this file (Markdown).
    pub out: Option<PathBuf>,
}

/// Explain one pair; returns the table.
pub fn explain(args: &ExplainOptions) -> Result<String> {
    let design = args.design.as_deref().map(Design::load).transpose()?;
    let display = display_spec(design.as_ref(), args.distance_m, args.viewer.as_deref())?;
    let table = super::explain::pair(&args.stimuli, &args.test, &args.reference, &display)?;
    if let Some(out) = &args.out {
        renderer::atomic::write_atomic(out, table.as_bytes())?;
    }
    Ok(table)
}

/// The design's display block (or the default display), at `distance_m` if given, or at the
/// geometry the `viewer` log holds.
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

/// Single-frame predictions combined into a video's JNDs (`blurlab predict frames`).
#[derive(Clone, Debug, PartialEq)]
pub struct FramesOptions {
    /// The frames' predictions (predicted.csv files or the folders holding them).
    pub predictions: Vec<PathBuf>,
    /// Minkowski exponent over frames (infinity: the most visible frame).
    pub exponent: f64,
    /// Also write the table to this file (Markdown).
    pub out: Option<PathBuf>,
}

impl FramesOptions {
    /// The model's fitted time exponent over these predictions.
    pub fn new(predictions: Vec<PathBuf>) -> Self {
        Self {
            predictions,
            exponent: FITTED.space,
            out: None,
        }
    }
}

/// Combine single-frame predictions; returns the table.
pub fn combine_frames(args: &FramesOptions) -> Result<String> {
    let frames = super::frames::load_all(&args.predictions)?;
    let jnds = super::frames::combine(&frames, args.exponent)?;
    let table = super::frames::markdown(&frames, &jnds, args.exponent);
    if let Some(out) = &args.out {
        renderer::atomic::write_atomic(out, table.as_bytes())?;
    }
    Ok(table)
}

/// Validate against ModelFest (the folder `dir`: stimuli.json, thresholds.csv, stimuli/*.png);
/// returns the report (its last line the RMS error), also written to `out` if given.
pub fn validate_modelfest(
    dir: &Path,
    out: Option<&Path>,
    progress: &dyn Progress,
) -> Result<String> {
    let stimuli = modelfest::load(dir)?;
    let r = modelfest::fit::responses(
        &stimuli,
        &modelfest::fit::grid(),
        &modelfest::fit::shapes(),
        progress,
    )?;
    let report = modelfest::fit::markdown(&modelfest::fit::validate(&stimuli, &r)?);
    if let Some(out) = out {
        renderer::atomic::write_atomic(out, format!("{report}\n").as_bytes())?;
    }
    Ok(report)
}

/// Validate the decision stages against Meese et al. 2007's cross-orientation masking (the
/// folder `dir`: thresholds.csv), the side-by-side stage's cross-orientation weight fitted over
/// `cross_weights`; returns the report, also written to `out` if given.
pub fn validate_meese(
    dir: &Path,
    cross_weights: &[f64],
    out: Option<&Path>,
    progress: &dyn Progress,
) -> Result<String> {
    let series = meese::load(dir)?;
    let report = meese::fit::validate(&series, cross_weights, progress)?;
    if let Some(out) = out {
        renderer::atomic::write_atomic(out, format!("{report}\n").as_bytes())?;
    }
    Ok(report)
}

/// A stimulus set's prediction (`blurlab predict SET`).
#[derive(Clone, Debug, PartialEq)]
pub struct PredictOptions {
    /// The stimulus set: its manifest file or the folder holding it.
    pub stimuli: PathBuf,
    /// A design over the set: its trials' (test, reference) pairs and its `display` block;
    /// `None`: every test stimulus against its scene's reference, the thesis's display.
    pub design: Option<PathBuf>,
    /// Output folder; `None`: results/<job>/predict.
    pub out: Option<PathBuf>,
    /// Sensitivity constant k (d' = k Q).
    pub sensitivity: f64,
    /// Viewing distance in metres, over the design's display block or the default display.
    pub distance_m: Option<f64>,
    /// A browser session's log: the display at that subject's own pixels per degree.
    pub viewer: Option<PathBuf>,
    /// How the observer compares test and reference; `None`: as the design's layout shows the
    /// pairs ([`StageChoice::for_layout`]).
    pub decision: Option<DecisionStage>,
    /// Fit k to these sessions (folders or logs) and write the prediction with the fitted k.
    pub calibrate: Vec<PathBuf>,
}

impl PredictOptions {
    /// The defaults (k fitted to ModelFest, the design's display and stage) for a set.
    pub fn new(stimuli: PathBuf) -> Self {
        Self {
            stimuli,
            design: None,
            out: None,
            sensitivity: DEFAULT_K,
            distance_m: None,
            viewer: None,
            decision: None,
            calibrate: Vec::new(),
        }
    }
}

/// What a prediction produced.
pub struct Outcome {
    pub prediction: Prediction,
    pub files: Files,
    pub calibration: Option<Calibration>,
}

/// Predict a stimulus set, calibrate k if asked, write the files.
pub fn run_predict(args: &PredictOptions, progress: &dyn Progress) -> Result<Outcome> {
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
        decision: match args.decision {
            Some(d) => StageChoice::given(d),
            None => StageChoice::for_layout(design.as_ref().map(|d| d.file.layout)),
        },
    };
    let mut prediction = predict(&args.stimuli, design.as_ref(), &settings, progress)?;
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
