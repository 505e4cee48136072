//! `blurlab render export stimuli/<job> --format y4m|ffv1|h264`: stimuli as playable videos.

use anyhow::Result;
use clap::builder::PossibleValue;
use clap::{Args, ValueEnum};
use renderer::export::{VideoFormat, export_job, y4m};
use std::path::PathBuf;

/// Write every stimulus (or those given with --id) of a rendered job as a video file.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// The rendered job's folder (holding manifest.json).
    pub stimuli: PathBuf,
    /// y4m is written by blurlab itself; ffv1 and h264 need the `ffmpeg` program.
    #[arg(long, value_enum, default_value = "y4m")]
    pub format: Format,
    /// Output folder [default: <stimuli>/videos].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Export only this stimulus (repeatable).
    #[arg(long = "id")]
    pub ids: Vec<String>,
    /// Y'CbCr matrix of Y4M output.
    #[arg(long, value_enum, default_value = "bt601")]
    pub matrix: Matrix,
    /// Y'CbCr range of Y4M output.
    #[arg(long, value_enum, default_value = "limited")]
    pub range: Range,
}

pub fn run(args: ExportArgs) -> Result<()> {
    let out = args.out.unwrap_or_else(|| args.stimuli.join("videos"));
    let opts = y4m::Y4mOptions {
        matrix: args.matrix.0,
        range: args.range.0,
    };
    for f in export_job(&args.stimuli, &out, args.format.0, opts, &args.ids)? {
        println!("wrote {}", f.display());
    }
    Ok(())
}

/// The flags' names (and help) for the export choices: a flag type wrapping each library
/// type, which knows nothing of clap.
macro_rules! value_enum {
    ($flag:ident($ty:ty): $($variant:path => $name:literal $(: $help:literal)?),+ $(,)?) => {
        #[derive(Clone, Copy, Debug)]
        pub struct $flag(pub $ty);

        impl ValueEnum for $flag {
            fn value_variants<'a>() -> &'a [Self] {
                &[$($flag($variant)),+]
            }
            fn to_possible_value(&self) -> Option<PossibleValue> {
                Some(match self.0 {
                    $($variant => PossibleValue::new($name)$(.help($help))?),+
                })
            }
        }
    };
}

value_enum!(Format(VideoFormat):
    VideoFormat::Y4m => "y4m": "Uncompressed YUV4MPEG2 4:4:4 (no external program)",
    VideoFormat::Ffv1 => "ffv1": "Lossless FFV1 in Matroska (needs ffmpeg)",
    VideoFormat::H264 => "h264": "H.264 4:4:4 lossless (qp 0) in MP4 (needs ffmpeg)",
);
value_enum!(Matrix(y4m::Matrix): y4m::Matrix::Bt601 => "bt601", y4m::Matrix::Bt709 => "bt709");
value_enum!(Range(y4m::Range):
    y4m::Range::Limited => "limited": "Y in 16..235, Cb/Cr in 16..240 (the default of video players)",
    y4m::Range::Full => "full": "Y, Cb, Cr in 0..255",
);
