//! `render export stimuli/<job> --format y4m|ffv1|h264`: stimuli as playable videos.

use crate::export::{VideoFormat, export_job, y4m};
use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

/// Write every stimulus (or those given with --id) of a rendered job as a video file.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// The rendered job's folder (holding manifest.json).
    pub stimuli: PathBuf,
    /// y4m is written by blurlab itself; ffv1 and h264 need the `ffmpeg` program.
    #[arg(long, value_enum, default_value = "y4m")]
    pub format: VideoFormat,
    /// Output folder [default: <stimuli>/videos].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Export only this stimulus (repeatable).
    #[arg(long = "id")]
    pub ids: Vec<String>,
    /// Y'CbCr matrix of Y4M output.
    #[arg(long, value_enum, default_value = "bt601")]
    pub matrix: y4m::Matrix,
    /// Y'CbCr range of Y4M output.
    #[arg(long, value_enum, default_value = "limited")]
    pub range: y4m::Range,
}

pub fn run(args: ExportArgs) -> Result<()> {
    let out = args.out.unwrap_or_else(|| args.stimuli.join("videos"));
    let opts = y4m::Y4mOptions {
        matrix: args.matrix,
        range: args.range,
    };
    for f in export_job(&args.stimuli, &out, args.format, opts, &args.ids)? {
        println!("wrote {}", f.display());
    }
    Ok(())
}
