//! Encoded videos for browsers (issue 48): each stimulus's frames as lossless WebP, one file per
//! video (the frames' WebP files back to back, a "frame pack"), encoded once and kept beside the
//! stimulus set in `<set>/web/`, so that every session and every server reuses them. The lab app
//! and every other command keep reading the PNG frames; nothing here changes them.
//!
//! A pack is self-delimiting: every WebP file starts with `RIFF`, its length and `WEBP`, so a
//! client finds frame `n` by walking the RIFF headers (`experiment/web/videos.js`). Each frame is
//! checked after encoding: decoded again, its pixels must equal the PNG's, or nothing is written.

use crate::playback::frames::{RgbFrame, VideoSource, decode_png};
use anyhow::{Context, Result, bail};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The cache's folder name inside a stimulus set (beside `manifest.json`).
pub const CACHE_DIR: &str = "web";
/// A pack's file name ending.
pub const PACK_EXT: &str = "webpframes";
const INDEX: &str = "index.json";
const FORMAT: &str = "blurlab-web-videos/1";

/// One encoded video as the cache's index records it.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Pack {
    /// File name inside the cache folder.
    pub file: String,
    pub bytes: u64,
    /// SHA-256 of the pack's bytes (hex): names it in exports, checks it after a copy.
    pub sha256: String,
    pub frames: u32,
    pub width: u32,
    pub height: u32,
    /// Bytes of the source PNG frames, for the before/after figures.
    pub png_bytes: u64,
    /// What the PNG frames were when encoded (names, sizes, modification times): a re-rendered
    /// stimulus is encoded again.
    pub source: String,
}

#[derive(Clone, Debug, Default, Serialize, Deserialize)]
struct Index {
    format: String,
    videos: BTreeMap<String, Pack>,
}

/// The encoded videos of one stimulus set.
#[derive(Clone, Debug)]
pub struct Cache {
    pub dir: PathBuf,
    index: Index,
}

/// What [`Cache::ensure`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Encoded {
    pub encoded: usize,
    pub reused: usize,
}

impl Cache {
    /// The cache of the stimulus set whose manifest is at `manifest_path` (read if present).
    pub fn open(manifest_path: &Path) -> Result<Self> {
        let set = renderer::manifest::manifest_file(manifest_path)
            .parent()
            .unwrap_or(Path::new(""))
            .to_path_buf();
        let dir = set.join(CACHE_DIR);
        let path = dir.join(INDEX);
        let index = match std::fs::read_to_string(&path) {
            Ok(text) => match serde_json::from_str::<Index>(&text) {
                Ok(i) if i.format == FORMAT => i,
                // Another version's or a damaged index: encode again, never fail the server.
                _ => Index::default(),
            },
            Err(_) => Index::default(),
        };
        Ok(Self { dir, index })
    }

    /// The pack of stimulus `id`, if encoded from its current frames.
    pub fn get(&self, id: &str) -> Option<&Pack> {
        self.index.videos.get(id)
    }

    /// The path of a pack.
    pub fn path(&self, pack: &Pack) -> PathBuf {
        self.dir.join(&pack.file)
    }

    /// Encode every video of `videos` whose pack is missing or older than its frames; `progress`
    /// is told each stimulus as it starts. The index is rewritten (atomically) after each one,
    /// so a killed run keeps what it finished.
    pub fn ensure(
        &mut self,
        videos: &[VideoSource],
        progress: &mut dyn FnMut(usize, usize, &str),
    ) -> Result<Encoded> {
        let mut done = Encoded::default();
        for (k, v) in videos.iter().enumerate() {
            let source = fingerprint(v)?;
            let fresh = self.index.videos.get(&v.id).is_some_and(|p| {
                p.source == source
                    && std::fs::metadata(self.path(p)).is_ok_and(|m| m.len() == p.bytes)
            });
            if fresh {
                done.reused += 1;
                continue;
            }
            progress(k, videos.len(), &v.id);
            let (bytes, png_bytes) = encode_video(v)?;
            let file = format!("{}.{PACK_EXT}", file_stem(&v.id));
            let pack = Pack {
                bytes: bytes.len() as u64,
                sha256: hex(&Sha256::digest(&bytes)),
                frames: v.frames(),
                width: v.width,
                height: v.height,
                png_bytes,
                source,
                file,
            };
            renderer::atomic::write_atomic(&self.path(&pack), &bytes)?;
            self.index.format = FORMAT.into();
            self.index.videos.insert(v.id.clone(), pack);
            let text = serde_json::to_string_pretty(&self.index)?;
            renderer::atomic::write_atomic(&self.dir.join(INDEX), text.as_bytes())?;
            done.encoded += 1;
        }
        Ok(done)
    }
}

