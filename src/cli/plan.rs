//! `blurlab plan --design D --observer O --subjects 4,8,12,16,24 --replications R`: the flags
//! of `analysis::plan::study::PlanOptions`, whose defaults they repeat (a test checks that
//! they agree).

use crate::cli::progress::{Look, Terminal};
use analysis::plan::study::{PlanOptions, plan_study};
use anyhow::Result;
use clap::Args;
use renderer::limits::real;
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

impl PlanArgs {
    /// The options these flags ask for.
    pub fn options(&self) -> PlanOptions {
        PlanOptions {
            design: self.design.clone(),
            observer: self.observer.clone(),
            subjects: self.subjects.clone(),
            replications: self.replications,
            factor: self.factor,
            resamples: self.resamples,
            probability: self.probability,
            min_difference: self.min_difference,
            conditions: self.conditions,
            video_seconds: self.video_seconds,
            response_seconds: self.response_seconds,
            break_seconds: self.break_seconds,
            out: self.out.clone(),
            equivalence: self.equivalence,
            equivalence_subjects: self.equivalence_subjects.clone(),
        }
    }
}

/// `blurlab plan`: plan the study, print plan.md and say where it is.
pub fn run(args: &PlanArgs) -> Result<()> {
    let bar = Terminal::new(Look::Steps, !args.no_progress);
    let out = plan_study(&args.options(), &bar)?;
    let md = out.files.first().expect("plan.md is written first");
    println!("{}", std::fs::read_to_string(md)?);
    println!("plan: {}", md.display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_flags_defaults_are_the_options_defaults() {
        let cli = crate::cli::try_parse::<PlanArgs>(&["plan", "--design", "d", "--observer", "o"])
            .unwrap();
        let want = PlanOptions::new("d".into(), "o".into());
        assert_eq!(cli.options(), want);
    }
}
