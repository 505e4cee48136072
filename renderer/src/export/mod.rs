//! Stimulus videos: every stimulus of a rendered job as one playable file, besides its PNG
//! frames. Y4M is written by the project itself; FFV1 and H.264 go through `ffmpeg`.

pub mod ffmpeg;
pub mod y4m;

use crate::manifest::Manifest;
use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};

/// A video format for export.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VideoFormat {
    /// Uncompressed YUV4MPEG2 4:4:4 (no external program).
    Y4m,
    /// Lossless FFV1 in Matroska (needs ffmpeg).
    Ffv1,
    /// H.264 4:4:4 lossless (qp 0) in MP4 (needs ffmpeg).
    H264,
}

impl VideoFormat {
    pub fn extension(self) -> &'static str {
        match self {
            VideoFormat::Y4m => "y4m",
            VideoFormat::Ffv1 => ffmpeg::Codec::Ffv1.extension(),
            VideoFormat::H264 => ffmpeg::Codec::H264.extension(),
        }
    }
}

/// Export the stimuli of the job in `stimuli_dir` (all, or those whose id is in `only`) to
/// `out_dir/<id>.<ext>`. Returns the written files.
pub fn export_job(
    stimuli_dir: &Path,
    out_dir: &Path,
    format: VideoFormat,
    y4m_options: y4m::Y4mOptions,
    only: &[String],
) -> Result<Vec<PathBuf>> {
    let manifest = Manifest::load(stimuli_dir)?;
    for id in only {
        if manifest.get(id).is_none() {
            bail!(
                "{}: no stimulus with id {id:?}",
                crate::manifest::manifest_file(stimuli_dir).display()
            );
        }
    }
    if format != VideoFormat::Y4m && !ffmpeg::ffmpeg_available() {
        bail!(
            "`ffmpeg` is not installed (not found on PATH; set BLURLAB_FFMPEG to its path), so \
             {format:?} export is unavailable. Install it (e.g. `apt install ffmpeg`) or use \
             `--format y4m`, which needs no external program"
        );
    }
    std::fs::create_dir_all(out_dir)
        .with_context(|| format!("cannot create folder {}", out_dir.display()))?;
    let mut written = Vec::new();
    for s in &manifest.stimuli {
        if !only.is_empty() && !only.contains(&s.id) {
            continue;
        }
        let frames: Vec<PathBuf> = s.frame_paths.iter().map(|p| stimuli_dir.join(p)).collect();
        let out = out_dir.join(format!("{}.{}", s.id, format.extension()));
        match format {
            VideoFormat::Y4m => y4m::write_y4m(&frames, s.fps, &out, y4m_options)?,
            VideoFormat::Ffv1 => ffmpeg::encode(&frames, s.fps, ffmpeg::Codec::Ffv1, &out)?,
            VideoFormat::H264 => ffmpeg::encode(&frames, s.fps, ffmpeg::Codec::H264, &out)?,
        }
        written.push(out);
    }
    Ok(written)
}