/// A stimulus id as a file name: kept when it is letters, digits, `-`, `_` and `.`, else hashed.
fn file_stem(id: &str) -> String {
    let plain = !id.is_empty()
        && !id.starts_with('.')
        && id
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b"-_.".contains(&b));
    if plain {
        id.to_string()
    } else {
        hex(&Sha256::digest(id.as_bytes())[..16])
    }
}

pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Names, sizes and modification times of a video's frame files and the encoder's settings,
/// hashed: a pack is reused only for the same frames encoded the same way.
fn fingerprint(v: &VideoSource) -> Result<String> {
    let mut h = Sha256::new();
    h.update(format!("libwebp lossless method {METHOD} quality {QUALITY}").as_bytes());
    for p in &v.frame_paths {
        let m = std::fs::metadata(p).with_context(|| format!("cannot read {}", p.display()))?;
        let mtime = m
            .modified()
            .ok()
            .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
            .map_or(0, |d| d.as_nanos());
        h.update(p.to_string_lossy().as_bytes());
        h.update(m.len().to_le_bytes());
        h.update(mtime.to_le_bytes());
    }
    Ok(hex(&h.finalize()))
}

/// A video's frames as one pack, and the PNGs' total size. Frames are encoded in parallel.
fn encode_video(v: &VideoSource) -> Result<(Vec<u8>, u64)> {
    let frames: Vec<(Vec<u8>, u64)> = v
        .frame_paths
        .par_iter()
        .map(|path| {
            let png = std::fs::metadata(path).map_or(0, |m| m.len());
            let frame = decode_png(path, v.width, v.height, &v.id)?;
            let webp = encode_frame(&frame)
                .with_context(|| format!("{}: cannot encode as WebP", path.display()))?;
            Ok((webp, png))
        })
        .collect::<Result<_>>()?;
    let total = frames.iter().map(|(w, _)| w.len()).sum();
    let mut out = Vec::with_capacity(total);
    let mut png_bytes = 0;
    for (webp, png) in frames {
        out.extend_from_slice(&webp);
        png_bytes += png;
    }
    Ok((out, png_bytes))
}

/// libwebp's lossless effort, as `cwebp -lossless -z 3` (method 3, quality 30): on thesis
/// frames 32-44% smaller than the PNG at 0.14 s a frame; higher levels gain under 1% for up to
/// 200 times the time (docs/benchmarks/web.md).
const METHOD: i32 = 3;
const QUALITY: f32 = 30.0;

/// One frame as lossless WebP (libwebp), checked: decoded again by an independent decoder (the
/// `image` crate's), every byte must equal the frame's.
pub fn encode_frame(frame: &RgbFrame) -> Result<Vec<u8>> {
    let mut config =
        webp::WebPConfig::new().map_err(|_| anyhow::anyhow!("libwebp refused its defaults"))?;
    config.lossless = 1;
    config.exact = 1;
    config.method = METHOD;
    config.quality = QUALITY;
    let out = webp::Encoder::from_rgb(&frame.rgb, frame.width, frame.height)
        .encode_advanced(&config)
        .map_err(|e| anyhow::anyhow!("libwebp: {e:?}"))?
        .to_vec();
    let back = image::load_from_memory_with_format(&out, image::ImageFormat::WebP)?.into_rgb8();
    if back.dimensions() != (frame.width, frame.height) || back.as_raw() != &frame.rgb {
        bail!("the WebP encoder did not round-trip the frame exactly");
    }
    Ok(out)
}

