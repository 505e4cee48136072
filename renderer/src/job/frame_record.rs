//! The small record written beside every rendered frame (`frame_NNNN.json`, format
//! `blurlab-frame/1`), last, after the frame's image files. Its presence and the sizes it
//! records are what resume trusts: a frame whose record is missing, unreadable or disagrees
//! with the files on disk is rendered again. Render time lives here too (the only field that
//! differs between two runs of the same job).

use crate::frame_io::names::{exr_path, png_path};
use crate::metrics::FrameError;
use anyhow::Result;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

pub const FRAME_RECORD_FORMAT: &str = "blurlab-frame/1";

/// What is known about one finished frame.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FrameRecord {
    pub format: String,
    pub frame: u32,
    /// Size and SHA-256 (hex) of the display PNG.
    pub png_bytes: u64,
    pub png_sha256: String,
    /// Size of the linear EXR, when one is kept for this frame.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exr_bytes: Option<u64>,
    /// Wall-clock seconds spent rendering this frame.
    pub render_seconds: f64,
    /// Error against the reference frame (test stimuli; filled at render time when the
    /// reference frame already existed, else when the job is finalized).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<FrameError>,
}

/// `dir/frame_NNNN.json`.
pub fn record_path(dir: &Path, frame: u32) -> PathBuf {
    dir.join(format!("frame_{frame:04}.json"))
}

impl FrameRecord {
    /// The record of `frame` in `dir`, if present and readable.
    pub fn load(dir: &Path, frame: u32) -> Option<Self> {
        let text = std::fs::read(record_path(dir, frame)).ok()?;
        let r: FrameRecord = serde_json::from_slice(&text).ok()?;
        (r.format == FRAME_RECORD_FORMAT && r.frame == frame).then_some(r)
    }

    pub fn save(&self, dir: &Path) -> Result<()> {
        let json = serde_json::to_vec_pretty(self)?;
        crate::atomic::write_atomic(&record_path(dir, self.frame), &json)
    }

    /// Whether the files on disk still match this record (cheap: sizes only; content hashes
    /// are checked when the job is finalized).
    pub fn matches_disk(&self, dir: &Path, need_exr: bool) -> bool {
        let size = |p: PathBuf| std::fs::metadata(p).ok().map(|m| m.len());
        if size(png_path(dir, self.frame)) != Some(self.png_bytes) {
            return false;
        }
        match (need_exr, self.exr_bytes) {
            (true, Some(n)) => size(exr_path(dir, self.frame)) == Some(n),
            (true, None) => false,
            (false, _) => true,
        }
    }
}

/// The finished record of `frame` in `dir`, if the frame is complete on disk.
pub fn completed(dir: &Path, frame: u32, need_exr: bool) -> Option<FrameRecord> {
    FrameRecord::load(dir, frame).filter(|r| r.matches_disk(dir, need_exr))
}

/// Lowercase hex SHA-256, the light core's (the assets hash files the same way).
pub use crate::digest::sha256_hex;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_record_is_complete_only_while_its_files_match() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::write(png_path(d, 3), b"pngdata").unwrap();
        let r = FrameRecord {
            format: FRAME_RECORD_FORMAT.into(),
            frame: 3,
            png_bytes: 7,
            png_sha256: sha256_hex(b"pngdata"),
            exr_bytes: None,
            render_seconds: 0.1,
            error: None,
        };
        assert!(completed(d, 3, false).is_none(), "no record yet");
        r.save(d).unwrap();
        assert_eq!(completed(d, 3, false), Some(r.clone()));
        assert!(completed(d, 3, true).is_none(), "EXR required but absent");
        std::fs::write(png_path(d, 3), b"png").unwrap(); // truncated
        assert!(completed(d, 3, false).is_none());
        std::fs::write(record_path(d, 3), b"{\"format\": ").unwrap(); // garbage
        assert!(FrameRecord::load(d, 3).is_none());
    }

    #[test]
    fn errors_read_back_from_records_are_bit_identical() {
        // A frame measured late (sharded runs) keeps its error in memory, a frame measured at
        // render time reads it back from its record: the manifests agree only if JSON parsing
        // is exact. serde_json's default parser is not (about 1 value in 10 came back one ULP
        // off); the workspace enables its `float_roundtrip` feature.
        for i in 0..1000 {
            let v = crate::hash::unit_f64(crate::hash::hash(1, &[i])) * 5.0;
            let back: f64 = serde_json::from_str(&serde_json::to_string(&v).unwrap()).unwrap();
            assert_eq!(back.to_bits(), v.to_bits(), "{v:?}");
        }
    }
}
