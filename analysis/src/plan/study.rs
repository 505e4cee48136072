//! What `blurlab plan` is asked to do: [`PlanOptions`], every field with its default written
//! out (the command's flags map onto it), and [`plan_study`]: simulate, analyse, recommend,
//! write plan.md and its tables and figures.

use super::duration::{SessionDuration, manifest_video_seconds, session};
use super::output::{Criteria, recommendation, write};
use super::replicate::ReplicationSettings;
use super::{Plan, PlanSettings, run as run_plan};
use crate::bootstrap::BootstrapSettings;
use crate::data::Grouping;
use crate::report::Settings;
use anyhow::{Result, bail};
use experiment::{Design, Observer};
use renderer::progress::Progress;
use std::path::PathBuf;

/// A study to plan (the flags' help of `blurlab plan` says what each field means).
#[derive(Clone, Debug, PartialEq)]
pub struct PlanOptions {
    /// The design file (blurlab-design/1).
    pub design: PathBuf,
    /// An observer file (blurlab-observer/1) or a predicted.csv.
    pub observer: PathBuf,
    /// Subject counts to try.
    pub subjects: Vec<usize>,
    /// Simulated studies per subject count.
    pub replications: u64,
    /// A pooled JND's interval is narrow when upper / lower < this factor (in spp).
    pub factor: f64,
    /// Bootstrap resamples per pooled fit (at least 19).
    pub resamples: usize,
    /// Probability a recommendation requires.
    pub probability: f64,
    /// Differences in proportion correct below this do not drive the recommendation.
    pub min_difference: f64,
    /// Fit a JND per condition too.
    pub conditions: bool,
    /// Video length in seconds when the design's manifest is not rendered.
    pub video_seconds: Option<f64>,
    /// Assumed time to answer a trial, seconds.
    pub response_seconds: f64,
    /// Assumed length of a break, seconds.
    pub break_seconds: f64,
    /// Output folder; `None`: results/<design name>/plan.
    pub out: Option<PathBuf>,
    /// Also plan the multilevel model's equivalence tests at this margin in ln JND.
    pub equivalence: Option<f64>,
    /// Subject counts for the equivalence tests; `None`: `subjects`.
    pub equivalence_subjects: Option<Vec<usize>>,
}

impl PlanOptions {
    /// The defaults for a design and an observer.
    pub fn new(design: PathBuf, observer: PathBuf) -> Self {
        Self {
            design,
            observer,
            subjects: vec![4, 8, 12, 16, 24],
            replications: 500,
            factor: 2.0,
            // The percentile interval of 39 resamples covers with probability exactly 0.95
            // (docs/benchmarks/recovery.md).
            resamples: 39,
            probability: 0.8,
            min_difference: 0.05,
            conditions: false,
            video_seconds: None,
            response_seconds: 2.0,
            break_seconds: 60.0,
            out: None,
            equivalence: None,
            equivalence_subjects: None,
        }
    }
}

/// What the command produced.
pub struct Outcome {
    pub plan: Plan,
    pub duration: Option<SessionDuration>,
    pub recommendation: String,
    pub files: Vec<PathBuf>,
}

/// Plan the study: replications through simulate -> analyze, the recommendation, the files.
pub fn plan_study(args: &PlanOptions, progress: &dyn Progress) -> Result<Outcome> {
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
    let plan = run_plan(&design, &observer, &settings, progress)?;
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
                progress,
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
