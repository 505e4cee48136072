//! `blurlab render convert IN OUT`: a scene or job from one format into another, by extension
//! (`.json` <-> `.scene`, `.json` <-> `.job`); see `renderer::convert`.

use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

/// Convert a scene (JSON <-> thesis block text `.scene`) or a job (JSON <-> thesis seven-line
/// text `.job`) without loss; the formats follow the file extensions.
#[derive(Debug, Args)]
pub struct ConvertArgs {
    /// The file to read: .json, .scene or .job.
    pub input: PathBuf,
    /// The file to write (atomically): .json, .scene or .job.
    pub output: PathBuf,
}

pub fn run(args: ConvertArgs) -> Result<()> {
    let doc = renderer::convert::convert(&args.input, &args.output)?;
    let what = match doc {
        renderer::convert::Document::Scene(_) => "scene",
        renderer::convert::Document::Job(_) => "job",
    };
    println!(
        "wrote {} ({what} from {})",
        args.output.display(),
        args.input.display()
    );
    Ok(())
}
