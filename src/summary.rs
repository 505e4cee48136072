//! `results/<study>/summary.md`: the perceptual result (pooled JND per scene and point set) next
//! to the numerical one (each stimulus's error against its reference and its render time), and
//! the error a scene's stimuli have at its JND — the number that lets a reader compare what
//! people see with what a metric measures.

use analysis::summary::Summary;
use anyhow::Result;
use renderer::convergence::{Row, rows, slopes};
use renderer::manifest::Manifest;
use std::fmt::Write as _;
use std::path::Path;

/// What the summary is made of.
pub struct Inputs<'a> {
    /// The stimulus set's manifest, as the render returned it, and its folder.
    pub manifest: &'a Manifest,
    pub stimuli: &'a Path,
    pub report: &'a Path,
    pub convergence: &'a Path,
    pub jnd: &'a Summary,
    /// The prediction from the stimuli and the JNDs it implies next to the recovered ones.
    pub prediction: Option<PredictionInputs<'a>>,
    pub render_seconds: f64,
    pub total_seconds: f64,
}

/// The prediction's part of the summary.
pub struct PredictionInputs<'a> {
    pub prediction: &'a analysis::predict::stimuli::Prediction,
    pub side_by_side: &'a [analysis::predict::compare::JndPair],
    /// The simulated subjects' observer.
    pub observer: &'a str,
}

/// The summary as Markdown.
pub fn markdown(inp: &Inputs) -> Result<String> {
    let manifest = inp.manifest;
    let rows = rows(manifest);
    let mut s = String::new();
    writeln!(s, "# Study summary: {}\n", manifest.job)?;
    writeln!(
        s,
        "{} stimuli in `{}`; full report in `{}` (report.md, jnd.csv, ttests.csv, figures), speed \
         against error in `{}`. Rendering took {:.1} s, the whole run {:.1} s.\n",
        manifest.stimuli.len(),
        inp.stimuli.display(),
        inp.report.display(),
        inp.convergence.display(),
        inp.render_seconds,
        inp.total_seconds
    )?;
    s.push_str(&inp.jnd.markdown());
    if let Some(text) = beside_thesis(inp.jnd, manifest) {
        writeln!(s, "## Beside the thesis\n\n{text}\n")?;
    }
    if let Some(p) = &inp.prediction {
        prediction_section(&mut s, p)?;
    }
    error_at_jnd(&mut s, inp.jnd, &rows)?;
    speed_table(&mut s, &rows)?;
    Ok(s)
}

/// The thesis's scene JNDs as its Chapter IV states them ("the JND for the plane scene occurs
/// close to halfway between 27 and 64 samples per pixel, while the JND for the spheres scene
/// occurs close to 125"), with the study it measured them on.
const THESIS_SCENES: [(&str, &str); 2] = [
    ("plane", "about 45 spp (halfway between 27 and 64)"),
    ("spheres", "about 125 spp"),
];
const THESIS_SIZE: (u32, u32) = (768, 210);

