//! The display model: what a subject's eye receives from an 8-bit sRGB frame.
//!
//! Luminance L = L_black + (L_peak - L_black) Y, with Y the relative luminance of the pixel's
//! linear RGB (sRGB transfer function and Rec. 709 primaries, IEC 61966-2-1:
//! Y = 0.2126 R + 0.7152 G + 0.0722 B). This is the gain-offset-gamma display model that
//! visible-difference metrics use (e.g. FovVideoVDP, Mantiuk et al. 2021), without ambient
//! reflections (a dark room). Visual angle: the design's screen size, resolution and viewing
//! distance give pixels per degree at the screen's centre; the videos are shown at 1:1 pixel
//! scale (thesis Chapter IV), so a video pixel is a screen pixel.

use experiment::display::DisplaySpec;

/// A display ready to convert frames.
#[derive(Clone, Debug)]
pub struct Display {
    pub spec: DisplaySpec,
    pub pixels_per_degree: f64,
    /// Luminance of each 8-bit code for each channel's share: `lut[c][v]` with the channel's
    /// Rec. 709 weight folded in, so L = black + sum over channels.
    lut: [[f32; 256]; 3],
}

/// Rec. 709 / sRGB luminance weights of linear R, G, B.
pub const LUMA: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// The sRGB electro-optical transfer function: 8-bit code value to linear [0, 1].
pub fn srgb_to_linear(v: u8) -> f64 {
    let c = v as f64 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

impl Display {
    pub fn new(spec: &DisplaySpec) -> Self {
        let range = spec.peak_cd_m2 - spec.black_cd_m2;
        let mut lut = [[0f32; 256]; 3];
        for (c, table) in lut.iter_mut().enumerate() {
            for (v, e) in table.iter_mut().enumerate() {
                *e = (range * LUMA[c] * srgb_to_linear(v as u8)) as f32;
            }
        }
        Self {
            spec: spec.clone(),
            pixels_per_degree: spec.pixels_per_degree(),
            lut,
        }
    }

    /// Luminance (cd/m^2) of packed 8-bit sRGB pixels, row-major.
    pub fn luminance(&self, rgb: &[u8]) -> Vec<f32> {
        let black = self.spec.black_cd_m2 as f32;
        rgb.chunks_exact(3)
            .map(|p| {
                black
                    + self.lut[0][p[0] as usize]
                    + self.lut[1][p[1] as usize]
                    + self.lut[2][p[2] as usize]
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn white_is_peak_black_is_black_and_grey_follows_the_srgb_curve() {
        let d = Display::new(&DisplaySpec::default());
        let l = d.luminance(&[255, 255, 255, 0, 0, 0, 128, 128, 128, 255, 0, 0]);
        assert!((l[0] - 300.0).abs() < 1e-3);
        assert!((l[1] - 0.3).abs() < 1e-6);
        // sRGB 128 is 21.6% linear.
        let grey = 0.3 + 299.7 * ((128.0 / 255.0 + 0.055) / 1.055f64).powf(2.4);
        assert!((l[2] as f64 - grey).abs() < 1e-3, "{}", l[2]);
        assert!((l[3] as f64 - (0.3 + 299.7 * 0.2126)).abs() < 1e-3);
    }
}
