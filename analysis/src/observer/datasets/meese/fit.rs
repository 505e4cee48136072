//! The decision stages against human masking data: Meese et al. 2007's cross-orientation
//! masking ([`super`]) predicted by each stage, and the errors in dB, of the threshold
//! elevations (the validated figure: what masking does) and of the absolute thresholds (at
//! ModelFest's presentation, for reference). `blurlab predict validate meese2007`.

use super::{Line, Series, elevation_rms_db, filters, predict, rms_db, threshold_rms_db};
use crate::observer::model::decision_stage::SideBySide;
use crate::observer::model::orientation::{ORIENTATIONS, OrientationMasking};
use crate::observer::model::pooling::FITTED;
use crate::observer::model::video::Filters;
use anyhow::Result;
use renderer::progress::Progress;
use std::fmt::Write as _;

/// One model's predictions.
#[derive(Clone)]
pub struct Run {
    /// The stage's name as the report gives it.
    pub name: String,
    pub lines: Vec<Line>,
}

/// A model to run: its name and how to build its filters.
pub struct Model<'a> {
    pub name: String,
    pub make: Box<dyn Fn() -> Result<Filters> + Sync + 'a>,
}

/// The stages compared with the fitted one: `difference`, and `side-by-side` as first built
/// (orientations pooled before the comparison).
pub fn stages() -> Vec<Model<'static>> {
    vec![
        Model {
            name: "difference".into(),
            make: Box::new(|| filters(None)),
        },
        Model {
            name: "side-by-side (pooled)".into(),
            make: Box::new(|| side_by_side(None)),
        },
    ]
}

/// The committed side-by-side stage with the orientation channels `orientation` (`None`:
/// pooled over orientation before the comparison).
fn side_by_side(orientation: Option<OrientationMasking>) -> Result<Filters> {
    filters(Some(SideBySide {
        orientation,
        ..SideBySide::committed(FITTED.space)
    }))
}

/// The cross-orientation weights searched: 0 (masking within orientation only), then
/// log-spaced up to 1 (every orientation masks alike).
pub const CROSS_WEIGHTS: [f64; 6] = [0.0, 0.01, 0.03, 0.1, 0.3, 1.0];

/// The side-by-side stage with orientation channels, its cross-orientation weight fitted.
pub fn fit_cross_weight(
    series: &[Series],
    weights: &[f64],
    progress: &dyn Progress,
) -> Result<ParameterFit> {
    let make = |w: f64| {
        side_by_side(Some(OrientationMasking {
            orientations: ORIENTATIONS,
            cross_weight: w,
        }))
    };
    fit_parameter(
        series,
        "cross-orientation weight w",
        weights,
        &make,
        progress,
    )
}

/// Every model on the data set.
pub fn run(series: &[Series], models: &[Model], progress: &dyn Progress) -> Result<Vec<Run>> {
    progress.start(models.len() as u64);
    progress.message("decision stages on Meese et al. 2007");
    let runs = models
        .iter()
        .map(|m| {
            let lines = predict(series, m.make.as_ref())?;
            progress.advance(1);
            Ok(Run {
                name: m.name.clone(),
                lines,
            })
        })
        .collect::<Result<Vec<_>>>();
    progress.finish();
    runs
}

/// A stage parameter fitted to the elevations: each candidate value's predictions, the best
/// (least RMS error of the masked elevations) and leave-one-out (each masked elevation
/// predicted with the value fitted to the others).
pub struct ParameterFit {
    /// The parameter's name as the report gives it.
    pub name: String,
    pub values: Vec<f64>,
    pub runs: Vec<Run>,
    pub best: usize,
    /// Per masked threshold (in the runs' order): the left-out prediction and the measured
    /// elevation.
    pub left_out: Vec<(Option<f64>, f64)>,
}

impl ParameterFit {
    /// The leave-one-out RMS error of the elevations, dB.
    pub fn loo_rms_db(&self) -> f64 {
        rms_db(self.left_out.iter().copied())
    }
}

/// Fit the parameter `name` over `values`, `make(v)` building the stage's filters at value v.
pub fn fit_parameter(
    series: &[Series],
    name: &str,
    values: &[f64],
    make: &(dyn Fn(f64) -> Result<Filters> + Sync),
    progress: &dyn Progress,
) -> Result<ParameterFit> {
    let models: Vec<Model> = values
        .iter()
        .map(|&v| Model {
            name: format!("{name} = {v}"),
            make: Box::new(move || make(v)),
        })
        .collect();
    let runs = run(series, &models, progress)?;
    let masked: Vec<usize> = (0..runs.first().map_or(0, |r| r.lines.len()))
        .filter(|&i| runs[0].lines[i].mask > 0.0)
        .collect();
    let error = |r: &Run, skip: Option<usize>| -> f64 {
        rms_db(masked.iter().filter(|&&i| Some(i) != skip).map(|&i| {
            (
                r.lines[i].predicted_elevation,
                r.lines[i].measured_elevation,
            )
        }))
    };
    let argmin = |skip: Option<usize>| -> usize {
        (0..runs.len())
            .min_by(|&a, &b| error(&runs[a], skip).total_cmp(&error(&runs[b], skip)))
            .unwrap_or(0)
    };
    let left_out = masked
        .iter()
        .map(|&i| {
            let l = &runs[argmin(Some(i))].lines[i];
            (l.predicted_elevation, l.measured_elevation)
        })
        .collect();
    Ok(ParameterFit {
        name: name.to_string(),
        values: values.to_vec(),
        best: argmin(None),
        runs,
        left_out,
    })
}

