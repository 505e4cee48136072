//! Write a simulated thesis-size study as `blurlab-session/1` logs, for trying and timing
//! `analyze` without a real experiment:
//!
//! ```text
//! cargo run -p analysis --release --example simulate_study -- <sessions dir> [seed]
//! cargo run --release -- analyze <sessions dir> --out <report dir>
//! ```
//!
//! The design is [`StudySpec::thesis`]: 12 subjects x 2 scenes (true JND 40 and 100 spp) x
//! 3 point sets x 8 levels x 4 repeats, logistic observers with slope 1.5 / ln spp.

use analysis::simulate::StudySpec;
use anyhow::{Context, Result};
use std::path::PathBuf;

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let dir = PathBuf::from(
        args.next()
            .context("usage: simulate_study <sessions dir> [seed]")?,
    );
    let mut spec = StudySpec::thesis();
    if let Some(seed) = args.next() {
        spec.seed = seed
            .parse()
            .with_context(|| format!("seed {seed:?}: expected an unsigned integer"))?;
    }
    let files = spec.write_logs(&dir, "simulated-thesis")?;
    eprintln!("wrote {} session logs to {}", files.len(), dir.display());
    Ok(())
}
