//! Figures in the thesis's style (Figures 19-25): proportion correct against spp on a log axis,
//! the mean over subjects with standard-error bars, dashed lines at the target (red) and at
//! chance (green), the pooled fit, and the JND marked (a triangle at the threshold, or a bar
//! spanning the interval of a step fit). Per scene, per point set, and overlaid; SVG and PNG.
//!
//! PNG text needs a font: the Ubuntu Light face bundled by `epaint_default_fonts` (pure Rust
//! bytes, the font egui ships) is registered with plotters' ab_glyph backend by
//! `renderer::plot_font` (as for the convergence plots), so no system font
//! library is involved. SVG text is left to the viewer's sans-serif.

use crate::data::Grouping;
use crate::jnd::Threshold;
use crate::psychometric::Shape;
use crate::report::{GroupResult, Report};
use anyhow::{Result, anyhow};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

pub(crate) const SIZE: (u32, u32) = (800, 600);
pub(crate) const FONT: &str = "sans-serif";

/// Colours of overlaid series: never red or green, which mark the target and chance lines
/// (the thesis's dashed red and green).
pub(crate) const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(0, 0, 0),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(23, 190, 207),
];

pub(crate) fn register_font() -> Result<()> {
    renderer::plot_font::register(FONT)
}

/// One figure: a title and the groups it overlays.
struct Figure<'a> {
    name: String,
    title: String,
    groups: Vec<&'a GroupResult>,
}

/// Draw every figure into `dir`; returns the figure names (files `<name>.svg` and `.png`).
pub fn draw_all(report: &Report, dir: &Path) -> Result<Vec<String>> {
    register_font()?;
    std::fs::create_dir_all(dir)
        .map_err(|e| anyhow!("cannot create folder {}: {e}", dir.display()))?;
    let target = report.settings.target;
    let guess = report.settings.fit.guess;
    let mut figures = Vec::new();
    for (grouping, single, overlaid) in [
        (Grouping::Scene, "scene", "All scenes"),
        (Grouping::PointSet, "point_set", "All point sets"),
        (Grouping::TimeFilter, "time_filter", "All time filters"),
        (Grouping::Condition, "", "All conditions"),
    ] {
        let groups: Vec<&GroupResult> = report.groups_of(grouping).collect();
        if groups.is_empty() {
            continue;
        }
        if !single.is_empty() {
            for g in &groups {
                figures.push(Figure {
                    name: format!("{single}_{}", file_safe(&g.key.label)),
                    title: format!(
                        "Psychometric function: {} {}",
                        single.replace('_', " "),
                        g.key.label
                    ),
                    groups: vec![g],
                });
            }
        }
        if groups.len() > 1 || single.is_empty() {
            figures.push(Figure {
                name: format!("{}_overlaid", grouping.name()),
                title: overlaid.to_string(),
                groups,
            });
        }
    }
    for f in &figures {
        save(
            dir,
            &f.name,
            &Thesis {
                figure: f,
                target,
                guess,
            },
        )?;
    }
    Ok(figures.into_iter().map(|f| f.name).collect())
}

/// A figure drawable on any plotters backend (so one drawing makes both the SVG and the PNG).
pub(crate) trait Drawable {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>;
}

struct Thesis<'a> {
    figure: &'a Figure<'a>,
    target: f64,
    guess: f64,
}

impl Drawable for Thesis<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        draw(root, self.figure, self.target, self.guess)
    }
}

/// Write `<name>.svg` and `<name>.png` into `dir`, each replaced atomically; returns both paths.
pub(crate) fn save(dir: &Path, name: &str, d: &impl Drawable) -> Result<[std::path::PathBuf; 2]> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        d.draw(&root)?;
        root.present().map_err(|e| anyhow!("{e:?}"))?;
    }
    let svg_path = dir.join(format!("{name}.svg"));
    renderer::atomic::write_atomic(&svg_path, svg.as_bytes())?;
    let png = dir.join(format!("{name}.png"));
    // plotters picks the encoder from the extension, so the temporary keeps `.png`.
    let tmp = dir.join(format!(".{name}.{}.tmp.png", std::process::id()));
    {
        let root = BitMapBackend::new(&tmp, SIZE).into_drawing_area();
        d.draw(&root)?;
        root.present()
            .map_err(|e| anyhow!("cannot write {}: {e:?}", png.display()))?;
    }
    std::fs::rename(&tmp, &png)
        .map_err(|e| anyhow!("cannot move {} to {}: {e}", tmp.display(), png.display()))?;
    Ok([svg_path, png])
}

