//! What `blurlab predict` writes: `predicted.csv` (`blurlab-predicted/1`, the simulated
//! observer's input), `predicted_jnd.csv` (one row per condition), `predict.md`, and a figure
//! per scene (`figures/predicted_<scene>.svg|png`: predicted proportion correct against spp per
//! point set and time filter, bars spanning the single frames' range).

use super::stimuli::{ConditionPrediction, FrameSpread, Prediction};
use crate::figures::{
    Drawable, PALETTE, dodge, err, error_bar, file_safe, legend, level_line, line_swatch,
    register_font, save, spp_axes,
};
use crate::jnd::Threshold;
use anyhow::{Result, anyhow};
use experiment::predicted::PredictedTable;
use experiment::psychometric::TARGET;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The files written.
#[derive(Clone, Debug)]
pub struct Files {
    pub predicted_csv: PathBuf,
    pub jnd_csv: PathBuf,
    pub markdown: PathBuf,
    pub figures: Vec<PathBuf>,
}

/// Write everything into `dir` (created; each file replaced atomically).
pub fn write(p: &Prediction, dir: &Path) -> Result<Files> {
    std::fs::create_dir_all(dir)
        .map_err(|e| anyhow!("cannot create folder {}: {e}", dir.display()))?;
    let table = PredictedTable::from_rows(p.stimuli.iter().map(|s| s.row.clone()).collect());
    let predicted_csv = dir.join("predicted.csv");
    renderer::atomic::write_atomic(&predicted_csv, table.to_csv()?.as_bytes())?;
    let jnd_csv = dir.join("predicted_jnd.csv");
    renderer::atomic::write_atomic(&jnd_csv, jnd_csv_text(p)?.as_bytes())?;
    let figures = draw(p, &dir.join("figures"))?;
    let markdown = dir.join("predict.md");
    renderer::atomic::write_atomic(&markdown, markdown_text(p).as_bytes())?;
    Ok(Files {
        predicted_csv,
        jnd_csv,
        markdown,
        figures,
    })
}

/// Text of a frame spread: "12.0 / 14.5 / 20.1 (min / median / max of 6 frames; 1 above range)".
pub fn spread_text(s: &FrameSpread) -> String {
    let mut t = match s.inside {
        Some([lo, mid, hi]) => format!("{lo:.1} / {mid:.1} / {hi:.1}"),
        None => "none inside".into(),
    };
    let inside = s.frames - s.below - s.above;
    let mut notes = vec![format!("{inside} of {} frames inside", s.frames)];
    if s.below > 0 {
        notes.push(format!("{} below range", s.below));
    }
    if s.above > 0 {
        notes.push(format!("{} above range", s.above));
    }
    write!(t, " ({})", notes.join(", ")).expect("writing to a String");
    t
}

fn jnd_csv_text(p: &Prediction) -> Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "scene",
        "point_set",
        "time_filter",
        "jnd_kind",
        "jnd_spp",
        "jnd",
        "frame_jnd_min",
        "frame_jnd_median",
        "frame_jnd_max",
        "frames_below_range",
        "frames_above_range",
        "frames",
        "k",
    ])?;
    for c in &p.conditions {
        let f = &c.frame_jnd;
        let num = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v}"));
        let jnd_spp = match c.jnd {
            Threshold::Value { spp } => Some(spp),
            _ => None,
        };
        w.write_record([
            c.condition.scene.clone(),
            c.condition.point_set.to_string(),
            c.condition.time_filter.to_string(),
            c.jnd.kind().into(),
            num(jnd_spp),
            c.jnd.display(),
            num(f.inside.map(|v| v[0])),
            num(f.inside.map(|v| v[1])),
            num(f.inside.map(|v| v[2])),
            f.below.to_string(),
            f.above.to_string(),
            f.frames.to_string(),
            format!("{}", p.k),
        ])?;
    }
    Ok(String::from_utf8(w.into_inner()?)?)
}

/// The per-condition JND table as Markdown (used by `predict.md` and the demo's summary).
pub fn jnd_table(p: &Prediction) -> String {
    let mut s = String::new();
    s.push_str("| scene | point set | time filter | predicted p at each level (spp: p) | predicted JND (spp) | single frames' JND (min / median / max) |\n|---|---|---|---|---|---|\n");
    for c in &p.conditions {
        let levels: Vec<String> = c
            .points
            .iter()
            .map(|(spp, _, pc)| format!("{spp}: {pc:.3}"))
            .collect();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} |",
            c.condition.scene,
            c.condition.point_set,
            c.condition.time_filter,
            levels.join(", "),
            c.jnd.display(),
            spread_text(&c.frame_jnd)
        );
    }
    s
}

