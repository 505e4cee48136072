//! The display a study is shown on (the design's optional `display` block): what the
//! prediction of visibility (`blurlab predict`) needs to turn pixels into luminance and visual
//! angle. The defaults are the thesis's monitor, a Dell U2311H (23-inch diagonal, 1920x1080,
//! thesis Chapter IV) with the manufacturer's typical peak luminance (300 cd/m^2) and contrast
//! ratio (1000:1, so black 0.3 cd/m^2), seen from 0.7 m: the thesis gives no viewing distance,
//! and 0.7 m is the one the manifest's FLIP error is measured at (FLIP's own default, hard-coded
//! in `renderer::metrics`), so the prediction and the stored error see the same display (about
//! 46 pixels per degree on that monitor).

use anyhow::{Result, bail};
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct DisplaySpec {
    /// Screen diagonal in inches.
    pub diagonal_inches: f64,
    /// Screen resolution in pixels (the whole screen, not the video).
    pub resolution: [u32; 2],
    /// Eye to screen, metres.
    pub distance_m: f64,
    /// Luminance of white (sRGB 255, 255, 255), cd/m^2.
    pub peak_cd_m2: f64,
    /// Luminance of black (sRGB 0, 0, 0) in the dark room, cd/m^2.
    pub black_cd_m2: f64,
}

impl Default for DisplaySpec {
    fn default() -> Self {
        Self {
            diagonal_inches: 23.0,
            resolution: [1920, 1080],
            distance_m: 0.7,
            peak_cd_m2: 300.0,
            black_cd_m2: 0.3,
        }
    }
}

impl DisplaySpec {
    /// Pixel pitch in metres (square pixels).
    pub fn pixel_pitch_m(&self) -> f64 {
        let [w, h] = self.resolution.map(f64::from);
        self.diagonal_inches * 0.0254 / w.hypot(h)
    }

    /// Pixels per degree of visual angle at the screen's centre: one degree spans
    /// 2 d tan(0.5 deg) metres there.
    pub fn pixels_per_degree(&self) -> f64 {
        2.0 * self.distance_m * (0.5f64.to_radians()).tan() / self.pixel_pitch_m()
    }

    /// Every field in range; messages name the field (`display.<field>`).
    pub fn validate(&self) -> Result<()> {
        let positive = [
            ("diagonal_inches", self.diagonal_inches),
            ("distance_m", self.distance_m),
            ("peak_cd_m2", self.peak_cd_m2),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                bail!(
                    "field `display.{name}` is {}; expected a positive number",
                    renderer::limits::shortest(v)
                );
            }
        }
        if self.resolution.contains(&0) {
            bail!(
                "field `display.resolution` is {:?}; expected [width, height] in pixels",
                self.resolution
            );
        }
        if !(self.black_cd_m2.is_finite()
            && self.black_cd_m2 >= 0.0
            && self.black_cd_m2 < self.peak_cd_m2)
        {
            bail!(
                "field `display.black_cd_m2` is {}; expected 0 <= black < peak ({})",
                renderer::limits::shortest(self.black_cd_m2),
                renderer::limits::shortest(self.peak_cd_m2)
            );
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thesis_monitor_geometry() {
        let d = DisplaySpec::default();
        // The U2311H's published pixel pitch is 0.265 mm.
        assert!((d.pixel_pitch_m() * 1e3 - 0.265).abs() < 0.001);
        // 0.7 m: 2 * 700 mm * tan(0.5 deg) / 0.2652 mm = 46.1 px per degree.
        assert!(
            (d.pixels_per_degree() - 46.1).abs() < 0.1,
            "{}",
            d.pixels_per_degree()
        );
        d.validate().unwrap();
        let bad = DisplaySpec {
            black_cd_m2: 400.0,
            ..d
        };
        assert!(
            bad.validate()
                .unwrap_err()
                .to_string()
                .contains("display.black_cd_m2")
        );
    }
}
