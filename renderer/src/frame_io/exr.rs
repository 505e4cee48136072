//! Linear HDR frames on disk: 32-bit float RGB EXR (lossless), the form in which references
//! (and, on request, every stimulus) keep radiance for the error metrics.

use anyhow::{Context, Result, ensure};
use std::path::Path;

/// Encode `pixels` (row-major, `width * height`) as EXR bytes. Non-finite values are written
/// as 0 so no NaN or infinity reaches a file.
pub fn exr_bytes(pixels: &[[f32; 3]], width: u32, height: u32) -> Result<Vec<u8>> {
    use exr::prelude::*;
    let (w, h) = (width as usize, height as usize);
    ensure!(
        pixels.len() == w * h,
        "frame holds {} pixels, expected {w}x{h}",
        pixels.len()
    );
    let clean = |v: f32| if v.is_finite() { v } else { 0.0 };
    let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
        let p = pixels[y * w + x];
        (clean(p[0]), clean(p[1]), clean(p[2]))
    });
    let image = Image::from_encoded_channels((w, h), Encoding::FAST_LOSSLESS, channels);
    let mut out = std::io::Cursor::new(Vec::new());
    image
        .write()
        .non_parallel()
        .to_buffered(&mut out)
        .context("cannot encode EXR")?;
    Ok(out.into_inner())
}

/// Read an RGB(A) EXR into row-major RGB with its size. The header's size is checked first
/// (at most [`crate::limits::MAX_MAP_TEXELS`] pixels): a corrupt or hostile header would
/// otherwise make the pixel buffer's allocation abort the process.
pub fn read_exr(path: &Path) -> Result<(Vec<[f32; 3]>, u32, u32)> {
    let meta = exr::meta::MetaData::read_from_file(path, false)
        .with_context(|| format!("cannot read EXR frame {}", path.display()))?;
    for h in &meta.headers {
        let (w, ht) = (h.layer_size.width(), h.layer_size.height());
        crate::limits::check_texels(w, ht)
            .with_context(|| format!("EXR frame {} is {w} x {ht} pixels", path.display()))?;
    }
    let image = exr::prelude::read_first_rgba_layer_from_file(
        path,
        |res, _| (vec![[0f32; 3]; res.width() * res.height()], res.width()),
        |(px, w): &mut (Vec<[f32; 3]>, usize), pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            px[pos.y() * *w + pos.x()] = [r, g, b];
        },
    )
    .with_context(|| format!("cannot read EXR frame {}", path.display()))?;
    let size = image.layer_data.size;
    let (pixels, _) = image.layer_data.channel_data.pixels;
    Ok((pixels, size.width() as u32, size.height() as u32))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_exactly_and_cleans_non_finite_values() {
        let (w, h) = (7u32, 3u32);
        let mut px: Vec<[f32; 3]> = (0..w * h)
            .map(|i| [i as f32 * 0.37, 1e4 + i as f32, -0.5])
            .collect();
        px[4] = [f32::NAN, f32::INFINITY, 1.0];
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("f.exr");
        std::fs::write(&path, exr_bytes(&px, w, h).unwrap()).unwrap();
        let (back, bw, bh) = read_exr(&path).unwrap();
        assert_eq!((bw, bh), (w, h));
        px[4] = [0.0, 0.0, 1.0];
        assert_eq!(back, px);
    }
}
