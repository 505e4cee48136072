//! The one font of every figure the suite draws (plotters' ab_glyph backend has no system
//! fonts): Ubuntu Light, bundled by `epaint_default_fonts`, registered once per family name
//! that a figure module uses (the name is written into SVG files, so each module keeps its
//! own).

use anyhow::{Result, anyhow};
use plotters::style::FontStyle;
use std::sync::Mutex;

/// Register the bundled font under `family` (once; later calls only report the outcome).
pub fn register(family: &'static str) -> Result<()> {
    static DONE: Mutex<Vec<(&str, bool)>> = Mutex::new(Vec::new());
    let mut done = DONE.lock().unwrap_or_else(|e| e.into_inner());
    let ok = match done.iter().find(|(f, _)| *f == family) {
        Some(&(_, ok)) => ok,
        None => {
            let ok = plotters::style::register_font(
                family,
                FontStyle::Normal,
                epaint_default_fonts::UBUNTU_LIGHT,
            )
            .is_ok();
            done.push((family, ok));
            ok
        }
    };
    ok.then_some(())
        .ok_or_else(|| anyhow!("the bundled Ubuntu Light font could not be loaded"))
}
