//! Where the app's videos come from: the session's frame store behind a small interface, so
//! the loader, the prefetch and the app can be driven without a file system (issue 27).
//!
//! What the player needs of a stimulus is its [`StoredVideo`] (size, rate, frame count) and, on a
//! decoding thread, each frame decoded ([`FrameStore::frame`]). [`FrameDir`] is the rendered
//! stimulus set on disk as `run` uses it: the manifest's PNG files, read and decoded exactly as
//! [`crate::playback::frames::load_frame`] does (same bytes, same messages). [`MemoryFrames`] holds
//! decoded frames in memory: tests, and any front end that makes its stimuli itself. No GUI types,
//! so both can be tested headless. `predict` keeps reading through
//! [`crate::playback::frames::VideoSource`] (it needs frame files, not a player's view of them).

use crate::playback::frames::{RgbFrame, VideoSource, decode_png};
use anyhow::{Context, Result, bail};
use renderer::manifest::Manifest;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// A video as the player sees it before its frames: which stimulus, how large, how fast and
/// how long.
#[derive(Clone, Debug, PartialEq)]
pub struct StoredVideo {
    pub id: String,
    pub width: u32,
    pub height: u32,
    /// Frames per second (the manifest's, or the design's playback rate: [`Self::played_by`]).
    pub fps: f64,
    pub frames: u32,
}

impl StoredVideo {
    /// The same video at the rate `design` plays it ([`crate::design::Playback::rate`]).
    pub fn played_by(mut self, design: &crate::Design) -> Self {
        self.fps = design.file.playback.rate(self.fps);
        self
    }
}

/// A stimulus set's frames, shared by the loader's decoding threads.
pub trait FrameStore: Send + Sync {
    /// Stimulus `id`'s video; an error names the store and the id.
    fn video(&self, id: &str) -> Result<StoredVideo>;

    /// Frame `index` (0-based, playback order) of stimulus `id`, decoded to 8-bit RGB at the
    /// video's size; an error names the frame.
    fn frame(&self, id: &str, index: usize) -> Result<RgbFrame>;
}

/// The rendered stimulus set on disk: a manifest and the PNG frames beside it.
#[derive(Clone, Debug)]
pub struct FrameDir {
    manifest: Manifest,
    manifest_path: PathBuf,
    folder: PathBuf,
}

impl FrameDir {
    /// The stimulus set of `manifest`, read from `manifest_path` (frame paths are relative to
    /// its folder).
    pub fn new(manifest: Manifest, manifest_path: PathBuf) -> Self {
        let folder = renderer::manifest::manifest_file(&manifest_path)
            .parent()
            .unwrap_or(Path::new(""))
            .to_path_buf();
        Self {
            manifest,
            manifest_path,
            folder,
        }
    }

    pub fn manifest(&self) -> &Manifest {
        &self.manifest
    }
}

impl FrameStore for FrameDir {
    fn video(&self, id: &str) -> Result<StoredVideo> {
        let v = VideoSource::from_manifest(&self.manifest, &self.manifest_path, id)?;
        Ok(StoredVideo {
            frames: v.frames(),
            id: v.id,
            width: v.width,
            height: v.height,
            fps: v.fps,
        })
    }

    fn frame(&self, id: &str, index: usize) -> Result<RgbFrame> {
        let Some(s) = self.manifest.get(id) else {
            bail!("{}: no stimulus {id:?}", self.manifest_path.display());
        };
        let rel = s.frame_paths.get(index).with_context(|| {
            format!(
                "{}: stimulus {id:?} has {} frames, not frame {index}",
                self.manifest_path.display(),
                s.frame_paths.len()
            )
        })?;
        decode_png(&self.folder.join(rel), s.width, s.height, id)
    }
}

/// Decoded videos in memory, by stimulus id.
#[derive(Clone, Debug, Default)]
pub struct MemoryFrames {
    videos: HashMap<String, (StoredVideo, Vec<RgbFrame>)>,
}

impl MemoryFrames {
    pub fn new() -> Self {
        Self::default()
    }

