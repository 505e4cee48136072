//! `blurlab simulate`: simulated subjects through a design (`experiment::simulate`).

use anyhow::Result;
use clap::Args;
use experiment::paths::sessions_dir;
use experiment::{Design, Observer};
use std::path::PathBuf;

/// Run simulated subjects through a design (the same trial lists and log format).
#[derive(Args, Clone, Debug)]
pub struct SimulateArgs {
    /// The design file (blurlab-design/1).
    #[arg(long)]
    pub design: PathBuf,
    /// The observer: a file of typed-in thresholds (blurlab-observer/1) or a prediction from
    /// the stimuli (`blurlab predict`'s predicted.csv, blurlab-predicted/1).
    #[arg(long)]
    pub observer: PathBuf,
    /// Number of subjects (named s01, s02, ...).
    #[arg(long, default_value_t = 12, value_parser = renderer::limits::parse_subjects,
          allow_hyphen_values = true)]
    pub subjects: usize,
    /// Folder of session logs [default: results/<design name>/sessions]; simulated logs of the
    /// same subject names are replaced.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// "96 trials" when every subject ran the planned main trials, else the range that ran.
fn trials_ran(planned: usize, ran: &[usize]) -> String {
    let lo = ran.iter().copied().min().unwrap_or(0);
    let hi = ran.iter().copied().max().unwrap_or(0);
    match (lo == planned, hi == planned, lo == hi) {
        (true, true, _) => format!("{planned} trials"),
        (_, _, true) => format!("{lo} main trials run (of {planned} planned: the stop rule)"),
        _ => format!("{lo} to {hi} main trials run (of {planned} planned: the stop rule)"),
    }
}

/// `simulate`: write one log per simulated subject and say where.
pub fn simulate(args: SimulateArgs) -> Result<()> {
    let design = Design::load(&args.design)?;
    let observer = Observer::load(&args.observer)?;
    let out = sessions_dir(args.out.as_deref(), &design);
    let paths = experiment::simulate::simulate(&design, &observer, args.subjects, &out)?;
    // What ran, read back from the logs: an adaptive procedure's stop rule can end a track
    // before its planned trials (issue 42: 96 were announced where 8 ran).
    let ran = paths
        .iter()
        .map(|p| experiment::log::SessionLog::read(p).map(|l| l.main_trials().count()))
        .collect::<Result<Vec<_>>>()?;
    eprintln!(
        "simulated {} subjects x {} of design {:?} with observer {:?} into {}",
        paths.len(),
        trials_ran(design.main_trial_count() as usize, &ran),
        design.name(),
        observer.file.name,
        out.display()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simulate_says_what_ran_not_what_was_planned() {
        assert_eq!(trials_ran(96, &[96, 96]), "96 trials");
        assert_eq!(
            trials_ran(96, &[8, 8]),
            "8 main trials run (of 96 planned: the stop rule)"
        );
        assert_eq!(
            trials_ran(96, &[20, 96]),
            "20 to 96 main trials run (of 96 planned: the stop rule)"
        );
    }
}
