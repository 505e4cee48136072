//! Display frames on disk: 8-bit sRGB PNG, encoded with fixed settings so that the same
//! pixels always give the same bytes (manifests hash them).

use anyhow::{Context, Result};

/// Encode packed RGB as PNG bytes (deterministic: fixed encoder settings).
pub fn png_bytes(rgb: &[u8], width: u32, height: u32) -> Result<Vec<u8>> {
    use image::ImageEncoder;
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new(&mut out)
        .write_image(rgb, width, height, image::ExtendedColorType::Rgb8)
        .context("cannot encode PNG")?;
    Ok(out)
}