/// The study's scene JNDs beside the thesis's, and, when its stimuli are not the thesis's size,
/// why they may not agree; `None` unless the study has both thesis scenes.
pub fn beside_thesis(jnd: &Summary, manifest: &Manifest) -> Option<String> {
    let ours = THESIS_SCENES.map(|(scene, _)| {
        jnd.rows
            .iter()
            .find(|r| r.grouping == analysis::data::Grouping::Scene && r.label == scene)
    });
    let [Some(plane), Some(spheres)] = ours else {
        return None;
    };
    let first = manifest.stimuli.iter().find(|s| s.scene == "plane")?;
    let (size, frames) = (first.width.max(first.height), first.frames);
    let thesis = THESIS_SCENES
        .map(|(scene, text)| format!("{scene} {text}"))
        .join(", ");
    // Where each JND lies in ln spp (a step's middle; beyond the tested levels, +-inf).
    let at = |t: &analysis::threshold::Threshold| t.ln_bounds().map(|(a, b)| 0.5 * (a + b));
    let order = match (at(&plane.jnd), at(&spheres.jnd)) {
        (Some(p), Some(s)) if s > p => "the same order as the thesis's (spheres above plane)",
        (Some(p), Some(s)) if s < p => {
            "**not** the thesis's order (there the spheres need more samples)"
        }
        _ => "an order that cannot be read (both beyond the tested levels, or undefined)",
    };
    let mut text = format!(
        "The thesis ({}x{0} pixels, {} frames, 12 subjects): {thesis}. This study ({}x{} pixels, \
         {frames} frames): plane {}, spheres {}: {order}.",
        THESIS_SIZE.0,
        THESIS_SIZE.1,
        first.width,
        first.height,
        plane.jnd.display(),
        spheres.jnd.display(),
    );
    if size < THESIS_SIZE.0 || frames < THESIS_SIZE.1 {
        write!(
            text,
            " A smaller study may differ, and is not a replication: at {size} pixels across, \
             each pixel covers about {:.0}x{0:.0} of the thesis's, so detail finer than that (the \
             spheres' specular highlights and sky reflections, where their noise lives) is \
             averaged inside a pixel before any noise is seen; {frames} frames show a fraction \
             of the thesis's motion; and simulated subjects answer from a model's prediction, \
             not from eyes. `blurlab render job scenes/thesis/job.json` renders the thesis's own \
             stimuli (docs/replication.md: what the thesis-sized prediction gives).",
            f64::from(THESIS_SIZE.0) / f64::from(size.max(1))
        )
        .ok()?;
    }
    Some(text)
}

fn prediction_section(s: &mut String, p: &PredictionInputs) -> Result<()> {
    writeln!(
        s,
        "## Predicted from the stimuli
"
    )?;
    writeln!(
        s,
        "How visible each stimulus's noise is, computed from its display frames (stelaCSF, \
         masking by the reference, pooling, the two-pair task's decision rule; `docs/predict.md`; \
         sensitivity constant k = {}, uncalibrated unless stated). Files in `predict/`.\n",
        p.prediction.k
    )?;
    writeln!(s, "{}", analysis::predict::output::jnd_table(p.prediction))?;
    writeln!(
        s,
        "Simulated subjects answered from observer `{}`. Its JND (the 0.75 crossing of the \
         population's pooled curve) next to the JND the analysis recovered:\n",
        p.observer
    )?;
    writeln!(
        s,
        "{}",
        analysis::predict::compare::markdown(p.side_by_side, p.observer)
    )?;
    Ok(())
}

/// Per scene, the error of its stimuli interpolated (log-log, over the point sets' mean) at the
/// scene's pooled JND.
fn error_at_jnd(s: &mut String, jnd: &Summary, rows: &[Row]) -> Result<()> {
    writeln!(s, "## Error at the JND\n")?;
    writeln!(
        s,
        "Each scene's stimulus error (mean over its point sets and time filters at each level), \
         interpolated linearly in log error against log spp at the scene's JND. A JND outside \
         the tested levels has no interpolated error.\n"
    )?;
    writeln!(s, "| scene | JND (spp) | RMSE (linear) | FLIP |")?;
    writeln!(s, "|---|---|---|---|")?;
    for r in jnd
        .rows
        .iter()
        .filter(|r| r.grouping == analysis::data::Grouping::Scene)
    {
        let scene_rows: Vec<&Row> = rows.iter().filter(|x| x.scene == r.label).collect();
        let (rmse, flip) = match r.jnd.spp() {
            Some(spp) => (
                interpolate(&level_means(&scene_rows, |x| x.rmse), spp),
                interpolate(&level_means(&scene_rows, |x| x.flip), spp),
            ),
            None => (None, None),
        };
        let show = |v: Option<f64>| v.map_or("n/a".to_string(), |v| format!("{v:.4}"));
        writeln!(
            s,
            "| {} | {} | {} | {} |",
            r.label,
            r.jnd.display(),
            show(rmse),
            show(flip)
        )?;
    }
    writeln!(s)?;
    Ok(())
}