/// The frames of a pack: byte ranges of its WebP files, found by walking the RIFF headers (as
/// the browser client does). Fails on anything that is not a whole sequence of WebP files.
pub fn split(pack: &[u8]) -> Result<Vec<std::ops::Range<usize>>> {
    let mut out = Vec::new();
    let mut at = 0;
    while at < pack.len() {
        let head = pack
            .get(at..at + 12)
            .context("a frame pack ends inside a header")?;
        if &head[0..4] != b"RIFF" || &head[8..12] != b"WEBP" {
            bail!("byte {at} of a frame pack does not start a WebP file");
        }
        let size = u32::from_le_bytes([head[4], head[5], head[6], head[7]]) as usize;
        let end = at + 8 + size + (size & 1);
        if end > pack.len() {
            bail!("the WebP file at byte {at} runs past the frame pack's end");
        }
        out.push(at..end);
        at = end;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn noisy(width: u32, height: u32, seed: u32) -> RgbFrame {
        let mut x = seed.wrapping_mul(2654435761).max(1);
        let rgb = (0..width * height * 3)
            .map(|_| {
                x ^= x << 13;
                x ^= x >> 17;
                x ^= x << 5;
                (x >> 24) as u8
            })
            .collect();
        RgbFrame { width, height, rgb }
    }

    #[test]
    fn a_pack_splits_into_its_frames_and_each_decodes_to_the_same_pixels() {
        // Odd sizes too: a RIFF chunk of odd length is padded, which the walk must skip.
        let frames: Vec<RgbFrame> = (0..5).map(|k| noisy(7 + k, 3 + 2 * k, k + 1)).collect();
        let mut pack = Vec::new();
        for f in &frames {
            pack.extend(encode_frame(f).unwrap());
        }
        let ranges = split(&pack).unwrap();
        assert_eq!(ranges.len(), frames.len());
        for (r, f) in ranges.iter().zip(&frames) {
            let img =
                image::load_from_memory_with_format(&pack[r.clone()], image::ImageFormat::WebP)
                    .unwrap()
                    .into_rgb8();
            assert_eq!(img.dimensions(), (f.width, f.height));
            assert_eq!(img.as_raw(), &f.rgb);
        }
    }

    #[test]
    fn a_damaged_pack_is_refused() {
        let mut pack = encode_frame(&noisy(4, 4, 9)).unwrap();
        assert!(split(&pack[..pack.len() - 1]).is_err(), "cut short");
        pack[0] = b'X';
        assert!(split(&pack).is_err(), "not RIFF");
        assert!(split(&[]).unwrap().is_empty());
    }

    #[test]
    fn packs_are_reused_until_a_frame_changes_and_hold_the_pngs_pixels() {
        let dir = tempfile::tempdir().unwrap();
        let study =
            crate::fixture::write_study(dir.path(), &crate::fixture::StudySpec::tiny()).unwrap();
        let design = crate::Design::load(&study.design_path).unwrap();
        let videos = crate::web::study::sources(&design).unwrap();
        let mut cache = Cache::open(&design.manifest_path).unwrap();
        let first = cache.ensure(&videos, &mut |_, _, _| {}).unwrap();
        assert_eq!((first.encoded, first.reused), (videos.len(), 0));
        let again = Cache::open(&design.manifest_path)
            .unwrap()
            .ensure(&videos, &mut |_, _, _| {})
            .unwrap();
        assert_eq!((again.encoded, again.reused), (0, videos.len()));
        // A re-rendered frame (a new modification time) is encoded again; the pack holds it.
        let v = &videos[0];
        let later = std::time::SystemTime::now() + std::time::Duration::from_secs(5);
        std::fs::File::options()
            .write(true)
            .open(&v.frame_paths[2])
            .unwrap()
            .set_modified(later)
            .unwrap();
        let mut cache = Cache::open(&design.manifest_path).unwrap();
        let after = cache.ensure(&videos, &mut |_, _, _| {}).unwrap();
        assert_eq!((after.encoded, after.reused), (1, videos.len() - 1));
        let pack = cache.get(&v.id).unwrap();
        let bytes = std::fs::read(cache.path(pack)).unwrap();
        assert_eq!(pack.bytes, bytes.len() as u64);
        let ranges = split(&bytes).unwrap();
        assert_eq!(ranges.len(), v.frame_paths.len());
        for (r, path) in ranges.iter().zip(&v.frame_paths) {
            let got = image::load_from_memory(&bytes[r.clone()])
                .unwrap()
                .into_rgb8();
            let want = image::open(path).unwrap().into_rgb8();
            assert_eq!(got.as_raw(), want.as_raw(), "{}", path.display());
        }
    }

    #[test]
    fn file_stems_are_plain_or_hashed() {
        assert_eq!(file_stem("plane_hammersley_1"), "plane_hammersley_1");
        assert_eq!(file_stem("../x").len(), 32);
        assert_eq!(file_stem(".hidden").len(), 32);
    }
}
