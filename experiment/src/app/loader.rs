//! Preloading a trial's videos into GPU textures before it starts: frames are decoded on the
//! rayon pool (off the UI thread) and uploaded by the UI thread a few per repaint, so the
//! progress bar keeps moving. Textures use nearest filtering: a video pixel is a screen pixel.

use crate::frames::{RgbFrame, VideoSource, load_frame};
use egui::{ColorImage, Context, TextureHandle, TextureOptions};
use rayon::prelude::*;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, channel};
use std::time::{Duration, Instant};

/// A video held as one texture per frame.
pub struct Video {
    pub source: VideoSource,
    pub textures: Vec<TextureHandle>,
}

enum Decoded {
    Frame(usize, usize, RgbFrame),
    Failed(String),
}

/// Loading some videos.
pub struct Loader {
    rx: Receiver<Decoded>,
    cancel: Arc<AtomicBool>,
    sources: Vec<VideoSource>,
    textures: Vec<Vec<Option<TextureHandle>>>,
    total: usize,
    uploaded: usize,
}

/// Where loading stands.
pub enum LoadState {
    Loading { fraction: f32 },
    Failed(String),
    Done,
}

impl Loader {
    /// Start decoding every frame of `sources` in the background.
    pub fn start(sources: Vec<VideoSource>) -> Self {
        let (tx, rx) = channel();
        let cancel = Arc::new(AtomicBool::new(false));
        let jobs: Vec<(usize, usize)> = sources
            .iter()
            .enumerate()
            .flat_map(|(v, s)| (0..s.frame_paths.len()).map(move |f| (v, f)))
            .collect();
        let total = jobs.len();
        let textures = sources
            .iter()
            .map(|s| vec![None; s.frame_paths.len()])
            .collect();
        let (stop, work) = (cancel.clone(), sources.clone());
        std::thread::spawn(move || {
            jobs.par_iter().for_each_with(tx, |tx, &(v, f)| {
                if stop.load(Ordering::Relaxed) {
                    return;
                }
                let msg = match load_frame(&work[v], f) {
                    Ok(img) => Decoded::Frame(v, f, img),
                    Err(e) => Decoded::Failed(format!("{e:#}")),
                };
                // The receiver is gone when loading was abandoned; nothing to do then.
                let _ = tx.send(msg);
            });
        });
        Self {
            rx,
            cancel,
            sources,
            textures,
            total,
            uploaded: 0,
        }
    }

    /// Upload decoded frames for at most `budget` of this repaint.
    pub fn pump(&mut self, ctx: &Context, budget: Duration) -> LoadState {
        let t0 = Instant::now();
        while self.uploaded < self.total && t0.elapsed() < budget {
            match self.rx.recv_timeout(Duration::from_millis(2)) {
                Ok(Decoded::Frame(v, f, img)) => {
                    let image =
                        ColorImage::from_rgb([img.width as usize, img.height as usize], &img.rgb);
                    let name = format!("{}#{f}", self.sources[v].id);
                    self.textures[v][f] =
                        Some(ctx.load_texture(name, image, TextureOptions::NEAREST));
                    self.uploaded += 1;
                }
                Ok(Decoded::Failed(e)) => return LoadState::Failed(e),
                Err(_) => break,
            }
        }
        if self.uploaded == self.total {
            LoadState::Done
        } else {
            LoadState::Loading {
                fraction: self.uploaded as f32 / self.total.max(1) as f32,
            }
        }
    }

    /// Every frame is uploaded.
    pub fn is_done(&self) -> bool {
        self.uploaded == self.total
    }

    /// The loaded videos (call after [`LoadState::Done`]).
    pub fn into_videos(mut self) -> Vec<Video> {
        let sources = std::mem::take(&mut self.sources);
        let textures = std::mem::take(&mut self.textures);
        sources
            .into_iter()
            .zip(textures)
            .map(|(source, t)| Video {
                source,
                textures: t.into_iter().flatten().collect(),
            })
            .collect()
    }
}

impl Drop for Loader {
    fn drop(&mut self) {
        self.cancel.store(true, Ordering::Relaxed);
    }
}
