//! Loading a trial's videos into GPU textures: frames are decoded (and made RGBA) on worker
//! threads in the order they are due ([`crate::stream::loading_order`]) and uploaded by the UI
//! thread in that order, a few per repaint, so the frames loaded are always a prefix of each
//! video and the trial can start before the last is in ([`crate::stream::can_start`]).
//! Textures use nearest filtering: a video pixel is a screen pixel.

use crate::frames::{VideoSource, load_frame};
use crate::stream::{self, Due};
use egui::{ColorImage, Context, TextureHandle, TextureOptions};
use std::collections::HashMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};
use std::time::{Duration, Instant};

/// Decoded frames waiting for the UI thread: bounds the memory they take (2.4 MB each at
/// 768 x 768) when uploads fall behind, e.g. while the prefetch waits for the answer screen.
const QUEUED_FRAMES: usize = 16;

/// A video held as one texture per frame: while loading, the first `textures.len()` frames.
pub struct Video {
    pub source: VideoSource,
    pub textures: Vec<TextureHandle>,
}

enum Decoded {
    Frame(usize, usize, ColorImage),
    Failed(String),
}

/// Loading some videos.
pub struct Loader {
    rx: Receiver<Decoded>,
    cancel: Arc<AtomicBool>,
    videos: Vec<Video>,
    order: Arc<Vec<Due>>,
    /// Frames decoded ahead of their turn, held until those before them are uploaded.
    waiting: HashMap<(usize, usize), ColorImage>,
    uploaded: usize,
    started: Instant,
}

/// Where loading stands.
pub enum LoadState {
    Loading { fraction: f32 },
    Failed(String),
    Done,
}

/// How much one repaint may upload.
#[derive(Clone, Copy, Debug)]
pub struct Budget {
    pub time: Duration,
    pub frames: usize,
}

impl Loader {
    /// Start decoding every frame of `sources`, first shown `starts[v]` seconds after the
    /// trial's start, in the background.
    pub fn start(sources: Vec<VideoSource>, starts: &[f64]) -> Self {
        let frames: Vec<usize> = sources.iter().map(|s| s.frame_paths.len()).collect();
        let fps = sources.first().map_or(30.0, |s| s.fps);
        let order = Arc::new(stream::loading_order(starts, &frames, fps));
        let (tx, rx) = sync_channel(QUEUED_FRAMES);
        let cancel = Arc::new(AtomicBool::new(false));
        let next = Arc::new(AtomicUsize::new(0));
        let work = Arc::new(sources.clone());
        let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
        for _ in 0..threads.min(order.len()) {
            let (tx, stop) = (tx.clone(), cancel.clone());
            let (work, order, next) = (work.clone(), order.clone(), next.clone());
            std::thread::spawn(move || decode_jobs(&work, &order, &next, &stop, &tx));
        }
        Self {
            rx,
            cancel,
            videos: sources
                .into_iter()
                .map(|source| Video {
                    source,
                    textures: Vec::new(),
                })
                .collect(),
            order,
            waiting: HashMap::new(),
            uploaded: 0,
            started: Instant::now(),
        }
    }

    /// Upload decoded frames, in the loading order, within `budget`.
    pub fn pump(&mut self, ctx: &Context, budget: Budget) -> LoadState {
        let t0 = Instant::now();
        let mut n = 0;
        while !self.is_done() && n < budget.frames && t0.elapsed() < budget.time {
            let Due {
                video: v, frame: f, ..
            } = self.order[self.uploaded];
            if let Some(image) = self.waiting.remove(&(v, f)) {
                let name = format!("{}#{f}", self.videos[v].source.id);
                let texture = ctx.load_texture(name, image, TextureOptions::NEAREST);
                self.videos[v].textures.push(texture);
                self.uploaded += 1;
                n += 1;
                continue;
            }
            match self.rx.recv_timeout(Duration::from_millis(2)) {
                Ok(Decoded::Frame(v, f, image)) => {
                    self.waiting.insert((v, f), image);
                }
                Ok(Decoded::Failed(e)) => return LoadState::Failed(e),
                Err(_) => break,
            }
        }
        if self.is_done() {
            LoadState::Done
        } else {
            LoadState::Loading {
                fraction: self.uploaded as f32 / self.order.len().max(1) as f32,
            }
        }
    }

    /// Every frame is uploaded.
    pub fn is_done(&self) -> bool {
        self.uploaded == self.order.len()
    }

    /// Frames of stimulus `id` uploaded, if this loader loads it.
    pub fn loaded(&self, id: &str) -> Option<u32> {
        let v = self.videos.iter().find(|v| v.source.id == id)?;
        Some(v.textures.len() as u32)
    }

    /// Whether the trial may start now, at the rate frames came in so far.
    pub fn can_start(&self) -> bool {
        let rate = self.uploaded as f64 / self.started.elapsed().as_secs_f64();
        stream::can_start(&self.order, self.uploaded, rate)
    }

