//! The film: one linear HDR value per pixel (the mean of its samples, each sample one (u, v, t)
//! point), and its two outputs — 8-bit sRGB for display (exposure, then clamp to [0, 1], then
//! the sRGB curve) and 32-bit float linear values (after exposure) for measurement.

use glam::Vec3;

/// One rendered frame in both forms.
#[derive(Clone, Debug)]
pub struct RenderedFrame {
    /// Linear HDR radiance after exposure, row-major.
    pub linear: Vec<[f32; 3]>,
    /// 8-bit sRGB display values, packed RGB, row-major.
    pub display: Vec<u8>,
}

/// Display encoding of a linear value: clamp to [0, 1], then the sRGB transfer curve, rounded
/// to 8 bits (the film's, and the synthetic test source's).
pub fn srgb8(linear: f32) -> u8 {
    let c = if linear.is_finite() {
        linear.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let s = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    /// Mean radiance per pixel, row-major from the top-left corner.
    pub pixels: Vec<Vec3>,
}

impl Film {
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            pixels: vec![Vec3::ZERO; width as usize * height as usize],
        }
    }

    /// Linear values after `exposure` and the display frame made from them.
    pub fn develop(&self, exposure: f32) -> RenderedFrame {
        let linear: Vec<[f32; 3]> = self
            .pixels
            .iter()
            .map(|p| (*p * exposure).to_array())
            .collect();
        let display = linear.iter().flat_map(|p| p.map(srgb8)).collect();
        RenderedFrame { linear, display }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn develop_applies_exposure_then_clamp_then_srgb() {
        let mut f = Film::new(3, 1);
        f.pixels = vec![
            Vec3::new(0.5, 2.0, 0.0),
            Vec3::splat(0.107),
            Vec3::splat(100.0),
        ];
        let r = f.develop(2.0);
        assert_eq!(r.linear[0], [1.0, 4.0, 0.0]);
        assert_eq!(&r.display[0..3], &[255, 255, 0]);
        // 0.107 * 2 = 0.214: sRGB mid grey (128).
        assert!((r.display[3] as i32 - 128).abs() <= 1);
        assert_eq!(r.linear[2], [200.0; 3], "linear values are not clamped");
    }
}
