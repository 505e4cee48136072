//! The study a server runs: the design and, for every stimulus it can show, its encoded video
//! (a frame pack, `packs.rs`) in the stimulus set's cache. Videos are served only from these
//! paths (never from a path in a request).

use super::packs::{Cache, Encoded, Pack};
use super::wire::{ClientSettings, Keys, PlaybackInfo, Video};
use crate::design::online::{Text, read_text};
use crate::design::{Design, Layout};
use crate::playback::frames::VideoSource;
use crate::playback::presentation::Presentation;
use anyhow::{Result, bail};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// One stimulus's encoded video and where it lies.
#[derive(Clone, Debug)]
pub struct Served {
    pub path: PathBuf,
    pub pack: Pack,
}

#[derive(Debug)]
pub struct Study {
    pub design: Design,
    /// Stimulus id -> its encoded video.
    videos: BTreeMap<String, Served>,
    pub video: Video,
    pub playback: PlaybackInfo,
    pub keys: Keys,
    pub min_window_px: [u32; 2],
    /// Video frames a trial shows (`Presentation::frames_shown`): an answer cannot time, drop
    /// or be late by more.
    pub frames_shown: u64,
    pub client: ClientSettings,
    /// What loading encoded (a first start encodes every video; later ones reuse them).
    pub encoded: Encoded,
    /// The design's `online.consent` and `online.debriefing` texts.
    pub consent: Option<Text>,
    pub debriefing: Option<Text>,
}

impl Study {
    /// Read the design's manifest and encode (or reuse) every video it shows; every stimulus
    /// must be in the manifest, with one size and frame count (the browser lays out one kind of
    /// video). `progress(k, n, id)` is told each video as its encoding starts.
    pub fn load(
        design: Design,
        client: ClientSettings,
        progress: &mut dyn FnMut(usize, usize, &str),
    ) -> Result<Self> {
        let text = |field: &str, file: &Option<String>| {
            file.as_ref()
                .map(|f| read_text(&design.path, field, f))
                .transpose()
        };
        let online = design.file.online.clone().unwrap_or_default();
        let consent = text("consent", &online.consent)?;
        let debriefing = text("debriefing", &online.debriefing)?;
        let sources = sources(&design)?;
        let Some(first) = sources.first() else {
            bail!("{}: the design shows no stimuli", design.path.display());
        };
        let video = Video {
            width: first.width,
            height: first.height,
            fps: first.fps,
            frames: first.frames(),
        };
        let mut cache = Cache::open(&design.manifest_path)?;
        let encoded = cache.ensure(&sources, progress)?;
        let videos = sources
            .iter()
            .map(|s| {
                let pack = cache.get(&s.id).expect("ensured above").clone();
                let served = Served {
                    path: cache.path(&pack),
                    pack,
                };
                (s.id.clone(), served)
            })
            .collect();
        let p = &design.file.playback;
        let spacing = p.spacing_px;
        let min_window_px = match design.file.layout {
            Layout::Sequential => [2 * video.width + spacing, video.height],
            Layout::Grid => [2 * video.width + spacing, 2 * video.height + spacing],
        };
        let frames_shown = Presentation::new(&design, video.frames, video.fps).frames_shown();
        Ok(Self {
            frames_shown,
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
            videos,
            client,
            encoded,
            consent,
            debriefing,
            design,
        })
    }

    /// The encoded video of stimulus `id` (an id from the design's trial list).
    pub fn video_of(&self, id: &str) -> Option<&Served> {
        self.videos.get(id)
    }

    /// Every video the study can serve, by stimulus id.
    pub fn videos(&self) -> impl Iterator<Item = (&str, &Served)> {
        self.videos.iter().map(|(k, v)| (k.as_str(), v))
    }
}

/// The frame files of every stimulus the design shows, checked to be one size of video.
pub fn sources(design: &Design) -> Result<Vec<VideoSource>> {
    let manifest = renderer::manifest::Manifest::load(&design.manifest_path)?;
    let mut out: Vec<VideoSource> = Vec::new();
    for needed in crate::preflight::needed_stimuli(design) {
        let source = VideoSource::from_manifest(&manifest, &design.manifest_path, &needed.id)?
            .played_by(design);
        if let Some(v) = out.first()
            && (v.width, v.height, v.frames(), v.fps)
                != (source.width, source.height, source.frames(), source.fps)
        {
            bail!(
                "{}: stimulus {} is {}x{}, {} frames at {} fps, but others are {}x{}, {} \
                     frames at {} fps; a web session shows one size of video",
                design.manifest_path.display(),
                needed.id,
                source.width,
                source.height,
                source.frames(),
                source.fps,
                v.width,
                v.height,
                v.frames(),
                v.fps
            );
        }
        out.push(source);
    }
    Ok(out)
}
