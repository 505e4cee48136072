//! Loading a trial's videos into GPU textures: frames are decoded (and made RGBA) on worker threads
//! in the order they are due ([`crate::playback::stream::loading_order`]) and uploaded by the UI
//! thread in that order, a few per repaint, so the frames loaded are always a prefix of each video
//! and the trial can start before the last is in ([`crate::playback::stream::can_start`]). Frames
//! come from a [`FrameStore`] (the stimulus folder, or memory). Textures use nearest filtering: a
//! video pixel is a screen pixel.

use crate::playback::frame_store::{FrameStore, StoredVideo};
use crate::playback::stream::{self, Due};
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
    pub source: StoredVideo,
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
    /// Start decoding every frame of `sources` from `store`, first shown `starts[v]` seconds
    /// after the trial's start, in the background.
    pub fn start(store: Arc<dyn FrameStore>, sources: Vec<StoredVideo>, starts: &[f64]) -> Self {
        let frames: Vec<usize> = sources.iter().map(|s| s.frames as usize).collect();
        let fps = sources.first().map_or(30.0, |s| s.fps);
        let order = Arc::new(stream::loading_order(starts, &frames, fps));
        let (tx, rx) = sync_channel(QUEUED_FRAMES);
        let cancel = Arc::new(AtomicBool::new(false));
        let next = Arc::new(AtomicUsize::new(0));
        let ids: Arc<Vec<String>> = Arc::new(sources.iter().map(|s| s.id.clone()).collect());
        let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
        for _ in 0..threads.min(order.len()) {
            let (tx, stop) = (tx.clone(), cancel.clone());
            let (store, ids) = (store.clone(), ids.clone());
            let (order, next) = (order.clone(), next.clone());
            std::thread::spawn(move || decode_jobs(&*store, &ids, &order, &next, &stop, &tx));
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
    store: &dyn FrameStore,
    ids: &[String],
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
        let msg = match store.frame(&ids[v], f) {
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
    use crate::playback::frame_store::{FrameDir, MemoryFrames};
    use crate::playback::frames::RgbFrame;
    use egui::epaint::ImageData;
    use renderer::manifest::Manifest;

    /// The first two stimuli of a small rendered study (12 frames each), from its folder.
    fn folder(dir: &std::path::Path) -> (Arc<dyn FrameStore>, Vec<StoredVideo>) {
        let spec = StudySpec {
            scenes: vec!["alpha".into()],
            point_sets: vec!["random".into()],
            frames: 12,
            ..StudySpec::tiny()
        };
        let study = write_study(dir, &spec).unwrap();
        let path = study.stimuli_dir.join("manifest.json");
        let manifest = Manifest::load(&path).unwrap();
        let ids: Vec<String> = manifest.stimuli[..2].iter().map(|s| s.id.clone()).collect();
        let store = FrameDir::new(manifest, path);
        let videos = ids.iter().map(|id| store.video(id).unwrap()).collect();
        (Arc::new(store), videos)
    }

    /// Two made-up videos of 12 frames of 5 x 3 pixels in memory: no file anywhere.
    fn memory() -> (Arc<dyn FrameStore>, Vec<StoredVideo>) {
        let mut store = MemoryFrames::new();
        for (v, id) in ["a-0001", "a-0512"].iter().enumerate() {
            let frames = (0..12u8)
                .map(|f| RgbFrame {
                    width: 5,
                    height: 3,
                    rgb: (0..45u8).map(|i| i ^ (f << 2) ^ (v as u8 * 0x80)).collect(),
                })
                .collect();
            store.insert(id, 30.0, frames).unwrap();
        }
        let videos = ["a-0001", "a-0512"].map(|id| store.video(id).unwrap());
        (Arc::new(store), videos.to_vec())
    }

    /// Pumped one frame per repaint, frames come in the order they are due (both videos from
    /// the start: frame by frame; the second shown later: after the first), and each texture
    /// holds exactly its own decoded frame.
    fn each_texture_holds_its_own_frame(store: Arc<dyn FrameStore>, s: &[StoredVideo]) {
        // The frames differ, so a frame uploaded in another's place would be seen.
        assert_ne!(
            store.frame(&s[0].id, 0).unwrap(),
            store.frame(&s[0].id, 11).unwrap()
        );
        for second in [0.0, 100.0] {
            let (loader, uploaded, counts) = load_all(&store, s, &[0.0, second]);
            for (a, b) in counts {
                if second == 0.0 {
                    assert!(a == b || a == b + 1, "{a} {b}");
                } else {
                    assert!(b == 0 || a == 12, "{a} {b}");
                }
            }
            for (source, video) in s.iter().zip(loader.into_videos()) {
                assert_eq!(video.textures.len(), source.frames as usize);
                for (f, t) in video.textures.iter().enumerate() {
                    let rgb = store.frame(&source.id, f).unwrap();
                    let size = [rgb.width as usize, rgb.height as usize];
                    let want = ColorImage::from_rgb(size, &rgb.rgb);
                    assert_eq!(*uploaded[&t.id()], want, "{} frame {f}", source.id);
                }
            }
        }
    }

    #[test]
    fn each_texture_holds_its_own_frame_in_the_order_they_are_due() {
        let dir = tempfile::tempdir().unwrap();
        let (store, videos) = folder(dir.path());
        each_texture_holds_its_own_frame(store, &videos);
    }

    /// The same loader from frames in memory: no stimulus folder.
    #[test]
    fn frames_in_memory_load_like_frames_on_disk() {
        let (store, videos) = memory();
        each_texture_holds_its_own_frame(store, &videos);
    }

    /// A frame the store cannot give fails the load with the store's message.
    #[test]
    fn a_missing_frame_fails_the_load_by_name() {
        let (store, mut videos) = memory();
        videos[1].frames = 13;
        let ctx = Context::default();
        let mut loader = Loader::start(store, videos, &[0.0, 0.0]);
        for _ in 0..1000 {
            let mut state = None;
            let mut out = ctx.run_ui(Default::default(), |_| {
                state = Some(loader.pump(&ctx, UNLIMITED))
            });
            out.textures_delta.clear();
            match state.unwrap() {
                LoadState::Failed(e) => {
                    assert!(e.contains("\"a-0512\" has 12 frames, not frame 12"), "{e}");
                    return;
                }
                LoadState::Done => panic!("loaded a frame the store lacks"),
                LoadState::Loading { .. } => {}
            }
        }
        panic!("never failed");
    }

    const UNLIMITED: Budget = Budget {
        time: Duration::from_secs(1),
        frames: usize::MAX,
    };

    type Images = HashMap<egui::TextureId, Arc<ColorImage>>;

    /// Load `s` one frame per repaint: the finished loader, every uploaded image by texture,
    /// and the frames of videos 0 and 1 in after each repaint.
    fn load_all(
        store: &Arc<dyn FrameStore>,
        s: &[StoredVideo],
        starts: &[f64],
    ) -> (Loader, Images, Vec<(u32, u32)>) {
        let ctx = Context::default();
        let mut loader = Loader::start(store.clone(), s.to_vec(), starts);
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
