//! `blurlab render pointsets`: look at a point set the way thesis Figure 4 does (its 2D
//! projections) and measure it (`renderer::pointset_figure`).

use anyhow::{Result, bail};
use clap::Args;
use renderer::pointset_figure::{make, measure, plot};
use renderer::sampling::pointset;
use std::path::PathBuf;

/// Print a point set's discrepancy and spacing; optionally plot its (u,v), (u,t), (v,t)
/// projections (thesis Figure 4).
#[derive(Debug, Args)]
pub struct PointsetsArgs {
    /// Point set (random, stratified, hammersley, poisson, sobol, halton), or `all` for a table
    /// of every set.
    #[arg(long, default_value = "all")]
    pub set: String,
    /// Number of points (samples per pixel).
    #[arg(long, default_value_t = 125)]
    pub n: u32,
    /// Seed of the set; the same seed gives the same points.
    #[arg(long, default_value_t = 1, value_parser = renderer::limits::parse_seed,
          allow_hyphen_values = true)]
    pub seed: u64,
    /// Make a product set of n/K positions x K times (scene setting `density: {"temporal": K}`).
    #[arg(long, value_name = "K")]
    pub temporal: Option<u32>,
    /// Draw the projections to this file (.svg or .png); needs a single --set.
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}

pub fn run(args: PointsetsArgs) -> Result<()> {
    let names: Vec<&str> = if args.set == "all" {
        pointset::ALL.iter().map(|s| s.name()).collect()
    } else {
        vec![args.set.as_str()]
    };
    if args.plot.is_some() && names.len() != 1 {
        bail!("--plot draws one set; name it with --set");
    }
    for name in names {
        let points = make(name, args.n, args.seed, args.temporal)?;
        let stats = measure(name, &points);
        println!("{stats}");
        if let Some(path) = &args.plot {
            plot(&points, &stats, path)?;
            println!("wrote {}", path.display());
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plot_needs_one_named_set() {
        let a = PointsetsArgs {
            set: "all".into(),
            n: 8,
            seed: 1,
            temporal: None,
            plot: Some("x.svg".into()),
        };
        assert!(run(a).unwrap_err().to_string().contains("--set"));
    }
}
