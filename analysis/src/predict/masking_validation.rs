//! The decision stages against human masking data: Meese et al. 2007's cross-orientation
//! masking ([`super::meese`]) predicted by each stage, and the errors in dB, of the threshold
//! elevations (the validated figure: what masking does) and of the absolute thresholds (at
//! ModelFest's presentation, for reference). `blurlab predict validate meese2007`.

use super::meese::{Line, Series, elevation_rms_db, predict, threshold_rms_db};
use super::video::{Comparison, Filters};
use anyhow::Result;
use renderer::progress::Progress;
use std::fmt::Write as _;

/// One model's predictions.
pub struct Run {
    /// The stage's name as the report gives it.
    pub name: String,
    pub lines: Vec<Line>,
}

/// A model to run: its name and how to build its filters.
pub struct Model {
    pub name: String,
    pub make: Box<dyn Fn() -> Result<Filters> + Sync>,
}

/// The committed decision stages: `difference` and `side-by-side`.
pub fn stages() -> Vec<Model> {
    [Comparison::Difference, Comparison::SideBySide]
        .into_iter()
        .map(|c| Model {
            name: super::stage::Stage::given(c).name().to_string(),
            make: Box::new(move || super::meese::filters(c)),
        })
        .collect()
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

#[cfg(test)]
mod tests {
    use super::super::meese::rms_db;

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