    /// Add (or replace) stimulus `id`: `frames` at `fps`, every one of the first's size.
    pub fn insert(&mut self, id: &str, fps: f64, frames: Vec<RgbFrame>) -> Result<()> {
        let Some(first) = frames.first() else {
            bail!("stimulus {id:?}: a video needs at least one frame");
        };
        let (width, height) = (first.width, first.height);
        for (f, frame) in frames.iter().enumerate() {
            let want = width as usize * height as usize * 3;
            if (frame.width, frame.height) != (width, height) || frame.rgb.len() != want {
                bail!(
                    "stimulus {id:?} frame {f}: {}x{} with {} bytes; expected {width}x{height} \
                     with {want} (the first frame's size, RGB)",
                    frame.width,
                    frame.height,
                    frame.rgb.len()
                );
            }
        }
        let video = StoredVideo {
            id: id.to_string(),
            width,
            height,
            fps,
            frames: frames.len() as u32,
        };
        self.videos.insert(id.to_string(), (video, frames));
        Ok(())
    }
}

impl FrameStore for MemoryFrames {
    fn video(&self, id: &str) -> Result<StoredVideo> {
        match self.videos.get(id) {
            Some((v, _)) => Ok(v.clone()),
            None => bail!("frames in memory: no stimulus {id:?}"),
        }
    }

    fn frame(&self, id: &str, index: usize) -> Result<RgbFrame> {
        let (_, frames) = self
            .videos
            .get(id)
            .with_context(|| format!("frames in memory: no stimulus {id:?}"))?;
        frames.get(index).cloned().with_context(|| {
            format!(
                "frames in memory: stimulus {id:?} has {} frames, not frame {index}",
                frames.len()
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixture::{StudySpec, write_study};
    use crate::playback::frames::load_frame;

    /// Frame `k` of a made-up video: every byte different between frames.
    fn frame(k: u8, width: u32, height: u32) -> RgbFrame {
        let n = (width * height * 3) as usize;
        RgbFrame {
            width,
            height,
            rgb: (0..n).map(|i| (i as u8).wrapping_add(k)).collect(),
        }
    }

    /// The directory store gives what the manifest and `load_frame` give, and refuses a frame
    /// or a stimulus it lacks by name.
    #[test]
    fn the_directory_store_reads_the_manifests_frames() {
        let dir = tempfile::tempdir().unwrap();
        let spec = StudySpec {
            scenes: vec!["alpha".into()],
            point_sets: vec!["random".into()],
            ..StudySpec::tiny()
        };
        let study = write_study(dir.path(), &spec).unwrap();
        let path = study.stimuli_dir.join("manifest.json");
        let manifest = Manifest::load(&path).unwrap();
        let s = &manifest.stimuli[0];
        let source = VideoSource::from_manifest(&manifest, &path, &s.id).unwrap();
        let store = FrameDir::new(manifest.clone(), path);
        let v = store.video(&s.id).unwrap();
        assert_eq!((v.width, v.height, v.fps), (s.width, s.height, s.fps));
        assert_eq!(v.frames as usize, s.frame_paths.len());
        for f in 0..s.frame_paths.len() {
            assert_eq!(
                store.frame(&s.id, f).unwrap(),
                load_frame(&source, f).unwrap()
            );
        }
        let past = store.frame(&s.id, s.frame_paths.len()).unwrap_err();
        assert!(format!("{past:#}").contains("not frame"), "{past:#}");
        let none = store.video("nothing").unwrap_err();
        assert!(format!("{none:#}").contains("\"nothing\""), "{none:#}");
    }

    #[test]
    fn the_memory_store_gives_back_its_frames_and_refuses_mixed_sizes() {
        let mut store = MemoryFrames::new();
        let frames: Vec<RgbFrame> = (0..3).map(|k| frame(k, 4, 2)).collect();
        store.insert("a", 30.0, frames.clone()).unwrap();
        let v = store.video("a").unwrap();
        assert_eq!((v.width, v.height, v.fps, v.frames), (4, 2, 30.0, 3));
        for (f, want) in frames.iter().enumerate() {
            assert_eq!(&store.frame("a", f).unwrap(), want);
        }
        assert!(store.frame("a", 3).is_err());
        assert!(store.video("b").is_err());
        let mixed = vec![frame(0, 4, 2), frame(1, 2, 4)];
        let e = store.insert("m", 30.0, mixed).unwrap_err();
        assert!(format!("{e}").contains("frame 1"), "{e}");
        assert!(store.insert("e", 30.0, vec![]).is_err());
    }
}
