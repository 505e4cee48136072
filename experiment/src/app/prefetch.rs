//! The app's video cache: the decoded videos of the current trial by stimulus id, and the next
//! trial's videos loading in advance while the subject answers, from the session's
//! [`FrameStore`].

use super::loader::{Budget, LoadState, Loader, Video};
use crate::design::Design;
use crate::playback::frame_store::{FrameStore, StoredVideo};
use crate::playback::stream;
use crate::trials::Trial;
use std::collections::HashMap;
use std::sync::Arc;
use std::time::Duration;

/// Uploads per repaint while loading (the time keeps the progress bar alive).
pub(super) const UPLOAD_BUDGET: Budget = Budget {
    time: Duration::from_millis(12),
    frames: usize::MAX,
};

/// Uploads per repaint while the trial streams: one repaint per video frame (timer pacing) must
/// bring more than the two new frames a pair needs, and leave the repaint on time.
pub(super) const PLAYBACK_BUDGET: Budget = Budget {
    time: Duration::from_millis(6),
    frames: 4,
};

/// Videos by stimulus id, and the prefetch of the next trial's.
pub(super) struct VideoCache {
    store: Arc<dyn FrameStore>,
    /// Decoded videos by stimulus id (those of the current trial).
    videos: HashMap<String, Video>,
    /// The next trial's videos, loading while the subject answers: (practice, index) and loader.
    prefetch: Option<((bool, u32), Loader)>,
}

impl VideoCache {
    pub(super) fn new(store: Arc<dyn FrameStore>) -> Self {
        VideoCache {
            store,
            videos: HashMap::new(),
            prefetch: None,
        }
    }

    pub(super) fn store(&self) -> &dyn FrameStore {
        &*self.store
    }

    /// The decoded video `id`, else the one `loading` streams.
    pub(super) fn video<'a>(&'a self, id: &str, loading: Option<&'a Loader>) -> Option<&'a Video> {
        self.videos
            .get(id)
            .or_else(|| loading.and_then(|l| l.videos().iter().find(|v| v.source.id == id)))
    }

    /// Keep the videos a finished loader decoded.
    pub(super) fn insert(&mut self, loader: Loader) {
        for v in loader.into_videos() {
            self.videos.insert(v.source.id.clone(), v);
        }
    }

    /// The loader of `trial`'s videos: the prefetch if it is that trial's, else a new one.
    pub(super) fn loader_for_trial(
        &mut self,
        design: &Design,
        trial: &Trial,
    ) -> anyhow::Result<Loader> {
        match self.prefetch.take() {
            Some((key, loader)) if key == (trial.practice, trial.index) => Ok(loader),
            _ => self.loader_for(design, trial),
        }
    }

    /// Free the videos `trial` does not show and start loading those it needs, in the order
    /// the trial shows their frames.
    fn loader_for(&mut self, design: &Design, trial: &Trial) -> anyhow::Result<Loader> {
        let needed = trial.stimuli();
        self.videos.retain(|id, _| needed.contains(&id.as_str()));
        let mut missing: Vec<StoredVideo> = Vec::new();
        for id in needed {
            if !self.videos.contains_key(id) && !missing.iter().any(|s| s.id == id) {
                missing.push(self.store.video(id)?.played_by(design));
            }
        }
        let starts: Vec<f64> = missing
            .iter()
            .map(|v| stream::first_shown_s(design, trial, &v.id, v.frames, v.fps))
            .collect();
        Ok(Loader::start(self.store.clone(), missing, &starts))
    }

    /// Start loading `next`'s videos unless a prefetch is already under way.
    pub(super) fn start_prefetch(&mut self, design: &Design, next: Option<&Trial>) {
        if self.prefetch.is_some() {
            return;
        }
        let Some(next) = next else {
            return;
        };
        // A failure here is reported when the trial itself starts.
        if let Ok(loader) = self.loader_for(design, next) {
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
