//! The stimulus manifest (`stimuli/<job>/manifest.json`): the one file through which the
//! experiment and the analysis learn what was rendered. Format `blurlab-manifest/1`.

use crate::condition::{Condition, PointSetKind, TimeFilter};
use anyhow::{Result, bail};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The format tag every manifest carries; readers refuse any other.
pub const MANIFEST_FORMAT: &str = "blurlab-manifest/1";

/// File name of a job's manifest inside its stimulus folder.
pub const MANIFEST_FILE: &str = "manifest.json";

/// One rendered stimulus set (one job).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    /// Always [`MANIFEST_FORMAT`].
    pub format: String,
    /// The job's name.
    pub job: String,
    /// One entry per rendered video, references included.
    pub stimuli: Vec<Stimulus>,
    /// The user's files rendered in place of the scenes' own (`render job --asset`), by name
    /// and SHA-256; absent when the scenes' own files were used.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub assets: Vec<crate::assets::AssetRecord>,
}

/// One rendered video.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Stimulus {
    /// Stable id, e.g. `plane-hammersley-truncated_box-64`; the experiment and analysis use only this.
    pub id: String,
    /// Scene name (the scene file's stem).
    pub scene: String,
    /// Point set, e.g. `hammersley`.
    pub point_set: PointSetKind,
    /// Time filter, e.g. `truncated_box`.
    pub time_filter: TimeFilter,
    /// Samples per pixel.
    pub spp: u32,
    /// True for an independent high-density reference of its scene.
    pub reference: bool,
    /// The stimulus this one's error is measured against: the scene's reference, or the highest
    /// level of the same point set and time filter (job reference `highest_level`), which is
    /// then its own reference (`reference_id == id`, zero error by construction, so `error`
    /// is absent). Absent for independent references, and in manifests written before the
    /// field existed, whose test stimuli were measured against `<scene>-reference`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference_id: Option<String>,
    /// The stimulus's master seed.
    pub seed: u64,
    pub width: u32,
    pub height: u32,
    /// Number of frames in the video.
    pub frames: u32,
    /// Playback rate.
    pub fps: f64,
    /// Display frames (8-bit sRGB PNG), relative to the manifest's folder, in playback order.
    pub frame_paths: Vec<String>,
    /// Linear HDR frames (EXR), relative to the manifest's folder, when rendered.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub exr_paths: Vec<String>,
    /// SHA-256 over the display frames' bytes in order, lowercase hex.
    pub content_hash: String,
    /// Wall-clock seconds the render took.
    pub render_seconds: f64,
    /// Error against the scene's reference, averaged over frames (absent for references).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<ErrorMetrics>,
}

impl Stimulus {
    /// The stimulus's condition: its scene, point set and time filter. (The manifest keeps the
    /// three as fields of the entry: it refuses unknown fields, which serde cannot combine
    /// with a flattened struct.)
    pub fn condition(&self) -> Condition {
        Condition::new(self.scene.clone(), self.point_set, self.time_filter)
    }

    /// Whether the stimulus is its own reference (the highest level under a `highest_level`
    /// job reference): its error is zero by construction and not recorded.
    pub fn own_reference(&self) -> bool {
        self.reference_id.as_deref() == Some(self.id.as_str())
    }
}

/// Error of a stimulus against its reference, averaged over frames.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ErrorMetrics {
    /// Root mean squared error in linear HDR radiance (after exposure).
    pub rmse: f64,
    /// Relative MSE: mean of (x - r)^2 / (r^2 + 0.01) in linear HDR.
    pub rel_mse: f64,
    /// PSNR in dB of the 8-bit display frames.
    pub psnr: f64,
    /// Mean FLIP error of the display frames (0 = identical, 1 = maximal).
    pub flip: f64,
}

impl Manifest {
    /// An empty manifest for a job.
    pub fn new(job: &str) -> Self {
        Self {
            format: MANIFEST_FORMAT.to_string(),
            job: job.to_string(),
            stimuli: Vec::new(),
            assets: Vec::new(),
        }
    }

    /// Read and check a manifest; `path` may be the file or the folder holding it.
    pub fn load(path: &Path) -> Result<Self> {
        let file = manifest_file(path);
        let text = crate::utf8::read(&file, "stimulus manifest")?;
        let m: Manifest = crate::json::from_str(&text, &file, "stimulus manifest")?;
        if m.format != MANIFEST_FORMAT {
            bail!(
                "{}: field `format` is {:?}; this version reads {:?}",
                file.display(),
                m.format,
                MANIFEST_FORMAT
            );
        }
        Ok(m)
    }

