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
use std::ops::RangeInclusive;

/// Pixels per degree a prediction accepts. The observer's filters grow with it (a design at
/// 1e308 m ran for minutes); 2,000 is 40 times the thesis's 46 and beyond any screen a subject
/// sits at.
pub const PIXELS_PER_DEGREE: RangeInclusive<f64> = 1.0..=2000.0;

// What a browser measures of a subject's display, and the range each fact must lie in (issue
// 51): `blurlab serve` refuses facts outside, and `blurlab predict --viewer` a log holding them.
// The ranges hold every real setting with room and no nonsense: a device pixel ratio from a
// zoomed-out desktop to a phone; device pixels per millimetre from a 0.8 mm-pitch wall display to
// a 1,000 dpi phone; eye to screen from a hand-held phone to across a room; a refresh interval
// from a 500 Hz gaming monitor to a 10 Hz stall.
pub const DEVICE_PIXEL_RATIO: RangeInclusive<f64> = 0.25..=8.0;
pub const PX_PER_MM: RangeInclusive<f64> = 1.0..=40.0;
pub const VIEWING_DISTANCE_MM: RangeInclusive<f64> = 100.0..=3000.0;
pub const REFRESH_INTERVAL_MS: RangeInclusive<f64> = 2.0..=100.0;

/// How far the browser's own `pixels_per_degree` may lie from px/mm x 2 d tan(0.5 deg), as a
/// fraction of the latter: the client computes it from the same two numbers, so only rounding
/// separates them; 1% allows for a client that rounds to whole pixels at low resolutions.
pub const PIXELS_PER_DEGREE_TOLERANCE: f64 = 0.01;

/// Pixels per degree from a screen pitch and a viewing distance: one degree spans
/// 2 d tan(0.5 deg) at the screen's centre.
pub fn pixels_per_degree(px_per_mm: f64, viewing_distance_mm: f64) -> f64 {
    px_per_mm * 2.0 * viewing_distance_mm * 0.5f64.to_radians().tan()
}

/// `value` of field `name` inside `range`; the message names the field and the range.
pub fn check_range(name: &str, value: f64, range: RangeInclusive<f64>) -> Result<(), String> {
    if value.is_finite() && range.contains(&value) {
        return Ok(());
    }
    Err(format!(
        "field `{name}` is {}; expected {} to {}",
        renderer::limits::shortest(value),
        range.start(),
        range.end()
    ))
}

/// The viewing geometry a browser measures, as both the log's `display.browser` and the
/// server's display facts carry it (field names are theirs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BrowserGeometry {
    pub device_pixel_ratio: f64,
    pub px_per_mm: f64,
    pub viewing_distance_mm: f64,
    pub pixels_per_degree: f64,
}

impl BrowserGeometry {
    /// Each fact in its range, and the pixels per degree the one px/mm and distance give.
    pub fn check(&self) -> Result<(), String> {
        check_range(
            "device_pixel_ratio",
            self.device_pixel_ratio,
            DEVICE_PIXEL_RATIO,
        )?;
        check_range("px_per_mm", self.px_per_mm, PX_PER_MM)?;
        check_range(
            "viewing_distance_mm",
            self.viewing_distance_mm,
            VIEWING_DISTANCE_MM,
        )?;
        let expected = pixels_per_degree(self.px_per_mm, self.viewing_distance_mm);
        let logged = self.pixels_per_degree;
        if logged.is_finite() && (logged - expected).abs() <= PIXELS_PER_DEGREE_TOLERANCE * expected
        {
            return Ok(());
        }
        Err(format!(
            "field `pixels_per_degree` is {}, but `px_per_mm` {} at `viewing_distance_mm` {} \
             gives {expected:.2} (px/mm x 2 d tan(0.5 deg)); expected within 1% of it",
            renderer::limits::shortest(logged),
            renderer::limits::shortest(self.px_per_mm),
            renderer::limits::shortest(self.viewing_distance_mm),
        ))
    }
}

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
        let ppd = self.pixels_per_degree();
        if !PIXELS_PER_DEGREE.contains(&ppd) {
            bail!(
                "fields `display.diagonal_inches`, `display.resolution` and `display.distance_m` \
                 give {ppd:.3e} pixels per degree; expected {} to {}",
                PIXELS_PER_DEGREE.start(),
                PIXELS_PER_DEGREE.end()
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

    #[test]
    fn a_viewing_distance_past_any_room_is_refused_before_the_observer_runs() {
        for distance_m in [1e308, 1e6] {
            let d = DisplaySpec {
                distance_m,
                ..DisplaySpec::default()
            };
            let e = d.validate().unwrap_err().to_string();
            assert!(
                e.contains("display.distance_m") && e.contains("pixels per degree"),
                "{e}"
            );
        }
    }

    /// A change that puts one fact out of range.
    type Spoil = fn(&mut BrowserGeometry);

    #[test]
    fn browser_facts_are_checked_against_their_ranges() {
        let good = BrowserGeometry {
            device_pixel_ratio: 1.0,
            px_per_mm: 3.78,
            viewing_distance_mm: 600.0,
            pixels_per_degree: pixels_per_degree(3.78, 600.0),
        };
        good.check().unwrap();
        let near = BrowserGeometry {
            pixels_per_degree: good.pixels_per_degree * 1.005,
            ..good
        };
        near.check().unwrap();
        let cases: [(&str, Spoil); 5] = [
            ("viewing_distance_mm", |g| g.viewing_distance_mm = 1e308),
            ("viewing_distance_mm", |g| g.viewing_distance_mm = 0.0),
            ("px_per_mm", |g| g.px_per_mm = f64::NAN),
            ("device_pixel_ratio", |g| g.device_pixel_ratio = -1.0),
            ("pixels_per_degree", |g| g.pixels_per_degree *= 2.0),
        ];
        for (name, spoil) in cases {
            let mut g = good;
            spoil(&mut g);
            let e = g.check().unwrap_err();
            assert!(e.contains(&format!("`{name}`")), "{name}: {e}");
        }
        let e = check_range("refresh_interval_ms", 0.0, REFRESH_INTERVAL_MS).unwrap_err();
        assert!(
            e.contains("`refresh_interval_ms`") && e.contains("2 to 100"),
            "{e}"
        );
    }
}
