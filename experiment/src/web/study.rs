//! The study a server runs: the design and, for every stimulus it can show, the frame files the
//! manifest lists. Frames are served only from these paths (never from a path in a request).

use super::wire::{Keys, PlaybackInfo, Video};
use crate::design::{Design, Layout};
use crate::frames::VideoSource;
use anyhow::{Result, bail};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

/// The frame files of one stimulus, in playback order.
pub type Frames = Arc<[PathBuf]>;

#[derive(Debug)]
pub struct Study {
    pub design: Design,
    frames: HashMap<String, Frames>,
    pub video: Video,
    pub playback: PlaybackInfo,
    pub keys: Keys,
    pub min_window_px: [u32; 2],
}

impl Study {
    /// Read the design's manifest; every stimulus the design shows must be in it, with one size
    /// and frame count (the browser lays out and preloads one kind of video).
    pub fn load(design: Design) -> Result<Self> {
        let manifest = renderer::manifest::Manifest::load(&design.manifest_path)?;
        let mut frames = HashMap::new();
        let mut video: Option<Video> = None;
        for needed in crate::preflight::needed_stimuli(&design) {
            let source = VideoSource::from_manifest(&manifest, &design.manifest_path, &needed.id)?
                .played_by(&design);
            let this = Video {
                width: source.width,
                height: source.height,
                fps: source.fps,
                frames: source.frames(),
            };
            match &video {
                Some(v) if *v != this => bail!(
                    "{}: stimulus {} is {}x{}, {} frames at {} fps, but others are {}x{}, {} \
                     frames at {} fps; a web session shows one size of video",
                    design.manifest_path.display(),
                    needed.id,
                    this.width,
                    this.height,
                    this.frames,
                    this.fps,
                    v.width,
                    v.height,
                    v.frames,
                    v.fps
                ),
                _ => video = Some(this),
            }
            frames.insert(needed.id, Frames::from(source.frame_paths));
        }
        let Some(video) = video else {
            bail!("{}: the design shows no stimuli", design.path.display());
        };
        let p = &design.file.playback;
        let spacing = p.spacing_px;
        let min_window_px = match design.file.layout {
            Layout::Sequential => [2 * video.width + spacing, video.height],
            Layout::Grid => [2 * video.width + spacing, 2 * video.height + spacing],
        };
        Ok(Self {
            playback: PlaybackInfo {
                layout: match design.file.layout {
                    Layout::Sequential => "sequential",
                    Layout::Grid => "simultaneous",
                }
                .into(),
                loops: p.loops,
                fixation_ms: p.fixation_ms,
                gap_ms: p.gap_ms,
                spacing_px: spacing,
                background: p.background,
            },
            keys: Keys {
                pair1: design.file.keys.pair1.clone(),
                pair2: design.file.keys.pair2.clone(),
            },
            min_window_px,
            video,
            frames,
            design,
        })
    }

    /// The frame files of stimulus `id` (an id from the design's trial list).
    pub fn frames(&self, id: &str) -> Option<Frames> {
        self.frames.get(id).cloned()
    }

    /// Every frame file the study can serve (for the byte counts in docs and the benchmark).
    pub fn all_frames(&self) -> impl Iterator<Item = (&str, &Frames)> {
        self.frames.iter().map(|(k, v)| (k.as_str(), v))
    }
}