fn markdown_text(p: &Prediction) -> String {
    let frames: u64 = p.stimuli.iter().map(|s| s.row.frames as u64).sum();
    let cpu: f64 = p.stimuli.iter().map(|s| s.seconds).sum();
    let d = &p.display;
    format!(
        "# Predicted visibility: {job}\n\n\
         Stimuli `{manifest}`; display {diag}-inch {w}x{h} at {dist} m ({ppd:.1} px/deg), \
         white {peak} cd/m^2, black {black} cd/m^2; sensitivity constant k = {k}. \
         {n} test stimuli, {frames} frame pairs compared in {wall:.1} s ({per:.1} ms of thread \
         time per frame pair). Model: `docs/predict.md`.\n\n\
         Decision stage: `{stage}`, because {reason}.\n\n\
         ## Predicted JND per condition (p = {target})\n\n{table}\n\
         Files: `predicted.csv` (format blurlab-predicted/1, per stimulus), `predicted_jnd.csv` \
         (per condition), `figures/predicted_<scene>.svg|png`.\n",
        job = p.job,
        manifest = p.manifest_path.display(),
        diag = d.diagonal_inches,
        w = d.resolution[0],
        h = d.resolution[1],
        dist = d.distance_m,
        ppd = p.pixels_per_degree,
        peak = d.peak_cd_m2,
        black = d.black_cd_m2,
        k = p.k,
        stage = p.decision.stage,
        reason = p.decision.reason,
        n = p.stimuli.len(),
        wall = p.wall_seconds,
        per = 1e3 * cpu / frames.max(1) as f64,
        target = TARGET,
        table = jnd_table(p),
    )
}

/// One scene's figure.
struct SceneFigure<'a> {
    title: String,
    conditions: Vec<&'a ConditionPrediction>,
}

impl Drawable for SceneFigure<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        draw_scene(root, &self.title, &self.conditions)
    }
}

fn draw(p: &Prediction, dir: &Path) -> Result<Vec<PathBuf>> {
    register_font()?;
    std::fs::create_dir_all(dir)
        .map_err(|e| anyhow!("cannot create folder {}: {e}", dir.display()))?;
    let mut scenes: Vec<&str> = p
        .conditions
        .iter()
        .map(|c| c.condition.scene.as_str())
        .collect();
    scenes.dedup();
    let mut out = Vec::new();
    for scene in scenes {
        let conds: Vec<&ConditionPrediction> = p
            .conditions
            .iter()
            .filter(|c| c.condition.scene == scene)
            .collect();
        let name = format!("predicted_{}", file_safe(scene));
        let figure = SceneFigure {
            title: format!("Predicted psychometric function: {scene}"),
            conditions: conds,
        };
        out.extend(save(dir, &name, &figure)?);
    }
    Ok(out)
}

fn draw_scene<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    conds: &[&ConditionPrediction],
) -> Result<()> {
    root.fill(&WHITE).map_err(err)?;
    let ticks: Vec<f64> = conds
        .iter()
        .flat_map(|c| c.points.iter().map(|p| p.0 as f64))
        .collect();
    let (mut chart, (x0, x1)) = spp_axes(root, title, &ticks, 0.3, "predicted proportion correct")?;
    for (y, colour) in [(TARGET, RED), (0.5, GREEN)] {
        chart
            .draw_series(level_line(y, (x0, x1), colour.stroke_width(2)))
            .map_err(err)?;
    }
    for (i, c) in conds.iter().enumerate() {
        let colour = PALETTE[i % PALETTE.len()];
        let style = colour.stroke_width(2);
        let dodge = dodge(i, conds.len());
        let line: Vec<(f64, f64)> = c
            .points
            .iter()
            .map(|&(s, _, pc)| (s as f64 * dodge, pc))
            .collect();
        chart
            .draw_series(LineSeries::new(line.clone(), style))
            .map_err(err)?
            .label(format!(
                "{}/{} (bars: single frames)",
                c.condition.point_set, c.condition.time_filter
            ))
            .legend(line_swatch(colour, 2));
        chart
            .draw_series(line.iter().map(|&pt| Circle::new(pt, 4, colour.filled())))
            .map_err(err)?;
        for (&(x, _), &span) in line.iter().zip(&c.frame_p) {
            chart.draw_series(error_bar(x, span, style)).map_err(err)?;
        }
        if let Threshold::Value { spp } = c.jnd {
            chart
                .draw_series(std::iter::once(TriangleMarker::new(
                    (spp, TARGET),
                    8,
                    colour.filled(),
                )))
                .map_err(err)?;
        }
    }
    legend(&mut chart, 14, SeriesLabelPosition::LowerLeft)
}
