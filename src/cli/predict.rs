//! `blurlab predict <stimulus set>`, `predict validate modelfest|meese2007 DIR`, `predict frames`,
//! `predict explain`: the flags of `analysis::predict::run`, whose defaults they repeat (a
//! test checks that they agree), and what each prints.

use super::named::named;
use crate::cli::progress::{Look, Terminal};
use analysis::observer::datasets::meese::fit::CROSS_WEIGHTS;
use analysis::observer::model::decision_stage::DecisionStage;
use analysis::observer::model::pooling::FITTED;
use analysis::observer::model::proportion_correct::DEFAULT_K;
use analysis::predict::run::{
    ExplainOptions, FramesOptions, PredictOptions, combine_frames, explain, run_predict,
    validate_meese, validate_modelfest,
};
use anyhow::Result;
use clap::{Args, Subcommand};
use std::path::PathBuf;

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

#[derive(Args, Clone, Debug)]
pub struct FramesArgs {
    /// The frames' predictions (predicted.csv files or the folders holding them).
    #[arg(required = true, num_args = 1..)]
    pub predictions: Vec<PathBuf>,
    /// Minkowski exponent over frames [default: the model's fitted time exponent].
    #[arg(long, default_value_t = FITTED.space, allow_hyphen_values = true,
          value_parser = renderer::limits::real(1.0, f64::INFINITY, false,
              "a Minkowski exponent over frames (inf: the most visible frame)"))]
    pub exponent: f64,
    /// Also write the table to this file (Markdown).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

#[derive(Subcommand, Clone, Debug)]
pub enum ValidateData {
    /// ModelFest's 43 stimuli and 16 observers' thresholds (analysis/tests/data/modelfest).
    Modelfest(ModelfestArgs),
    /// Meese et al. 2007: a grating's detection threshold under an orthogonal mask, two
    /// observers at 1 and 7 c/deg (analysis/tests/data/meese2007): how much each decision
    /// stage masks across orientations, as errors of the threshold elevations in dB.
    Meese2007(MeeseArgs),
}

#[derive(Args, Clone, Debug)]
pub struct MeeseArgs {
    /// The data set's folder (thresholds.csv), as analysis/tests/data/meese2007.
    pub dir: PathBuf,
    /// The cross-orientation weights w searched for the side-by-side stage (comma-separated,
    /// each in [0, 1]).
    #[arg(long, value_delimiter = ',', default_values_t = CROSS_WEIGHTS,
          value_parser = renderer::limits::real(0.0, 1.0, false, "a cross-orientation weight in [0, 1]"))]
    pub cross_weights: Vec<f64>,
    /// Also write the report to this file (Markdown).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Hide the progress bar.
    #[arg(long)]
    pub no_progress: bool,
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
    #[arg(long, value_parser = named::<DecisionStage>())]
    pub decision: Option<DecisionStage>,
    /// Fit k to these sessions (folders or logs) by maximum likelihood, report the
    /// leave-one-condition-out error, and write the prediction with the fitted k.
    #[arg(long, num_args = 1..)]
    pub calibrate: Vec<PathBuf>,
    /// Hide the progress bar.
    #[arg(long)]
    pub no_progress: bool,
}

impl PredictArgs {
    /// The options these flags ask for.
    pub fn options(&self) -> PredictOptions {
        PredictOptions {
            stimuli: self.stimuli.clone(),
            design: self.design.clone(),
            out: self.out.clone(),
            sensitivity: self.sensitivity,
            distance_m: self.distance_m,
            viewer: self.viewer.clone(),
            decision: self.decision,
            calibrate: self.calibrate.clone(),
        }
    }
}

impl ExplainArgs {
    /// The options these flags ask for.
    pub fn options(&self) -> ExplainOptions {
        ExplainOptions {
            stimuli: self.stimuli.clone(),
            test: self.test.clone(),
            reference: self.reference.clone(),
            design: self.design.clone(),
            distance_m: self.distance_m,
            viewer: self.viewer.clone(),
            out: self.out.clone(),
        }
    }
}

impl FramesArgs {
    /// The options these flags ask for.
    pub fn options(&self) -> FramesOptions {
        FramesOptions {
            predictions: self.predictions.clone(),
            exponent: self.exponent,
            out: self.out.clone(),
        }
    }
}

/// `blurlab predict`: run the subcommand or predict the set, and print the result.
pub fn run(cli: &PredictCli) -> Result<()> {
    let args = match (&cli.command, &cli.args) {
        (Some(PredictCommand::Validate { data }), _) => {
            let report = match data {
                ValidateData::Modelfest(m) => {
                    let bar = Terminal::new(Look::Steps, !m.no_progress);
                    validate_modelfest(&m.dir, m.out.as_deref(), &bar)?
                }
                ValidateData::Meese2007(m) => {
                    let bar = Terminal::new(Look::Steps, !m.no_progress);
                    validate_meese(&m.dir, &m.cross_weights, m.out.as_deref(), &bar)?
                }
            };
            println!("{report}");
            return Ok(());
        }
        (Some(PredictCommand::Frames(f)), _) => {
            println!("{}", combine_frames(&f.options())?);
            return Ok(());
        }
        (Some(PredictCommand::Explain(e)), _) => {
            println!("{}", explain(&e.options())?);
            return Ok(());
        }
        (None, Some(args)) => args,
        (None, None) => anyhow::bail!("blurlab predict: give a stimulus set or a subcommand"),
    };
    let bar = Terminal::new(Look::Steps, !args.no_progress);
    let out = run_predict(&args.options(), &bar)?;
    if let Some(c) = &out.calibration {
        println!("calibrated sensitivity constant k = {:.4}", c.k);
    }
    println!("{}", analysis::predict::output::jnd_table(&out.prediction));
    println!("prediction: {}", out.files.predicted_csv.display());
    println!("report:     {}", out.files.markdown.display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(argv: &[&str]) -> PredictCli {
        crate::cli::try_parse(&[&["predict"][..], argv].concat()).unwrap()
    }

    #[test]
    fn the_flags_defaults_are_the_options_defaults() {
        let set = parse(&["stimuli/demo"]).args.unwrap();
        assert_eq!(set.options(), PredictOptions::new("stimuli/demo".into()));
        let Some(PredictCommand::Frames(f)) = parse(&["frames", "a.csv"]).command else {
            panic!("frames parses as the subcommand");
        };
        assert_eq!(f.options(), FramesOptions::new(vec!["a.csv".into()]));
        let set = parse(&["s", "--decision", "side-by-side"]).args.unwrap();
        assert_eq!(set.options().decision, Some(DecisionStage::SideBySide));
        let wrong = crate::cli::try_parse::<PredictCli>(&["predict", "s", "--decision", "overlay"]);
        let e = wrong.expect_err("an unknown stage is refused").to_string();
        assert!(
            e.contains("difference") && e.contains("side-by-side"),
            "{e}"
        );
    }
}