    /// The videos being loaded, each with the frames uploaded so far.
    pub fn videos(&self) -> &[Video] {
        &self.videos
    }

    /// The loaded videos (call after [`LoadState::Done`]).
    pub fn into_videos(mut self) -> Vec<Video> {
        std::mem::take(&mut self.videos)
    }
}

impl Drop for Loader {
    fn drop(&mut self) {
        self.cancel.store(true, Ordering::Relaxed);
    }
}

/// One worker: take the next frame in order until none is left, loading is abandoned or the
/// receiver is gone.
fn decode_jobs(
    sources: &[VideoSource],
    order: &[Due],
    next: &AtomicUsize,
    stop: &AtomicBool,
    tx: &SyncSender<Decoded>,
) {
    while !stop.load(Ordering::Relaxed) {
        let Some(&Due {
            video: v, frame: f, ..
        }) = order.get(next.fetch_add(1, Ordering::Relaxed))
        else {
            return;
        };
        let msg = match load_frame(&sources[v], f) {
            Ok(img) => Decoded::Frame(
                v,
                f,
                ColorImage::from_rgb([img.width as usize, img.height as usize], &img.rgb),
            ),
            Err(e) => Decoded::Failed(format!("{e:#}")),
        };
        if tx.send(msg).is_err() {
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixture::{StudySpec, write_study};
    use egui::epaint::ImageData;
    use renderer::manifest::Manifest;

    /// Two videos of 12 frames of a small rendered study.
    fn sources(dir: &std::path::Path) -> Vec<VideoSource> {
        let spec = StudySpec {
            scenes: vec!["alpha".into()],
            point_sets: vec!["random".into()],
            frames: 12,
            ..StudySpec::tiny()
        };
        let study = write_study(dir, &spec).unwrap();
        let path = study.stimuli_dir.join("manifest.json");
        let manifest = Manifest::load(&path).unwrap();
        manifest.stimuli[..2]
            .iter()
            .map(|s| VideoSource::from_manifest(&manifest, &path, &s.id).unwrap())
            .collect()
    }

    /// Pumped one frame per repaint, frames come in the order they are due (both videos from
    /// the start: frame by frame; the second shown later: after the first), and each texture
    /// holds exactly its own decoded frame.
    #[test]
    fn each_texture_holds_its_own_frame_in_the_order_they_are_due() {
        let dir = tempfile::tempdir().unwrap();
        let s = sources(dir.path());
        // The frames differ, so a frame uploaded in another's place would be seen.
        assert_ne!(
            load_frame(&s[0], 0).unwrap(),
            load_frame(&s[0], 11).unwrap()
        );
        for second in [0.0, 100.0] {
            let (loader, uploaded, counts) = load_all(&s, &[0.0, second]);
            for (a, b) in counts {
                if second == 0.0 {
                    assert!(a == b || a == b + 1, "{a} {b}");
                } else {
                    assert!(b == 0 || a == 12, "{a} {b}");
                }
            }
            for (source, video) in s.iter().zip(loader.into_videos()) {
                assert_eq!(video.textures.len(), source.frame_paths.len());
                for (f, t) in video.textures.iter().enumerate() {
                    let rgb = load_frame(source, f).unwrap();
                    let size = [rgb.width as usize, rgb.height as usize];
                    let want = ColorImage::from_rgb(size, &rgb.rgb);
                    assert_eq!(*uploaded[&t.id()], want, "{} frame {f}", source.id);
                }
            }
        }
    }

    type Images = HashMap<egui::TextureId, Arc<ColorImage>>;

    /// Load `s` one frame per repaint: the finished loader, every uploaded image by texture,
    /// and the frames of videos 0 and 1 in after each repaint.
    fn load_all(s: &[VideoSource], starts: &[f64]) -> (Loader, Images, Vec<(u32, u32)>) {
        let ctx = Context::default();
        let mut loader = Loader::start(s.to_vec(), starts);
        let one = Budget {
            time: Duration::from_secs(1),
            frames: 1,
        };
        let (mut uploaded, mut counts) = (HashMap::new(), Vec::new());
        for _ in 0..1000 {
            let mut state = None;
            let mut out = ctx.run_ui(Default::default(), |_| state = Some(loader.pump(&ctx, one)));
            for (id, deltas) in &out.textures_delta.set {
                for delta in deltas {
                    let ImageData::Color(image) = &delta.image;
                    uploaded.insert(*id, image.clone());
                }
            }
            out.textures_delta.clear();
            let count = |v: usize| loader.loaded(&s[v].id).unwrap();
            counts.push((count(0), count(1)));
            match state.unwrap() {
                LoadState::Done => return (loader, uploaded, counts),
                LoadState::Failed(e) => panic!("{e}"),
                LoadState::Loading { .. } => {}
            }
        }
        panic!("never loaded");
    }
}