/// Axes of proportion correct against spp: a log axis with ticks at the levels and a little
/// room either side; returns the chart and its x range.
pub(crate) fn spp_axes<'a, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, Shift>,
    title: &str,
    levels: &[f64],
    y0: f64,
    y_desc: &str,
) -> Result<(Chart<'a, DB>, (f64, f64))> {
    let lo = levels
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min)
        .max(1.0);
    let hi = levels.iter().copied().fold(1.0, f64::max).max(2.0);
    let (x0, x1) = (lo / 1.5, hi * 1.5);
    let mut ticks: Vec<f64> = levels.to_vec();
    ticks.sort_by(f64::total_cmp);
    ticks.dedup();
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FONT, 24))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d((x0..x1).log_scale().with_key_points(ticks), y0..1.05f64)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("samples per pixel")
        .y_desc(y_desc)
        .x_label_formatter(&|x| format!("{x:.0}"))
        .label_style((FONT, 14))
        .draw()
        .map_err(err)?;
    Ok((chart, (x0, x1)))
}

pub(crate) fn file_safe(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

pub(crate) fn err<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow!("drawing failed: {e:?}")
}

/// The legend of every figure: the series' labels in a box of translucent white with a black
/// border, in `font_size` points, at `position` (a corner the figure's curves leave empty).
pub(crate) fn legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    font_size: u32,
    position: SeriesLabelPosition,
) -> Result<()> {
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font((FONT, font_size))
        .position(position)
        .draw()
        .map_err(err)
}

/// A line's legend swatch: a 20-pixel stroke of its colour and width.
pub(crate) fn line_swatch(
    colour: RGBColor,
    width: u32,
) -> impl Fn((i32, i32)) -> PathElement<(i32, i32)> {
    move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(width))
}

/// A dashed horizontal line at `y` across `(x0, x1)`: the target's and chance's levels.
pub(crate) fn level_line(
    y: f64,
    (x0, x1): (f64, f64),
    style: ShapeStyle,
) -> DashedLineSeries<std::vec::IntoIter<(f64, f64)>, i32> {
    DashedLineSeries::new(vec![(x0, y), (x1, y)], 8, 5, style)
}

/// Factor on spp that nudges overlaid series apart on a log axis: 3% of a decade per series,
/// centred on the tested level (1 for a single series).
pub(crate) fn dodge(series: usize, of: usize) -> f64 {
    10f64.powf(0.03 * (series as f64 - 0.5 * (of as f64 - 1.0)))
}

/// An error bar from `lo` to `hi` at `x` on the log spp axis, with caps 4% of a decade wide.
pub(crate) fn error_bar(
    x: f64,
    (lo, hi): (f64, f64),
    style: ShapeStyle,
) -> [PathElement<(f64, f64)>; 3] {
    let cap = 10f64.powf(0.02);
    [
        PathElement::new(vec![(x, lo), (x, hi)], style),
        PathElement::new(vec![(x / cap, lo), (x * cap, lo)], style),
        PathElement::new(vec![(x / cap, hi), (x * cap, hi)], style),
    ]
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    f: &Figure,
    target: f64,
    guess: f64,
) -> Result<()> {
    root.fill(&WHITE).map_err(err)?;
    let levels: Vec<u32> = f
        .groups
        .iter()
        .flat_map(|g| g.levels.iter().map(|l| l.level))
        .collect();
    let ticks: Vec<f64> = levels.iter().map(|&l| l as f64).collect();
    let y0 = (guess - 0.2).clamp(0.0, 0.3);
    let (mut chart, (x0, x1)) = spp_axes(root, &f.title, &ticks, y0, "proportion correct")?;
    for (y, colour, label) in [(target, RED, "JND threshold"), (guess, GREEN, "chance")] {
        chart
            .draw_series(level_line(y, (x0, x1), colour.stroke_width(2)))
            .map_err(err)?
            .label(format!("{label} (p = {y})"))
            .legend(move |(x, y)| {
                // A dashed swatch, like the line it names.
                let dash = |a: i32| {
                    PathElement::new(vec![(x + a, y), (x + a + 6, y)], colour.stroke_width(2))
                };
                EmptyElement::at((0, 0)) + dash(0) + dash(10) + dash(20)
            });
    }
    let labels = legend_labels(&f.groups);
    for (i, g) in f.groups.iter().enumerate() {
        let series = Series {
            group: g,
            label: &labels[i],
            colour: PALETTE[i % PALETTE.len()],
            // Overlaid means and bars are nudged apart.
            dodge: dodge(i, f.groups.len()),
        };
        draw_group(&mut chart, &series, target, (x0, x1))?;
    }
    // Lower left: the curves start near 1 at few spp, so that corner stays empty.
    legend(&mut chart, 14, SeriesLabelPosition::LowerLeft)
}

