//! The command lines `run` and `simulate`, as clap `Args` the umbrella binary embeds
//! (`blurlab run ...`, `blurlab simulate ...`) and the crate's own `experiment` binary reuses.

use crate::design::Design;
use crate::observer::Observer;
use crate::paths::sessions_dir;
use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

/// Run a subject's session in a full-screen window (continues an interrupted one).
#[derive(Args, Clone, Debug)]
pub struct RunArgs {
    /// The design file (blurlab-design/1).
    #[arg(long)]
    pub design: PathBuf,
    /// The subject's id (letters, digits, - and _); names the log file.
    #[arg(long)]
    pub subject: String,
    /// Folder of session logs [default: results/<design name>/sessions].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// A window of this size in logical pixels (e.g. 1280x720) instead of full screen. For
    /// trying out a design only: subjects should always see the full-screen window.
    #[arg(long, value_parser = parse_size)]
    pub windowed: Option<(u32, u32)>,
    /// Pace frames with timers instead of waiting for the display's vertical sync (for displays
    /// without vsync, such as Xvfb). Real sessions should keep vsync.
    #[arg(long)]
    pub no_vsync: bool,
    /// Skip the content-hash check of preflight (sizes and frame counts are still checked).
    #[arg(long)]
    pub skip_hash_check: bool,
}

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

impl RunArgs {
    /// The library's options for these arguments.
    #[cfg(feature = "gui")]
    pub fn launch_options(&self) -> crate::app::LaunchOptions {
        crate::app::LaunchOptions {
            design: self.design.clone(),
            subject: self.subject.clone(),
            out: self.out.clone(),
            windowed: self.windowed,
            pacing: if self.no_vsync {
                crate::app::Pacing::Timer
            } else {
                crate::app::Pacing::Vsync
            },
            check_hashes: !self.skip_hash_check,
        }
    }
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once('x')
        .ok_or_else(|| format!("{s:?}: expected WIDTHxHEIGHT, e.g. 1280x720"))?;
    let n = |v: &str| {
        v.parse::<u32>()
            .ok()
            .filter(|&x| x > 0)
            .ok_or_else(|| format!("{s:?}: expected positive whole pixel counts"))
    };
    Ok((n(w)?, n(h)?))
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
    let paths = crate::simulate::simulate(&design, &observer, args.subjects, &out)?;
    // What ran, read back from the logs: an adaptive procedure's stop rule can end a track
    // before its planned trials (issue 42: 96 were announced where 8 ran).
    let ran = paths
        .iter()
        .map(|p| crate::log::SessionLog::read(p).map(|l| l.main_trials().count()))
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

/// `run`: a subject's session in the window.
#[cfg(feature = "gui")]
pub fn run(args: RunArgs) -> Result<()> {
    use renderer::progress::terminal::{Look, Terminal};
    let prepared = crate::app::prepare(
        &args.launch_options(),
        &Terminal::new(Look::Preflight, true),
    )?;
    // Before the window covers the screen.
    for w in prepared.warnings() {
        eprintln!("warning: {w}");
    }
    eprintln!("{}", crate::app::show(prepared)?);
    Ok(())
}

/// `run` without the window: explain how to get it.
#[cfg(not(feature = "gui"))]
pub fn run(args: RunArgs) -> Result<()> {
    let _ = args;
    anyhow::bail!(
        "this build has no session window (it was built without the `gui` feature). Build with \
         it: `cargo build --release` (the feature is on by default) or \
         `cargo build --release --features gui`"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn window_sizes_parse_or_explain() {
        assert_eq!(parse_size("1280x720"), Ok((1280, 720)));
        assert!(parse_size("1280").unwrap_err().contains("WIDTHxHEIGHT"));
        assert!(parse_size("0x10").is_err());
    }

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
