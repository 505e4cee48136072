//! `blurlab render report stimuli/<job>`: speed against error tables and plots.

use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

/// Tabulate and plot error against spp and against render time for a rendered job.
#[derive(Debug, Args)]
pub struct ReportArgs {
    /// The rendered job's folder (holding manifest.json).
    pub stimuli: PathBuf,
    /// Where to write convergence.csv, convergence_slopes.csv and the plots
    /// [default: <stimuli>/report].
    #[arg(long)]
    pub out: Option<PathBuf>,
}

pub fn run(args: ReportArgs) -> Result<()> {
    let out = args.out.unwrap_or_else(|| args.stimuli.join("report"));
    let files = renderer::convergence::write_report(&args.stimuli, &out)?;
    println!("wrote {}", files.csv.display());
    println!("wrote {}", files.slopes_csv.display());
    for f in &files.figures {
        println!("wrote {}", f.display());
    }
    Ok(())
}
