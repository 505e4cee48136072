//! `blurlab plan --design D --observer O --subjects 4,8,12,16,24 --replications R`.

use super::duration::{SessionDuration, manifest_video_seconds, session};
use super::output::{Criteria, recommendation, write};
use super::replicate::ReplicationSettings;
use super::{Plan, PlanSettings, run as run_plan};
use crate::bootstrap::BootstrapSettings;
use crate::data::Grouping;
use crate::report::Settings;
use anyhow::{Result, bail};
use clap::Args;
use experiment::{Design, Observer};
use renderer::limits::real;
use renderer::progress::terminal::{Look, Terminal};
use std::path::PathBuf;

/// Longest time a duration flag takes (a typo guard): a day, in seconds.
const DAY: f64 = 86_400.0;

/// How many subjects a study needs: simulate it many times and analyse each simulation.
#[derive(Args, Clone, Debug)]
pub struct PlanArgs {
    /// The design file (blurlab-design/1).
    #[arg(long)]
    pub design: PathBuf,
    /// The observer: an observer file (blurlab-observer/1) or a predicted.csv.
    #[arg(long)]
    pub observer: PathBuf,
    /// Subject counts to try.
    #[arg(long, value_delimiter = ',', default_value = "4,8,12,16,24",
          value_parser = renderer::limits::parse_subjects, allow_hyphen_values = true)]
    pub subjects: Vec<usize>,
    /// Simulated studies per subject count.
    #[arg(long, default_value_t = 500, value_parser = renderer::limits::parse_replications,
          allow_hyphen_values = true)]
    pub replications: u64,
    /// A pooled JND's interval is narrow when upper / lower < this factor (in spp).
    #[arg(long, default_value_t = 2.0, value_parser = real(1.0, 1e6, true, "a ratio"),
          allow_hyphen_values = true)]
    pub factor: f64,
    /// Bootstrap resamples per pooled fit (39: the percentile interval of 39 resamples covers
    /// with probability exactly 0.95, docs/benchmarks/recovery.md).
    #[arg(long, default_value_t = 39, value_parser = renderer::limits::resamples(19),
          allow_hyphen_values = true)]
    pub resamples: usize,
    /// Probability a recommendation requires (of a narrow interval, of significance).
    #[arg(long, default_value_t = 0.8, value_parser = real(0.0, 1.0, true, "a probability"),
          allow_hyphen_values = true)]
    pub probability: f64,
    /// Differences in proportion correct below this do not drive the recommendation.
    #[arg(long, default_value_t = 0.05,
          value_parser = real(0.0, 1.0, false, "a difference in proportion correct"),
          allow_hyphen_values = true)]
    pub min_difference: f64,
    /// Fit a JND per condition too (not only per scene, point set and time filter).
    #[arg(long)]
    pub conditions: bool,
    /// Video length in seconds when the design's manifest is not rendered.
    #[arg(long, value_parser = real(0.0, DAY, true, "seconds"), allow_hyphen_values = true)]
    pub video_seconds: Option<f64>,
    /// Assumed time to answer a trial, seconds.
    #[arg(long, default_value_t = 2.0, value_parser = real(0.0, DAY, false, "seconds"),
          allow_hyphen_values = true)]
    pub response_seconds: f64,
    /// Assumed length of a break, seconds.
    #[arg(long, default_value_t = 60.0, value_parser = real(0.0, DAY, false, "seconds"),
          allow_hyphen_values = true)]
    pub break_seconds: f64,
    /// Output folder [default: results/<design name>/plan].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Hide the progress bar.
    #[arg(long)]
    pub no_progress: bool,
    /// Also plan the multilevel model's equivalence tests (TOST) of point sets and time
    /// filters at this margin in ln JND (0.2: a ratio within 0.82-1.22): their power and the
    /// subjects needed (`equivalence.json`, a section of plan.md).
    #[arg(long, value_parser = real(0.0, 5.0, true, "a margin in ln JND"),
          allow_hyphen_values = true)]
    pub equivalence: Option<f64>,
    /// Subject counts for the equivalence tests [default: --subjects]. The TOST needs far more
    /// subjects than the pooled intervals (about 100 at margin 0.2 on the thesis design), and
    /// these replications skip the pooled fits, so they can search higher counts cheaply.
    #[arg(long, value_delimiter = ',', value_parser = renderer::limits::parse_subjects,
          allow_hyphen_values = true, requires = "equivalence")]
    pub equivalence_subjects: Option<Vec<usize>>,
}

/// What the command produced.
pub struct Outcome {
    pub plan: Plan,
    pub duration: Option<SessionDuration>,
    pub recommendation: String,
    pub files: Vec<PathBuf>,
}

pub fn run(args: &PlanArgs) -> Result<Outcome> {
    if args.factor.is_nan() || args.factor <= 1.0 {
        bail!("--factor is {}; expected a ratio > 1", args.factor);
    }
    if args.resamples < 19 {
        bail!(
            "--resamples is {}; expected at least 19 (a 95% percentile interval needs them)",
            args.resamples
        );
    }
    let design = Design::load(&args.design)?;
    let observer = Observer::load(&args.observer)?;
    let defaults = Settings::default();
    let mut groupings = vec![Grouping::Scene, Grouping::PointSet, Grouping::TimeFilter];
    if args.conditions {
        groupings.push(Grouping::Condition);
    }
    let settings = PlanSettings {
        subjects: args.subjects.clone(),
        replications: args.replications,
        factor: args.factor,
        replication: ReplicationSettings {
            analysis: Settings {
                bootstrap: BootstrapSettings {
                    resamples: args.resamples,
                    seed: 0,
                    ..defaults.bootstrap
                },
                ..defaults
            },
            groupings,
        },
        keep_replications: false,
    };
    let bar = Terminal::new(Look::Steps, !args.no_progress);
    let plan = run_plan(&design, &observer, &settings, &bar)?;
    let duration = args
        .video_seconds
        .or_else(|| manifest_video_seconds(&design))
        .map(|v| session(&design, v, args.response_seconds, args.break_seconds));
    let mut text = recommendation(
        &plan,
        Criteria {
            probability: args.probability,
            min_difference: args.min_difference,
        },
    );
    let equivalence = args
        .equivalence
        .map(|m| {
            let rows = super::equivalence::run(
                &design,
                &observer,
                args.equivalence_subjects.as_ref().unwrap_or(&args.subjects),
                args.replications,
                m,
                &bar,
            )?;
            text.push_str("\n\n");
            text.push_str(&super::equivalence::markdown(&rows, m, args.probability));
            anyhow::Ok(rows)
        })
        .transpose()?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("results").join(design.name()).join("plan"));
    let mut files = write(&plan, duration.as_ref(), &text, &out)?;
    if let Some(rows) = equivalence {
        let path = out.join("equivalence.json");
        renderer::atomic::write_atomic(&path, serde_json::to_string_pretty(&rows)?.as_bytes())?;
        files.push(path);
    }
    Ok(Outcome {
        plan,
        duration,
        recommendation: text,
        files,
    })
}