    /// Write atomically to `path` (file or folder).
    pub fn save(&self, path: &Path) -> Result<()> {
        let json = serde_json::to_vec_pretty(self)?;
        crate::atomic::write_atomic(&manifest_file(path), &json)
    }

    /// The stimulus with this id.
    pub fn get(&self, id: &str) -> Option<&Stimulus> {
        self.stimuli.iter().find(|s| s.id == id)
    }

    /// The independent reference stimulus of a scene.
    pub fn reference(&self, scene: &str) -> Option<&Stimulus> {
        self.stimuli
            .iter()
            .find(|s| s.reference && s.scene == scene)
    }

    /// The stimulus `s` is measured against (itself for an own reference); `None` for an
    /// independent reference.
    pub fn reference_of(&self, s: &Stimulus) -> Option<&Stimulus> {
        if s.reference {
            return None;
        }
        match &s.reference_id {
            Some(id) => self.get(id),
            None => self.reference(&s.scene),
        }
    }
}

/// The manifest's `content_hash` of a video: SHA-256 over its display frames' file bytes, in
/// playback order, as lowercase hex. The runner writes it and the experiment's preflight checks
/// it, both through this type, so the two can never disagree on the definition.
#[derive(Clone, Default)]
pub struct ContentHash(sha2::Sha256);

impl ContentHash {
    pub fn new() -> Self {
        Self::default()
    }

    /// Add the next frame's file bytes.
    pub fn add_frame(&mut self, png_bytes: &[u8]) {
        sha2::Digest::update(&mut self.0, png_bytes);
    }

    /// The hash as lowercase hex.
    pub fn finish(self) -> String {
        crate::digest::hex(&sha2::Digest::finalize(self.0))
    }
}

/// `path` itself if it names a file, else `path/manifest.json`.
pub fn manifest_file(path: &Path) -> PathBuf {
    if path.extension().is_some_and(|e| e == "json") {
        path.to_path_buf()
    } else {
        path.join(MANIFEST_FILE)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Manifest {
        let mut m = Manifest::new("demo");
        m.stimuli.push(Stimulus {
            id: "plane-hammersley-truncated_box-8".into(),
            scene: "plane".into(),
            point_set: PointSetKind::Hammersley,
            time_filter: TimeFilter::TruncatedBox,
            spp: 8,
            reference: false,
            reference_id: Some("plane-reference".into()),
            seed: 1,
            width: 4,
            height: 2,
            frames: 1,
            fps: 24.0,
            frame_paths: vec!["a/frame_0000.png".into()],
            exr_paths: vec![],
            content_hash: "00".into(),
            render_seconds: 0.5,
            error: Some(ErrorMetrics {
                rmse: 0.1,
                rel_mse: 0.01,
                psnr: 30.0,
                flip: 0.05,
            }),
        });
        m
    }

    #[test]
    fn round_trips_through_disk() {
        let dir = tempfile::tempdir().unwrap();
        let m = sample();
        m.save(dir.path()).unwrap();
        assert_eq!(Manifest::load(dir.path()).unwrap(), m);
    }

    #[test]
    fn references_are_found_by_id_and_old_manifests_fall_back_to_the_scene_reference() {
        let mut m = sample();
        let mut reference = m.stimuli[0].clone();
        reference.id = "plane-reference".into();
        reference.reference = true;
        reference.reference_id = None;
        m.stimuli.push(reference);
        let test = m.stimuli[0].clone();
        assert_eq!(m.reference_of(&test).unwrap().id, "plane-reference");
        // Written before `reference_id` existed: the scene's reference.
        let mut old = test.clone();
        old.reference_id = None;
        let text = serde_json::to_string(&old).unwrap();
        assert!(!text.contains("reference_id"));
        assert_eq!(m.reference_of(&old).unwrap().id, "plane-reference");
        assert_eq!(m.reference_of(&m.stimuli[1]), None);
        // Its own reference.
        let mut top = test;
        top.reference_id = Some(top.id.clone());
        assert!(top.own_reference());
        m.stimuli[0] = top.clone();
        assert_eq!(m.reference_of(&top).unwrap().id, top.id);
    }

    #[test]
    fn refuses_unknown_version_naming_the_field() {
        let dir = tempfile::tempdir().unwrap();
        let mut m = sample();
        m.format = "blurlab-manifest/9".into();
        m.save(dir.path()).unwrap();
        let err = format!("{:#}", Manifest::load(dir.path()).unwrap_err());
        assert!(
            err.contains("format") && err.contains("blurlab-manifest/1"),
            "{err}"
        );
    }
}
