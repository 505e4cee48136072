//! A point set the way thesis Figure 4 shows it (its 2D projections) and measured: L2-star
//! discrepancy against the random expectation, and the minimum toroidal distance against the
//! densest packing (`blurlab render pointsets`).

use crate::convergence::{FONT, register_font};
use crate::sampling::discrepancy::{l2_star, random_l2_star_squared};
use crate::sampling::pointset::{self, Points};
use crate::sampling::spacing::{max_packing_distance, min_toroidal_distance};
use crate::sampling::{Density, density};
use anyhow::{Context, Result, anyhow, bail};
use plotters::prelude::*;
use std::path::Path;

/// What `render pointsets` measures of one set.
#[derive(Clone, Debug, PartialEq)]
pub struct SetStats {
    pub name: String,
    pub n: usize,
    /// L2-star discrepancy (Warnock).
    pub l2_star: f64,
    /// RMS L2-star discrepancy of n random points, sqrt((2^-3 - 3^-3) / n).
    pub random_l2_star: f64,
    /// Closest toroidal pair; `None` for a single point.
    pub min_distance: Option<f64>,
    /// Neighbour distance of the densest packing of n points (d_max = 2 r_max).
    pub packing_distance: f64,
}

impl std::fmt::Display for SetStats {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{:<11} N={:<5} L2* {:.5} ({:.2} x random {:.5})  ",
            self.name,
            self.n,
            self.l2_star,
            self.l2_star / self.random_l2_star,
            self.random_l2_star
        )?;
        match self.min_distance {
            Some(d) => write!(
                f,
                "min distance {d:.5} ({:.2} x packing {:.5})",
                d / self.packing_distance,
                self.packing_distance
            ),
            None => write!(f, "min distance - (one point)"),
        }
    }
}

/// The (u, v, t) points `render pointsets` shows: the set as a frame sampler would make it,
/// before any pixel shift or warp.
/// `temporal`: a product set of n/K positions x K times (the scene setting
/// `density: {"temporal": K}`).
pub fn make(name: &str, n: u32, seed: u64, temporal: Option<u32>) -> Result<Points> {
    let set = pointset::by_name(name)?;
    let split = match temporal {
        Some(k) => Density::Temporal(k),
        None => Density::Joint,
    };
    let p = density::points(set, n as usize, split, seed)
        .with_context(|| format!("point set {name} with {n} points"))?;
    Ok(Points::from_fn(p.len(), 3, |i, d| p[i][d]))
}

/// Discrepancy and spacing of a 3D set.
pub fn measure(name: &str, p: &Points) -> SetStats {
    SetStats {
        name: name.to_string(),
        n: p.len(),
        l2_star: l2_star(p),
        random_l2_star: random_l2_star_squared(p.len(), p.dims()).sqrt(),
        min_distance: min_toroidal_distance(p),
        packing_distance: max_packing_distance(p.dims(), p.len()),
    }
}

/// Draw the three projections side by side, with the measurements in the title; written
/// whole or not at all.
pub fn plot(p: &Points, stats: &SetStats, path: &Path) -> Result<()> {
    register_font()?;
    let size = (1200, 460);
    let bytes = match path.extension().and_then(|e| e.to_str()) {
        Some("svg") => {
            let mut svg = String::new();
            draw(
                SVGBackend::with_string(&mut svg, size).into_drawing_area(),
                p,
                stats,
            )?;
            svg.into_bytes()
        }
        Some("png") => {
            let mut rgb = vec![0u8; (size.0 * size.1 * 3) as usize];
            draw(
                BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area(),
                p,
                stats,
            )?;
            let img = image::RgbImage::from_raw(size.0, size.1, rgb)
                .ok_or_else(|| anyhow!("plot buffer has the wrong size"))?;
            let mut png = std::io::Cursor::new(Vec::new());
            img.write_to(&mut png, image::ImageFormat::Png)?;
            png.into_inner()
        }
        _ => bail!(
            "--plot {}: expected a file name ending in .svg or .png",
            path.display()
        ),
    };
    crate::atomic::write_atomic(path, &bytes)
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    p: &Points,
    s: &SetStats,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let err = |e: &dyn std::fmt::Display| anyhow!("plotting failed: {e}");
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let spacing = match s.min_distance {
        Some(d) => format!(
            "min toroidal distance {d:.4} ({:.2} of densest packing)",
            d / s.packing_distance
        ),
        None => "one point".into(),
    };
    let title = format!(
        "{}, N = {}: L2-star discrepancy {:.4} ({:.2} x random), {spacing}",
        s.name,
        s.n,
        s.l2_star,
        s.l2_star / s.random_l2_star
    );
    let body = root.titled(&title, (FONT, 20)).map_err(|e| err(&e))?;
    let panels = body.split_evenly((1, 3));
    for (panel, (a, b, label)) in
        panels
            .iter()
            .zip([(0, 1, "(u, v)"), (0, 2, "(u, t)"), (1, 2, "(v, t)")])
    {
        let mut chart = ChartBuilder::on(panel)
            .caption(label, (FONT, 18))
            .margin(14)
            .x_label_area_size(28)
            .y_label_area_size(36)
            .build_cartesian_2d(0f64..1f64, 0f64..1f64)
            .map_err(|e| err(&e))?;
        chart
            .configure_mesh()
            .x_labels(5)
            .y_labels(5)
            .disable_mesh()
            .label_style((FONT, 12))
            .draw()
            .map_err(|e| err(&e))?;
        chart
            .draw_series(
                p.iter()
                    .map(|x| Circle::new((x[a], x[b]), 2, RGBColor(31, 119, 180).filled())),
            )
            .map_err(|e| err(&e))?;
    }
    root.present().map_err(|e| err(&e))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plots_are_written_whole_with_the_measurements() {
        let dir = tempfile::tempdir().unwrap();
        let p = make("hammersley", 125, 1, None).unwrap();
        let s = measure("hammersley", &p);
        let svg = dir.path().join("h.svg");
        plot(&p, &s, &svg).unwrap();
        let text = std::fs::read_to_string(&svg).unwrap();
        assert!(text.contains("L2-star discrepancy"), "title missing");
        assert!(text.matches("<circle").count() >= 3 * 125);
        let png = dir.path().join("h.png");
        plot(&p, &s, &png).unwrap();
        assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
        assert!(plot(&p, &s, &dir.path().join("h.jpg")).is_err());
    }

    #[test]
    fn bad_requests_are_explained() {
        let e = format!("{:#}", make("stratified", 100, 1, None).unwrap_err());
        assert!(e.contains("64 and 125"), "{e}");
    }
}