/// Legend labels: the group labels, without a part every overlaid condition shares (e.g. the
/// single time filter of `plane/hammersley/truncated_box`).
fn legend_labels(groups: &[&GroupResult]) -> Vec<String> {
    let parts: Vec<Vec<&str>> = groups
        .iter()
        .map(|g| g.key.label.split('/').collect())
        .collect();
    let n = parts.iter().map(Vec::len).min().unwrap_or(0);
    let shared: Vec<bool> = (0..n)
        .map(|k| groups.len() > 1 && parts.iter().all(|p| p.len() == n && p[k] == parts[0][k]))
        .collect();
    parts
        .iter()
        .map(|p| {
            let kept: Vec<&str> = p
                .iter()
                .enumerate()
                .filter(|(k, _)| !shared.get(*k).copied().unwrap_or(false))
                .map(|(_, s)| *s)
                .collect();
            if kept.is_empty() {
                p.join("/")
            } else {
                kept.join("/")
            }
        })
        .collect()
}

pub(crate) type Chart<'a, DB> = ChartContext<
    'a,
    DB,
    Cartesian2d<
        plotters::coord::combinators::WithKeyPoints<plotters::coord::combinators::LogCoord<f64>>,
        plotters::coord::types::RangedCoordf64,
    >,
>;

/// One group drawn in a figure.
struct Series<'a> {
    group: &'a GroupResult,
    label: &'a str,
    colour: RGBColor,
    /// Factor on spp for the means and error bars (1 unless overlaid).
    dodge: f64,
}

fn draw_group<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    series: &Series,
    target: f64,
    (x0, x1): (f64, f64),
) -> Result<()> {
    let Series {
        group: g,
        label,
        colour,
        dodge,
    } = *series;
    let style = colour.stroke_width(2);
    // Mean over subjects with standard-error bars.
    for l in &g.levels {
        let Some(e) = l.sem else { continue };
        let x = l.level as f64 * dodge;
        chart
            .draw_series(error_bar(x, (l.mean - e, l.mean + e), style))
            .map_err(err)?;
    }
    chart
        .draw_series(
            g.levels
                .iter()
                .map(|l| Circle::new((l.level as f64 * dodge, l.mean), 4, colour.filled())),
        )
        .map_err(err)?
        .label(format!("{label} (mean +- SEM)"))
        .legend(move |(x, y)| Circle::new((x + 10, y), 4, colour.filled()));
    // The pooled fit: the function itself, or for a step its values at the tested levels.
    let fitted: Vec<(f64, f64)> = match &g.pooled.shape {
        Shape::Finite(m) => (0..=200)
            .map(|i| {
                let x = x0.ln() + (x1.ln() - x0.ln()) * i as f64 / 200.0;
                (x.exp(), m.p(x))
            })
            .collect(),
        _ => g
            .pooled
            .curve
            .points
            .iter()
            .zip(&g.pooled.fitted)
            .map(|(c, &p)| (c.level as f64, p))
            .collect(),
    };
    chart
        .draw_series(LineSeries::new(fitted, colour.stroke_width(1)))
        .map_err(err)?;
    // The JND.
    match g.threshold {
        Threshold::Value { .. } | Threshold::AtLevel { .. } => {
            let spp = g.threshold.spp().unwrap_or(1.0);
            chart
                .draw_series(std::iter::once(TriangleMarker::new(
                    (spp, target),
                    8,
                    colour.filled(),
                )))
                .map_err(err)?;
        }
        Threshold::Between { lower, upper } => {
            chart
                .draw_series(std::iter::once(PathElement::new(
                    vec![(lower as f64, target), (upper as f64, target)],
                    colour.stroke_width(5),
                )))
                .map_err(err)?;
        }
        _ => {}
    }
    Ok(())
}
