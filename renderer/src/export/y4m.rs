//! Uncompressed YUV4MPEG2 video (4:4:4, 8 bit), written by the project so that every stimulus
//! plays in mpv, VLC and ffmpeg without any codec installed.
//!
//! Y4M carries no colour matrix tag; ffmpeg treats such input as BT.601 and mpv guesses from
//! the frame size, so the default is BT.601 limited ("TV") range, the interpretation players
//! fall back to. BT.709 and full range are options; full range is tagged with
//! `XCOLORRANGE=FULL`, which ffmpeg reads.

use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};

/// The colour matrix turning R'G'B' into Y'CbCr.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Matrix {
    Bt601,
    Bt709,
}

/// Quantisation range of the 8-bit samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Range {
    /// Y in 16..235, Cb/Cr in 16..240 (the default of video players).
    Limited,
    /// Y, Cb, Cr in 0..255.
    Full,
}

/// How to encode the frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Y4mOptions {
    pub matrix: Matrix,
    pub range: Range,
}

impl Default for Y4mOptions {
    fn default() -> Self {
        Self {
            matrix: Matrix::Bt601,
            range: Range::Limited,
        }
    }
}

impl Matrix {
    /// Luma weights (Kr, Kb).
    fn weights(self) -> (f64, f64) {
        match self {
            Matrix::Bt601 => (0.299, 0.114),
            Matrix::Bt709 => (0.2126, 0.0722),
        }
    }
}

/// Convert one 8-bit R'G'B' pixel to 8-bit Y'CbCr.
pub fn rgb_to_ycbcr(rgb: [u8; 3], opts: Y4mOptions) -> [u8; 3] {
    let (kr, kb) = opts.matrix.weights();
    let [r, g, b] = rgb.map(|c| c as f64 / 255.0);
    let y = kr * r + (1.0 - kr - kb) * g + kb * b;
    let cb = (b - y) / (2.0 * (1.0 - kb));
    let cr = (r - y) / (2.0 * (1.0 - kr));
    let (ys, yo, cs) = match opts.range {
        Range::Limited => (219.0, 16.0, 224.0),
        Range::Full => (255.0, 0.0, 255.0),
    };
    let q = |v: f64| v.round().clamp(0.0, 255.0) as u8;
    [q(yo + ys * y), q(128.0 + cs * cb), q(128.0 + cs * cr)]
}

/// The stream header line (without the newline).
pub fn header(width: u32, height: u32, fps: f64, opts: Y4mOptions) -> String {
    let (num, den) = frame_rate_ratio(fps);
    let range = match opts.range {
        Range::Limited => "LIMITED",
        Range::Full => "FULL",
    };
    format!("YUV4MPEG2 W{width} H{height} F{num}:{den} Ip A1:1 C444 XCOLORRANGE={range}")
}

/// A frame rate as a reduced ratio; fractional rates keep three decimals (29.97 -> 2997:100).
pub fn frame_rate_ratio(fps: f64) -> (u64, u64) {
    let fps = if fps.is_finite() && fps > 0.0 {
        fps
    } else {
        30.0
    };
    let num = (fps * 1000.0).round() as u64;
    let g = gcd(num.max(1), 1000);
    (num.max(1) / g, 1000 / g)
}

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 { a } else { gcd(b, a % b) }
}

/// Write the PNG frames (in order) as one Y4M file, atomically.
pub fn write_y4m(frames: &[PathBuf], fps: f64, out: &Path, opts: Y4mOptions) -> Result<()> {
    let Some(first) = frames.first() else {
        bail!("no frames to write into {}", out.display());
    };
    let (w, h) = image::image_dimensions(first)
        .with_context(|| format!("cannot read frame {}", first.display()))?;
    crate::atomic::write_atomic_with(out, |wr| {
        writeln!(wr, "{}", header(w, h, fps, opts))?;
        let mut planes = vec![0u8; 3 * w as usize * h as usize];
        for path in frames {
            let img = image::open(path)
                .with_context(|| format!("cannot read frame {}", path.display()))?
                .to_rgb8();
            if img.dimensions() != (w, h) {
                bail!(
                    "frame {} is {}x{}, expected {w}x{h} like {}",
                    path.display(),
                    img.width(),
                    img.height(),
                    first.display()
                );
            }
            frame_planes(img.as_raw(), opts, &mut planes);
            wr.write_all(b"FRAME\n")?;
            wr.write_all(&planes)?;
        }
        Ok(())
    })
}

