//! `blurlab render assets`: regenerate the procedural models and environment maps under `scenes/`.

use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

/// Write the stand-ins scenes/thesis/models/B-727-200.obj and scenes/thesis/data/CedarCity.hdr
/// from the procedural generators.
#[derive(Debug, Args)]
pub struct AssetsArgs {
    /// The scenes folder.
    #[arg(long, default_value = "scenes")]
    pub scenes: PathBuf,
}

pub fn run(args: AssetsArgs) -> Result<()> {
    for p in renderer::procedural::write_assets(&args.scenes)? {
        println!("wrote {}", p.display());
    }
    Ok(())
}
