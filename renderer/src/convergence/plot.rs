//! The convergence plots: log-log RMSE against spp and against seconds, one per scene, each
//! scene x point set x time filter a series with its fitted slope, as SVG and PNG.

use super::{FONT, Row, Slope, groups};
use anyhow::{Context, Result, anyhow};
use plotters::prelude::*;
use std::path::Path;

#[derive(Clone, Copy, PartialEq)]
pub(super) enum Axis {
    Spp,
    Seconds,
}

impl Axis {
    pub(super) fn slug(self) -> &'static str {
        match self {
            Axis::Spp => "spp",
            Axis::Seconds => "seconds",
        }
    }
    fn x(self, r: &Row) -> f64 {
        match self {
            Axis::Spp => r.spp as f64,
            Axis::Seconds => r.render_seconds,
        }
    }
}

/// A tick label with three significant digits and no trailing zeros (log axes otherwise show
/// values like 0.7000000001).
fn tick(v: f64) -> String {
    if !v.is_finite() || v == 0.0 {
        return "0".into();
    }
    let decimals = (2.0 - v.abs().log10().floor()).max(0.0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
];

pub(super) fn plot(
    rows: &[Row],
    slopes: &[Slope],
    scene: &str,
    axis: Axis,
    path: &Path,
    size: (u32, u32),
) -> Result<()> {
    let is_svg = path.extension().is_some_and(|e| e == "svg");
    // Draw to a temporary path, then rename: no half-written figure.
    let tmp = crate::atomic::temp_path(path).with_extension(if is_svg { "svg" } else { "png" });
    let result = if is_svg {
        draw(
            SVGBackend::new(&tmp, size).into_drawing_area(),
            rows,
            slopes,
            scene,
            axis,
        )
    } else {
        draw(
            BitMapBackend::new(&tmp, size).into_drawing_area(),
            rows,
            slopes,
            scene,
            axis,
        )
    };
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(e.context(format!("while drawing {}", path.display())));
    }
    std::fs::rename(&tmp, path)
        .with_context(|| format!("cannot move {} to {}", tmp.display(), path.display()))
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    rows: &[Row],
    slopes: &[Slope],
    scene: &str,
    axis: Axis,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let err = |e: &dyn std::fmt::Display| anyhow!("plotting failed: {e}");
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let mine: Vec<&Row> = rows.iter().filter(|r| r.scene == scene).collect();
    let xs: Vec<f64> = mine
        .iter()
        .map(|r| axis.x(r))
        .filter(|v| *v > 0.0)
        .collect();
    let ys: Vec<f64> = mine.iter().map(|r| r.rmse).filter(|v| *v > 0.0).collect();
    let range = |v: &[f64]| {
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(0.0f64, f64::max);
        if lo.is_finite() && hi > 0.0 {
            (lo / 1.5, hi * 1.5)
        } else {
            (0.1, 10.0)
        }
    };
    let (x0, x1) = range(&xs);
    let (y0, y1) = range(&ys);
    let x_label = match axis {
        Axis::Spp => "samples per pixel",
        Axis::Seconds => "render seconds (whole video)",
    };
    let mut chart = ChartBuilder::on(&root)
        .caption(format!("{scene}: RMSE against {}", axis.slug()), (FONT, 22))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc("RMSE (linear HDR)")
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 16))
        .draw()
        .map_err(|e| err(&e))?;
    let groups = groups(rows);
    for (i, ((g_scene, ps, tf), rs)) in groups.iter().filter(|(k, _)| k.0 == scene).enumerate() {
        let color = PALETTE[i % PALETTE.len()];
        let pts: Vec<(f64, f64)> = rs
            .iter()
            .map(|r| (axis.x(r), r.rmse))
            .filter(|(x, y)| *x > 0.0 && *y > 0.0)
            .collect();
        let slope = slopes
            .iter()
            .find(|s| &s.scene == g_scene && &s.point_set == ps && &s.time_filter == tf)
            .map(|s| match axis {
                Axis::Spp => s.rmse_vs_spp,
                Axis::Seconds => s.rmse_vs_seconds,
            })
            .filter(|v| v.is_finite());
        let label = match slope {
            Some(k) => format!("{ps}, {tf} (slope {k:.2})"),
            None => format!("{ps}, {tf}"),
        };
        chart
            .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))
            .map_err(|e| err(&e))?
            .label(label)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2))
            });
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 4, color.filled())))
            .map_err(|e| err(&e))?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font((FONT, 14))
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(tick(0.700_000_000_1), "0.7");
        assert_eq!(tick(1.0), "1");
        assert_eq!(tick(125.0), "125");
        assert_eq!(tick(0.001_234_5), "0.00123");
    }
}
