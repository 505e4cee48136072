//! Reading a stimulus's frames for display: the manifest's PNG files decoded to 8-bit RGB,
//! exactly as rendered (no colour management, no resampling). No GUI types, so the preload can
//! be measured and tested headless.

use anyhow::{Context, Result, bail};
use renderer::manifest::Manifest;
use std::path::{Path, PathBuf};

/// A video as the player needs it.
#[derive(Clone, Debug, PartialEq)]
pub struct VideoSource {
    pub id: String,
    pub width: u32,
    pub height: u32,
    pub fps: f64,
    /// Frame files in playback order.
    pub frame_paths: Vec<PathBuf>,
}

impl VideoSource {
    /// The stimulus `id` of a manifest read from `manifest_path`.
    pub fn from_manifest(manifest: &Manifest, manifest_path: &Path, id: &str) -> Result<Self> {
        let Some(s) = manifest.get(id) else {
            bail!("{}: no stimulus {id:?}", manifest_path.display());
        };
        let folder = renderer::manifest::manifest_file(manifest_path)
            .parent()
            .unwrap_or(Path::new(""))
            .to_path_buf();
        Ok(Self {
            id: id.to_string(),
            width: s.width,
            height: s.height,
            fps: s.fps,
            frame_paths: s.frame_paths.iter().map(|p| folder.join(p)).collect(),
        })
    }

    /// The same video at the rate `design` plays it ([`crate::design::Playback::rate`]).
    pub fn played_by(mut self, design: &crate::Design) -> Self {
        self.fps = design.file.playback.rate(self.fps);
        self
    }

    pub fn frames(&self) -> u32 {
        self.frame_paths.len() as u32
    }

    /// Bytes one decoded frame takes as RGBA (what a GPU texture holds).
    pub fn rgba_bytes_per_frame(&self) -> u64 {
        self.width as u64 * self.height as u64 * 4
    }
}

/// One decoded frame.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RgbFrame {
    pub width: u32,
    pub height: u32,
    /// Packed 8-bit sRGB, row-major, top row first.
    pub rgb: Vec<u8>,
}

/// Decode frame `index` of a video, refusing a size other than the manifest's.
pub fn load_frame(video: &VideoSource, index: usize) -> Result<RgbFrame> {
    decode_png(
        &video.frame_paths[index],
        video.width,
        video.height,
        &video.id,
    )
}

/// Read and decode the PNG frame at `path` of stimulus `id`, refusing a size other than
/// `width` x `height` (the manifest's).
pub fn decode_png(path: &Path, width: u32, height: u32, id: &str) -> Result<RgbFrame> {
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    let img = image::load_from_memory_with_format(&bytes, image::ImageFormat::Png)
        .with_context(|| format!("{}: not a readable PNG", path.display()))?
        .into_rgb8();
    if img.dimensions() != (width, height) {
        bail!(
            "{}: is {}x{}, but the manifest says {width}x{height} for {id}",
            path.display(),
            img.width(),
            img.height(),
        );
    }
    Ok(RgbFrame {
        width: img.width(),
        height: img.height(),
        rgb: img.into_raw(),
    })
}