/// The report of `blurlab predict validate meese2007`: the committed stages, the oriented
/// side-by-side stage with its cross-orientation weight fitted (and leave-one-out).
pub fn validate(series: &[Series], weights: &[f64], progress: &dyn Progress) -> Result<String> {
    if weights.is_empty() {
        anyhow::bail!("no cross-orientation weight to search; expected at least one in [0, 1]");
    }
    let mut runs = run(series, &stages(), progress)?;
    let fit = fit_cross_weight(series, weights, progress)?;
    let mut best = fit.runs[fit.best].clone();
    best.name = format!("side-by-side (w = {})", fit.values[fit.best]);
    runs.push(best);
    Ok(markdown(&runs) + &fit_markdown(&fit))
}

/// A contrast as a percentage, or "> 100%".
fn percent(c: Option<f64>) -> String {
    c.map_or_else(|| "> 100%".into(), |c| format!("{:.2}%", 100.0 * c))
}

/// A ratio to two decimals, or "-".
fn ratio(r: Option<f64>) -> String {
    r.map_or_else(|| "-".into(), |r| format!("{r:.2}"))
}

/// The report: per threshold the measured and each model's threshold and elevation, then the
/// RMS errors; its last line names the lowest elevation error.
pub fn markdown(runs: &[Run]) -> String {
    let mut s = String::from(
        "# Cross-orientation masking: Meese et al. (2007)\n\n\
         Detection threshold T of a horizontal grating patch under a superimposed vertical \
         one (the mask), and the elevation T / T0 over the unmasked threshold; the model's \
         stimuli and their geometry: analysis/tests/data/meese2007/README.md. Predicted \
         thresholds are at ModelFest's presentation; elevations from the static frames.\n\n",
    );
    let mut head = String::from("| observer | c/deg | mask | T | T / T0 |");
    let mut rule = String::from("|---|---|---|---|---|");
    for r in runs {
        let _ = write!(head, " {} T | {} T / T0 |", r.name, r.name);
        rule.push_str("---|---|");
    }
    let _ = writeln!(s, "{head}\n{rule}");
    let Some(first) = runs.first() else {
        return s;
    };
    for (i, l) in first.lines.iter().enumerate() {
        let _ = write!(
            s,
            "| {} | {} | {} | {} | {:.2} |",
            l.observer,
            l.spatial_frequency_cpd,
            percent(Some(l.mask)),
            percent(Some(l.measured)),
            l.measured_elevation
        );
        for r in runs {
            let p = &r.lines[i];
            let _ = write!(
                s,
                " {} | {} |",
                percent(p.predicted),
                ratio(p.predicted_elevation)
            );
        }
        s.push('\n');
    }
    let masked = first.lines.iter().filter(|l| l.mask > 0.0).count();
    let _ = writeln!(
        s,
        "\nRMS error (dB) | elevations ({masked}) | thresholds ({})\n---|---|---",
        first.lines.len()
    );
    for r in runs {
        let _ = writeln!(
            s,
            "{} | {:.2} | {:.2}",
            r.name,
            elevation_rms_db(&r.lines),
            threshold_rms_db(&r.lines)
        );
    }
    if let Some(best) = runs
        .iter()
        .min_by(|a, b| elevation_rms_db(&a.lines).total_cmp(&elevation_rms_db(&b.lines)))
    {
        let _ = write!(
            s,
            "\nLowest elevation error: {} at {:.2} dB over {masked} masked thresholds",
            best.name,
            elevation_rms_db(&best.lines)
        );
    }
    s
}

/// The fit as Markdown: the error at each value, the best, leave-one-out.
pub fn fit_markdown(fit: &ParameterFit) -> String {
    let mut s = format!(
        "\n## {} fitted to the elevations\n\n| {} | RMS error of the elevations (dB) |\n|---|---|\n",
        fit.name, fit.name
    );
    for (v, r) in fit.values.iter().zip(&fit.runs) {
        let mark = if std::ptr::eq(r, &fit.runs[fit.best]) {
            " (best)"
        } else {
            ""
        };
        let _ = writeln!(s, "| {v}{mark} | {:.2} |", elevation_rms_db(&r.lines));
    }
    let _ = write!(
        s,
        "\n{} = {}: RMS error {:.2} dB; leave-one-out (each elevation predicted with the value \
         fitted to the other {}) {:.2} dB",
        fit.name,
        fit.values[fit.best],
        elevation_rms_db(&fit.runs[fit.best].lines),
        fit.left_out.len().saturating_sub(1),
        fit.loo_rms_db()
    );
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_are_in_decibels_and_a_missing_threshold_counts_as_full_contrast() {
        // Twice and half the measured: 20 log10 2 = 6.02 dB either way.
        let e = rms_db([(Some(0.02), 0.01), (Some(0.005), 0.01)].into_iter());
        assert!((e - 6.0206).abs() < 1e-3, "{e}");
        // Not visible up to 100% against a measured 10%: 20 dB.
        let e = rms_db([(None, 0.1)].into_iter());
        assert!((e - 20.0).abs() < 1e-9, "{e}");
        assert_eq!(rms_db([(Some(0.3), 0.3)].into_iter()), 0.0);
    }
}