/// Mean of `f` over the rows at each level, sorted by level.
fn level_means(rows: &[&Row], f: impl Fn(&Row) -> f64) -> Vec<(f64, f64)> {
    let mut levels: Vec<u32> = rows.iter().map(|r| r.spp).collect();
    levels.sort_unstable();
    levels.dedup();
    levels
        .into_iter()
        .map(|l| {
            let v: Vec<f64> = rows.iter().filter(|r| r.spp == l).map(|r| f(r)).collect();
            (l as f64, v.iter().sum::<f64>() / v.len() as f64)
        })
        .collect()
}

/// Piecewise-linear interpolation in (ln x, ln y) at `x`; `None` outside the points' range or
/// where an error is not positive.
pub fn interpolate(points: &[(f64, f64)], x: f64) -> Option<f64> {
    let i = points.windows(2).position(|w| w[0].0 <= x && x <= w[1].0)?;
    let ((x0, y0), (x1, y1)) = (points[i], points[i + 1]);
    if y0 <= 0.0 || y1 <= 0.0 || x0 <= 0.0 {
        return None;
    }
    if x1 == x0 {
        return Some(y0);
    }
    let w = (x.ln() - x0.ln()) / (x1.ln() - x0.ln());
    Some((y0.ln() + w * (y1.ln() - y0.ln())).exp())
}

fn speed_table(s: &mut String, rows: &[Row]) -> Result<()> {
    writeln!(s, "## Speed against error\n")?;
    writeln!(
        s,
        "Per stimulus: render seconds and error against its scene's reference (RMSE and relative \
         MSE in linear HDR, PSNR and FLIP on the display frames, averaged over frames). The \
         slope is the least-squares slope of log RMSE against log spp (-0.5 is plain Monte \
         Carlo).\n"
    )?;
    writeln!(
        s,
        "| scene | point set | time filter | spp | seconds | RMSE | rel. MSE | PSNR (dB) | FLIP |"
    )?;
    writeln!(s, "|---|---|---|---|---|---|---|---|---|")?;
    // `rows` is sorted by group and spp, `slopes` lists the groups in the same order.
    for g in slopes(rows) {
        let (scene, ps, tf) = (&g.scene, &g.point_set, &g.time_filter);
        for r in rows
            .iter()
            .filter(|r| (&r.scene, &r.point_set, &r.time_filter) == (scene, ps, tf))
        {
            writeln!(
                s,
                "| {scene} | {ps} | {tf} | {} | {:.2} | {:.4} | {:.4} | {:.1} | {:.4} |",
                r.spp, r.render_seconds, r.rmse, r.rel_mse, r.psnr, r.flip
            )?;
        }
        if g.rmse_vs_spp.is_finite() {
            writeln!(
                s,
                "| {scene} | {ps} | {tf} | slope | | {:.2} | | | |",
                g.rmse_vs_spp
            )?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolation_is_exact_on_a_power_law_and_refuses_extrapolation() {
        // y = 3 x^-0.5 is a straight line in log-log: interpolation must reproduce it.
        let pts: Vec<(f64, f64)> = [1.0, 8.0, 27.0, 64.0]
            .iter()
            .map(|&x: &f64| (x, 3.0 * x.powf(-0.5)))
            .collect();
        for x in [1.0, 2.0, 8.0, 40.0, 64.0] {
            let y = interpolate(&pts, x).unwrap();
            assert!((y - 3.0 * x.powf(-0.5)).abs() < 1e-12, "{x}: {y}");
        }
        assert_eq!(interpolate(&pts, 0.5), None);
        assert_eq!(interpolate(&pts, 100.0), None);
        assert_eq!(interpolate(&[(1.0, 0.0), (8.0, 1.0)], 2.0), None);
    }
}
