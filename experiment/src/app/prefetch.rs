//! The app's video cache: the decoded videos of the current trial by stimulus id, and the next
//! trial's videos loading in advance while the subject answers.

use super::loader::{LoadState, Loader, Video};
use crate::frames::VideoSource;
use crate::trials::Trial;
use renderer::manifest::Manifest;
use std::collections::HashMap;
use std::path::PathBuf;
use std::time::Duration;

/// Upload time per repaint while loading (keeps the progress bar alive).
pub(super) const UPLOAD_BUDGET: Duration = Duration::from_millis(12);

/// Videos by stimulus id, and the prefetch of the next trial's.
pub(super) struct VideoCache {
    manifest: Manifest,
    manifest_path: PathBuf,
    /// Decoded videos by stimulus id (those of the current trial).
    videos: HashMap<String, Video>,
    /// The next trial's videos, loading while the subject answers: (practice, index) and loader.
    prefetch: Option<((bool, u32), Loader)>,
}

impl VideoCache {
    pub(super) fn new(manifest: Manifest, manifest_path: PathBuf) -> Self {
        VideoCache {
            manifest,
            manifest_path,
            videos: HashMap::new(),
            prefetch: None,
        }
    }

    pub(super) fn manifest(&self) -> &Manifest {
        &self.manifest
    }

    /// The decoded videos by stimulus id.
    pub(super) fn videos(&self) -> &HashMap<String, Video> {
        &self.videos
    }

    /// Keep the videos a finished loader decoded.
    pub(super) fn insert(&mut self, loader: Loader) {
        for v in loader.into_videos() {
            self.videos.insert(v.source.id.clone(), v);
        }
    }

    /// The loader of `trial`'s videos: the prefetch if it is that trial's, else a new one.
    pub(super) fn loader_for_trial(&mut self, trial: &Trial) -> anyhow::Result<Loader> {
        match self.prefetch.take() {
            Some((key, loader)) if key == (trial.practice, trial.index) => Ok(loader),
            _ => self.loader_for(trial),
        }
    }

    /// Free the videos `trial` does not show and start loading those it needs.
    fn loader_for(&mut self, trial: &Trial) -> anyhow::Result<Loader> {
        let needed = trial.stimuli();
        self.videos.retain(|id, _| needed.contains(&id.as_str()));
        let mut missing: Vec<VideoSource> = Vec::new();
        for id in needed {
            if !self.videos.contains_key(id) && !missing.iter().any(|s| s.id == id) {
                missing.push(VideoSource::from_manifest(
                    &self.manifest,
                    &self.manifest_path,
                    id,
                )?);
            }
        }
        Ok(Loader::start(missing))
    }

    /// Start loading `next`'s videos unless a prefetch is already under way.
    pub(super) fn start_prefetch(&mut self, next: Option<&Trial>) {
        if self.prefetch.is_some() {
            return;
        }
        let Some(next) = next else {
            return;
        };
        // A failure here is reported when the trial itself starts.
        if let Ok(loader) = self.loader_for(next) {
            self.prefetch = Some(((next.practice, next.index), loader));
        }
    }

    /// Upload prefetched frames a few at a time (the caller makes sure nothing moves on
    /// screen).
    pub(super) fn pump_prefetch(&mut self, ctx: &egui::Context) {
        if let Some((_, loader)) = self.prefetch.as_mut() {
            match loader.pump(ctx, UPLOAD_BUDGET) {
                LoadState::Loading { .. } => ctx.request_repaint(),
                LoadState::Done => {}
                LoadState::Failed(_) => self.prefetch = None,
            }
        }
    }

    /// Whether the next trial's videos are still being loaded in advance.
    pub(super) fn prefetching(&self) -> bool {
        self.prefetch.as_ref().is_some_and(|(_, l)| !l.is_done())
    }
}