/// Planar Y, then Cb, then Cr, each `width * height` bytes, from packed RGB.
pub fn frame_planes(rgb: &[u8], opts: Y4mOptions, planes: &mut [u8]) {
    let n = rgb.len() / 3;
    for (i, px) in rgb.chunks_exact(3).enumerate() {
        let [y, cb, cr] = rgb_to_ycbcr([px[0], px[1], px[2]], opts);
        planes[i] = y;
        planes[n + i] = cb;
        planes[2 * n + i] = cr;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_colours_map_to_the_standard_codes() {
        let lim = Y4mOptions::default();
        assert_eq!(rgb_to_ycbcr([255, 255, 255], lim), [235, 128, 128]);
        assert_eq!(rgb_to_ycbcr([0, 0, 0], lim), [16, 128, 128]);
        // BT.601 red: Y = 16 + 219 * 0.299 = 81.48, Cr = 128 + 224 * 0.5 = 240.
        assert_eq!(rgb_to_ycbcr([255, 0, 0], lim), [81, 90, 240]);
        let full709 = Y4mOptions {
            matrix: Matrix::Bt709,
            range: Range::Full,
        };
        assert_eq!(rgb_to_ycbcr([255, 255, 255], full709), [255, 128, 128]);
        // BT.709 blue: Y = 255 * 0.0722 = 18.4, Cb = 128 + 127.5 -> clamped 255, Cr = 128 - 11.7.
        assert_eq!(rgb_to_ycbcr([0, 0, 255], full709), [18, 255, 116]);
    }

    #[test]
    fn frame_rates_reduce() {
        assert_eq!(frame_rate_ratio(30.0), (30, 1));
        assert_eq!(frame_rate_ratio(29.97), (2997, 100));
        assert_eq!(frame_rate_ratio(12.5), (25, 2));
        assert_eq!(frame_rate_ratio(f64::NAN), (30, 1));
    }

    #[test]
    fn file_has_header_then_planar_frames() {
        let dir = tempfile::tempdir().unwrap();
        let (w, h) = (5u32, 3u32);
        let mut paths = Vec::new();
        for f in 0..2u8 {
            let img = image::RgbImage::from_fn(w, h, |x, y| {
                image::Rgb([(x * 50) as u8, (y * 80) as u8, f * 200])
            });
            let p = dir.path().join(format!("frame_{f:04}.png"));
            img.save(&p).unwrap();
            paths.push(p);
        }
        let out = dir.path().join("v.y4m");
        let opts = Y4mOptions::default();
        write_y4m(&paths, 30.0, &out, opts).unwrap();
        let bytes = std::fs::read(&out).unwrap();
        let head = "YUV4MPEG2 W5 H3 F30:1 Ip A1:1 C444 XCOLORRANGE=LIMITED\n";
        assert!(bytes.starts_with(head.as_bytes()));
        let plane = (w * h) as usize;
        assert_eq!(bytes.len(), head.len() + 2 * (6 + 3 * plane));
        // Second frame, pixel (x=2, y=1): planes are Y then Cb then Cr, row-major.
        let frame1 = head.len() + (6 + 3 * plane) + 6;
        assert_eq!(&bytes[frame1 - 6..frame1], b"FRAME\n");
        let i = w as usize + 2; // row 1, column 2
        let expect = rgb_to_ycbcr([100, 80, 200], opts);
        let got = [
            bytes[frame1 + i],
            bytes[frame1 + plane + i],
            bytes[frame1 + 2 * plane + i],
        ];
        assert_eq!(got, expect);
    }

    #[test]
    fn mismatched_frame_sizes_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.png");
        let b = dir.path().join("b.png");
        image::RgbImage::new(4, 4).save(&a).unwrap();
        image::RgbImage::new(4, 5).save(&b).unwrap();
        let out = dir.path().join("v.y4m");
        let err = write_y4m(&[a, b], 30.0, &out, Y4mOptions::default()).unwrap_err();
        assert!(format!("{err:#}").contains("b.png"));
        assert!(!out.exists());
    }
}
