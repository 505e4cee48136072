//! `blurlab run`: a subject's session in the window (`experiment::app`).

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

impl RunArgs {
    /// The library's options for these arguments.
    #[cfg(feature = "gui")]
    pub fn launch_options(&self) -> experiment::app::LaunchOptions {
        experiment::app::LaunchOptions {
            design: self.design.clone(),
            subject: self.subject.clone(),
            out: self.out.clone(),
            windowed: self.windowed,
            pacing: if self.no_vsync {
                experiment::app::Pacing::Timer
            } else {
                experiment::app::Pacing::Vsync
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

/// `run`: a subject's session in the window.
#[cfg(feature = "gui")]
pub fn run(args: RunArgs) -> Result<()> {
    use crate::cli::progress::{Look, Terminal};
    let prepared = experiment::app::prepare(
        &args.launch_options(),
        &Terminal::new(Look::Preflight, true),
    )?;
    // Before the window covers the screen.
    for w in prepared.warnings() {
        eprintln!("warning: {w}");
    }
    eprintln!("{}", experiment::app::show(prepared)?);
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
}
