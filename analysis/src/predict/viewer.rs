//! One subject's own viewing geometry (issue 39): a browser session logs the subject's screen
//! scale (card method, device pixels per millimetre) and viewing distance (blind-spot method),
//! which together give that subject's pixels per degree. `blurlab predict --viewer LOG` predicts
//! at that geometry instead of the design's display block.
//!
//! Only the geometry is the subject's: a browser cannot measure luminance, so the design's (or
//! the default) peak and black luminance stay. The screen's size is stated as the browser window
//! in device pixels at the measured pitch; only the pitch enters the prediction (the videos are
//! shown 1:1, so a video pixel is a device pixel).

use anyhow::{Result, bail};
use experiment::display::{self, DisplaySpec};
use experiment::log::{BrowserDisplay, SessionLog};
use std::path::Path;

/// `base` (the design's display or the default) seen at the geometry logged in `log`.
pub fn display_for_session(log: &Path, base: &DisplaySpec) -> Result<DisplaySpec> {
    let read = SessionLog::read(log)?;
    let Some(browser) = read.header.display.and_then(|d| d.browser) else {
        bail!(
            "{}: the header has no `display.browser` (mode `{}`); only browser sessions \
             (`blurlab serve`) log a subject's pixels per degree",
            log.display(),
            read.header.mode
        );
    };
    check_geometry(&browser)
        .map_err(|e| anyhow::anyhow!("{}: header `display.browser`: {e}", log.display()))?;
    let d = with_geometry(base, &browser);
    d.validate()
        .map_err(|e| anyhow::anyhow!("{}: display.browser: {e}", log.display()))?;
    Ok(d)
}

/// The log's own geometry fields in range, named as the log names them, before anything is
/// derived from them (a distance of 1e308 mm once ran the observer for minutes).
fn check_geometry(b: &BrowserDisplay) -> Result<(), String> {
    if b.window_px.contains(&0) {
        return Err(format!(
            "field `window_px` is {:?}; expected [width, height] in device pixels",
            b.window_px
        ));
    }
    display::BrowserGeometry {
        device_pixel_ratio: b.device_pixel_ratio,
        px_per_mm: b.px_per_mm,
        viewing_distance_mm: b.viewing_distance_mm,
        pixels_per_degree: b.pixels_per_degree,
    }
    .check()
}

/// `base` with the browser's screen pitch and viewing distance.
pub fn with_geometry(base: &DisplaySpec, b: &BrowserDisplay) -> DisplaySpec {
    let [w, h] = b.window_px;
    // Diagonal of the window in inches at b.px_per_mm device pixels per millimetre: the pitch
    // DisplaySpec derives from it is then 1 / px_per_mm mm.
    let diagonal_mm = f64::from(w).hypot(f64::from(h)) / b.px_per_mm;
    DisplaySpec {
        diagonal_inches: diagonal_mm / 25.4,
        resolution: [w, h],
        distance_m: b.viewing_distance_mm / 1000.0,
        ..base.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn browser(px_per_mm: f64, distance_mm: f64) -> BrowserDisplay {
        BrowserDisplay {
            window_px: [1000, 700],
            device_pixel_ratio: 1.0,
            px_per_mm,
            viewing_distance_mm: distance_mm,
            // What the client computes: px/mm x 2 d tan(0.5 deg).
            pixels_per_degree: display::pixels_per_degree(px_per_mm, distance_mm),
            user_agent: "test".into(),
            fullscreen: true,
        }
    }

    #[test]
    fn the_geometry_gives_the_pixels_per_degree_the_browser_logged() {
        for (px_per_mm, d) in [(3.0, 333.2), (3.78, 600.0), (7.5, 450.0)] {
            let b = browser(px_per_mm, d);
            let spec = with_geometry(&DisplaySpec::default(), &b);
            let ppd = spec.pixels_per_degree();
            assert!(
                (ppd - b.pixels_per_degree).abs() < 1e-9 * ppd,
                "{ppd} vs {}",
                b.pixels_per_degree
            );
            // Luminance stays the design's.
            assert_eq!(spec.peak_cd_m2, DisplaySpec::default().peak_cd_m2);
            spec.validate().unwrap();
        }
    }

    #[test]
    fn a_log_without_browser_facts_is_refused_and_named() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("lab.jsonl");
        let header = serde_json::json!({
            "kind": "header", "format": "blurlab-session/1", "subject": "s1", "session": 1,
            "design": "d", "design_hash": "h", "seed": 1, "app_version": "blurlab test",
            "mode": "gui", "started_unix": 0.0, "trials_planned": 4,
        });
        std::fs::write(&path, format!("{header}\n")).unwrap();
        let e = display_for_session(&path, &DisplaySpec::default())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("lab.jsonl") && e.contains("display.browser"),
            "{e}"
        );
        assert!(e.contains("`gui`"), "{e}");
    }

    /// A change that puts one geometry field out of range.
    type Spoil = fn(&mut BrowserDisplay);

    /// The error `display_for_session` gives for a web log whose header holds `b`.
    fn refusal(b: &BrowserDisplay) -> String {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("web.jsonl");
        let header = serde_json::json!({
            "kind": "header", "format": "blurlab-session/1", "subject": "s1", "session": 1,
            "design": "d", "design_hash": "h", "seed": 1, "app_version": "blurlab test",
            "mode": "web", "started_unix": 0.0, "trials_planned": 4,
            "display": {"width": 1000, "height": 700, "pixels_per_point": 1.0,
                        "refresh_interval_ms": 16.7, "browser": b},
        });
        std::fs::write(&path, format!("{header}\n")).unwrap();
        display_for_session(&path, &DisplaySpec::default())
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn every_geometry_field_out_of_range_is_named_as_the_log_names_it() {
        let cases: [(&str, Spoil); 6] = [
            ("viewing_distance_mm", |b| b.viewing_distance_mm = 0.0),
            ("viewing_distance_mm", |b| b.viewing_distance_mm = 1e308),
            ("viewing_distance_mm", |b| b.viewing_distance_mm = 60_000.0),
            ("px_per_mm", |b| b.px_per_mm = 1e-9),
            ("window_px", |b| b.window_px = [0, 700]),
            ("pixels_per_degree", |b| b.pixels_per_degree *= 3.0),
        ];
        for (field, spoil) in cases {
            let mut b = browser(3.0, 333.0);
            spoil(&mut b);
            let e = refusal(&b);
            assert!(
                e.contains("web.jsonl") && e.contains(&format!("`{field}`")),
                "{field}: {e}"
            );
            assert!(!e.contains("diagonal_inches"), "{e}");
        }
    }
}
