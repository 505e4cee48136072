//! Cross-orientation masking data of Meese, Summers, Holmes & Wallis (2007, "Contextual
//! modulation involves suppression and facilitation from the center and the surround", JOV
//! 7(4):7): the detection threshold of a horizontal grating patch against the contrast of a
//! superimposed vertical (orthogonal) grating, at 1 c/deg (observer DHB) and 7 c/deg (DJH),
//! loaded from `analysis/tests/data/meese2007/` (its README gives the digitisation's source and
//! the stimulus geometry chosen), and the model's thresholds for the same stimuli.
//!
//! Why these data: a decision stage that masks noise by the scene's content must not mask
//! across orientations as strongly as within. The model sees each stimulus as one static
//! frame, L(x) = L0 (1 + C_t w(x) cos(2 pi f y) + C_m w(x) cos(2 pi f x)) at ModelFest's
//! luminance (30 cd/m^2) and 60 pixels per degree, in a 2IFC whose reference is the mask alone
//! (Meese's mask was in both intervals): the threshold is the target contrast C_t at which
//! k Q reaches the 2IFC 84% point, as for ModelFest ([`super::modelfest`]). The validated
//! figure is the threshold elevation T / T0 (masked over unmasked threshold): the paper's
//! presentation (duration, time course) is not ModelFest's, which offsets absolute thresholds
//! but not their ratio. Absolute thresholds are reported too, at ModelFest's presentation:
//! the unmasked threshold from ModelFest's time course ([`modelfest::response`]), times
//! the static frame's elevation.

use super::modelfest::{self, MEAN_LUMINANCE};
use crate::observer::model::decision_stage::SideBySide;
use crate::observer::model::pooling::{FITTED, Grid, Placement};
use crate::observer::model::proportion_correct::{CRITERION, DEFAULT_K, two_ifc_d_prime_for};
use crate::observer::model::shape;
use crate::observer::model::video::{Filters, Viewing, frame_differences};
use anyhow::{Context, Result, bail};
use serde::Deserialize;
use std::path::Path;

pub mod fit;

/// Pixels per degree of the model's frames: 8.6 pixels per cycle at 7 c/deg, and a quarter of
/// the pixels ModelFest's 120 would take (the validation searches many thresholds).
pub const PIXELS_PER_DEGREE: f64 = 60.0;
/// Side of the model's frames, pixels (4.27 deg: the 1 c/deg patch, 4 cycles across to its
/// edge, fits with room for the adaptation's blur).
pub const SIDE: usize = 256;
/// The window's flat top, radius in carrier cycles.
const FLAT_CYCLES: f64 = 1.0;
/// The window's raised-cosine edge, width in carrier cycles.
const EDGE_CYCLES: f64 = 1.0;
/// The highest target contrast searched (Michelson): a threshold above it is not a threshold.
const MAX_CONTRAST: f64 = 1.0;

/// One measured threshold.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    /// Michelson contrast of the orthogonal mask (0: no mask).
    pub mask: f64,
    /// Michelson contrast of the target at threshold.
    pub threshold: f64,
}

/// One observer's masking function at one spatial frequency.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    pub observer: String,
    pub spatial_frequency_cpd: f64,
    /// The threshold without a mask.
    pub no_mask: f64,
    /// The thresholds with a mask, in the file's order.
    pub masked: Vec<Point>,
}

/// A row of `thresholds.csv`.
#[derive(Deserialize)]
struct Row {
    observer: String,
    spatial_frequency_cpd: f64,
    mask_contrast: f64,
    threshold_contrast: f64,
}

const COLUMNS: &str = "observer, spatial_frequency_cpd, mask_contrast, threshold_contrast";

/// Load `thresholds.csv` of the data set in `dir`: per (observer, spatial frequency) one row
/// with mask contrast 0 (the no-mask threshold) and at least one with a mask.
pub fn load(dir: &Path) -> Result<Vec<Series>> {
    let path = dir.join("thresholds.csv");
    let mut reader = csv::Reader::from_path(&path).with_context(|| {
        format!(
            "cannot read {}: expected the Meese et al. 2007 folder (thresholds.csv)",
            path.display()
        )
    })?;
    let mut out: Vec<Series> = Vec::new();
    let mut no_mask_line: Vec<Option<usize>> = Vec::new();
    // (series, mask contrast, line) of every masked row, to refuse a row given twice.
    let mut masked_lines: Vec<(usize, f64, usize)> = Vec::new();
    for (i, row) in reader.deserialize::<Row>().enumerate() {
        let line = i + 2;
        let at = || format!("{} line {line}", path.display());
        let row = row.with_context(|| format!("{}: expected {COLUMNS}", at()))?;
        check(&row, &at())?;
        let k = match out.iter().position(|s| {
            s.observer == row.observer && s.spatial_frequency_cpd == row.spatial_frequency_cpd
        }) {
            Some(k) => k,
            None => {
                out.push(Series {
                    observer: row.observer.clone(),
                    spatial_frequency_cpd: row.spatial_frequency_cpd,
                    no_mask: f64::NAN,
                    masked: Vec::new(),
                });
                no_mask_line.push(None);
                out.len() - 1
            }
        };
        if row.mask_contrast == 0.0 {
            if let Some(first) = no_mask_line[k] {
                bail!(
                    "{}: a second no-mask threshold (mask_contrast 0) for observer {} at {} \
                     c/deg; the first is on line {first}",
                    at(),
                    row.observer,
                    row.spatial_frequency_cpd
                );
            }
            no_mask_line[k] = Some(line);
            out[k].no_mask = row.threshold_contrast;
        } else {
            if let Some(&(_, _, first)) = masked_lines
                .iter()
                .find(|&&(j, mask, _)| j == k && mask == row.mask_contrast)
            {
                bail!(
                    "{}: a second threshold for observer {} at {} c/deg with mask_contrast {}; \
                     the first is on line {first} (each mask contrast once per series)",
                    at(),
                    row.observer,
                    row.spatial_frequency_cpd,
                    row.mask_contrast
                );
            }
            masked_lines.push((k, row.mask_contrast, line));
            out[k].masked.push(Point {
                mask: row.mask_contrast,
                threshold: row.threshold_contrast,
            });
        }
    }
    if out.is_empty() {
        bail!("{}: no thresholds; expected {COLUMNS}", path.display());
    }
    for (s, line) in out.iter().zip(&no_mask_line) {
        if line.is_none() || s.masked.is_empty() {
            bail!(
                "{}: observer {} at {} c/deg has {} no-mask row(s) and {} masked row(s); \
                 expected exactly one row with mask_contrast 0 and at least one with a mask \
                 (the threshold elevation is the masked threshold over the no-mask one)",
                path.display(),
                s.observer,
                s.spatial_frequency_cpd,
                usize::from(line.is_some()),
                s.masked.len()
            );
        }
    }
    Ok(out)
}

/// A row's values: contrasts in [0, 1] (thresholds above 0), a positive spatial frequency.
fn check(row: &Row, at: &str) -> Result<()> {
    if row.observer.trim().is_empty() {
        bail!("{at}: field `observer` is empty; expected the observer's initials");
    }
    if !(row.spatial_frequency_cpd.is_finite() && row.spatial_frequency_cpd > 0.0) {
        bail!(
            "{at}: field `spatial_frequency_cpd` is {}; expected a positive number of cycles \
             per degree",
            row.spatial_frequency_cpd
        );
    }
    if !(0.0..=1.0).contains(&row.mask_contrast) {
        bail!(
            "{at}: field `mask_contrast` is {}; expected a Michelson contrast in [0, 1] \
             (0: no mask)",
            row.mask_contrast
        );
    }
    if !(row.threshold_contrast > 0.0 && row.threshold_contrast <= 1.0) {
        bail!(
            "{at}: field `threshold_contrast` is {}; expected a Michelson contrast in (0, 1]",
            row.threshold_contrast
        );
    }
    Ok(())
}

/// The patch window w(r) at `r` carrier cycles from the centre: 1 on the flat top, a raised
/// cosine to 0 over the edge.
fn window(r: f64) -> f64 {
    if r <= FLAT_CYCLES {
        1.0
    } else if r >= FLAT_CYCLES + EDGE_CYCLES {
        0.0
    } else {
        0.5 * (1.0 + (std::f64::consts::PI * (r - FLAT_CYCLES) / EDGE_CYCLES).cos())
    }
}

/// The luminance frame: a horizontal target of contrast `target` and a vertical mask of
/// contrast `mask`, both of `cpd` cycles per degree in one window, cosine phase at the centre.
pub fn frame(cpd: f64, target: f64, mask: f64) -> Vec<f32> {
    frame_at(cpd, target, mask, SIDE, PIXELS_PER_DEGREE)
}

/// [`frame`] on `side` x `side` pixels at `ppd` pixels per degree.
fn frame_at(cpd: f64, target: f64, mask: f64, side: usize, ppd: f64) -> Vec<f32> {
    let c = side as f64 / 2.0;
    let cycles_per_px = cpd / ppd;
    let omega = 2.0 * std::f64::consts::PI * cycles_per_px;
    (0..side * side)
        .map(|i| {
            let (x, y) = ((i % side) as f64 - c, (i / side) as f64 - c);
            let w = window((x * x + y * y).sqrt() * cycles_per_px);
            let l = 1.0 + w * (target * (omega * y).cos() + mask * (omega * x).cos());
            (MEAN_LUMINANCE * l) as f32
        })
        .collect()
}

/// The viewing of the model's static frames.
pub fn viewing() -> Viewing {
    Viewing {
        width: SIDE,
        height: SIDE,
        frames: 1,
        fps: modelfest::FPS,
        pixels_per_degree: PIXELS_PER_DEGREE,
        mean_luminance: MEAN_LUMINANCE,
    }
}

/// The model's filters for these frames (the committed pooling and CSF shape) with the
/// side-by-side stage set as `side_by_side`, or `None`: the difference stage.
pub fn filters(side_by_side: Option<SideBySide>) -> Result<Filters> {
    let f = Filters::new(viewing(), FITTED.channels, shape::FITTED)?;
    Ok(match side_by_side {
        Some(s) => f.side_by_side(s),
        None => f,
    })
}

/// d' = k Q of the pair (mask + target, mask).
pub fn d_prime(filters: &mut Filters, cpd: f64, target: f64, mask: f64) -> Result<f64> {
    let test = frame(cpd, target, mask);
    let reference = frame(cpd, 0.0, mask);
    let q = frame_differences(filters, &Grid::one(FITTED), Placement::Centre, |_| {
        Ok((test.clone(), reference.clone()))
    })?;
    Ok(DEFAULT_K * q[0][0])
}

/// The static frame's threshold: the target contrast at which d' reaches the 2IFC 84% point,
/// by regula falsi on log d' against log contrast (d' grows with the target; near a power of
/// it, so a few steps suffice). `None`: not visible up to [`MAX_CONTRAST`].
pub fn threshold(filters: &mut Filters, cpd: f64, mask: f64) -> Result<Option<f64>> {
    let want = two_ifc_d_prime_for(CRITERION).context("the criterion is inside (0.5, 1)")?;
    let mut f = |c: f64| -> Result<f64> { Ok((d_prime(filters, cpd, c, mask)? / want).ln()) };
    // Bracket: halve or double from 1% until the sign changes.
    let (mut a, mut fa) = (0.01f64.ln(), f(0.01)?);
    let step = if fa < 0.0 { 2f64.ln() } else { -(2f64.ln()) };
    let (mut b, mut fb) = (a, fa);
    while fa.signum() == fb.signum() {
        (a, fa) = (b, fb);
        b += step;
        if b > MAX_CONTRAST.ln() + 1e-12 {
            return Ok(None);
        }
        if b < 1e-6f64.ln() {
            bail!(
                "a target of 1e-6 contrast is already visible at {cpd} c/deg: the model is broken"
            );
        }
        fb = f(b.exp())?;
    }
    // Illinois regula falsi: keeps the bracket, converges superlinearly.
    let mut side = 0;
    for _ in 0..60 {
        let c = (a * fb - b * fa) / (fb - fa);
        let fc = f(c.exp())?;
        if fc.abs() < 1e-6 || (b - a).abs() < 1e-9 {
            return Ok(Some(c.exp()));
        }
        if fc.signum() == fb.signum() {
            (b, fb) = (c, fc);
            if side == -1 {
                fa /= 2.0;
            }
            side = -1;
        } else {
            (a, fa) = (c, fc);
            if side == 1 {
                fb /= 2.0;
            }
            side = 1;
        }
    }
    Ok(Some(((a + b) / 2.0).exp()))
}

/// One threshold of the data set, measured and predicted.
#[derive(Clone, Debug, PartialEq)]
pub struct Line {
    pub observer: String,
    pub spatial_frequency_cpd: f64,
    /// Michelson contrast of the mask (0: none).
    pub mask: f64,
    pub measured: f64,
    /// At ModelFest's presentation (see the module's text); `None`: not visible up to 100%.
    pub predicted: Option<f64>,
    /// Measured threshold over the series' unmasked one (1 for the unmasked row).
    pub measured_elevation: f64,
    /// The static frame's threshold over its unmasked one.
    pub predicted_elevation: Option<f64>,
}

/// The unmasked threshold of a patch at ModelFest's presentation (time course, 1 s video),
/// from the model's separable detection response ([`modelfest::response`]).
fn presented_threshold(cpd: f64) -> Result<f64> {
    // ModelFest's viewing is 120 px/deg: the same patch in degrees takes twice the pixels.
    let (side, ppd) = (2 * SIDE, modelfest::PIXELS_PER_DEGREE);
    let contrast: Vec<f32> = frame_at(cpd, 1.0, 0.0, side, ppd)
        .iter()
        .map(|&l| l / MEAN_LUMINANCE as f32 - 1.0)
        .collect();
    let s = modelfest::Stimulus {
        number: 0,
        name: format!("meese {cpd} c/deg"),
        family: "meese".into(),
        width: side,
        height: side,
        contrast,
        measured: f64::NAN,
        observations: 0,
    };
    let q1 = modelfest::response(&s, &Grid::one(FITTED), &[shape::FITTED])?[0];
    let want = two_ifc_d_prime_for(CRITERION).context("the criterion is inside (0.5, 1)")?;
    Ok(want / (DEFAULT_K * q1))
}

/// Every threshold of `series` through the model built by `make` (the searches run in
/// parallel, each thread on filters of its own).
pub fn predict(
    series: &[Series],
    make: &(dyn Fn() -> Result<Filters> + Sync),
) -> Result<Vec<Line>> {
    use rayon::prelude::*;
    // Every (series, mask) search, the unmasked first in each series.
    let jobs: Vec<(usize, f64)> = series
        .iter()
        .enumerate()
        .flat_map(|(i, s)| {
            std::iter::once((i, 0.0)).chain(s.masked.iter().map(move |p| (i, p.mask)))
        })
        .collect();
    let found: Vec<Option<f64>> = jobs
        .par_iter()
        .map_init(make, |filters, &(i, mask)| {
            let filters = filters.as_mut().map_err(|e| anyhow::anyhow!("{e:#}"))?;
            threshold(filters, series[i].spatial_frequency_cpd, mask)
        })
        .collect::<Result<_>>()?;
    let mut out = Vec::with_capacity(jobs.len());
    let mut next = 0;
    for s in series {
        let cpd = s.spatial_frequency_cpd;
        let t0 = found[next]
            .with_context(|| format!("the unmasked {cpd} c/deg patch is not visible at 100%"))?;
        let presented = presented_threshold(cpd)?;
        let measured =
            std::iter::once((0.0, s.no_mask)).chain(s.masked.iter().map(|p| (p.mask, p.threshold)));
        for ((mask, measured), t) in measured.zip(&found[next..]) {
            let elevation = t.map(|t| t / t0);
            out.push(Line {
                observer: s.observer.clone(),
                spatial_frequency_cpd: cpd,
                mask,
                measured,
                predicted: elevation.map(|e| presented * e),
                measured_elevation: measured / s.no_mask,
                predicted_elevation: elevation,
            });
        }
        next += 1 + s.masked.len();
    }
    Ok(out)
}

/// RMS error, dB, of predicted against measured values (`None` predictions count as 100%
/// contrast, the search's limit: an error, not a gap).
pub fn rms_db(pairs: impl Iterator<Item = (Option<f64>, f64)>) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for (p, m) in pairs {
        let e = 20.0 * (p.unwrap_or(MAX_CONTRAST) / m).log10();
        sum += e * e;
        n += 1;
    }
    (sum / n.max(1) as f64).sqrt()
}

/// The elevations' RMS error (the masked rows only: the unmasked row's is 1 by definition).
pub fn elevation_rms_db(lines: &[Line]) -> f64 {
    rms_db(
        lines
            .iter()
            .filter(|l| l.mask > 0.0)
            .map(|l| (l.predicted_elevation, l.measured_elevation)),
    )
}

/// The absolute thresholds' RMS error.
pub fn threshold_rms_db(lines: &[Line]) -> f64 {
    rms_db(lines.iter().map(|l| (l.predicted, l.measured)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(csv: &str) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("thresholds.csv"), csv).unwrap();
        dir
    }

    fn err(csv: &str) -> String {
        let dir = write(csv);
        format!("{:#}", load(dir.path()).unwrap_err())
    }

    const HEADER: &str = "observer,spatial_frequency_cpd,mask_contrast,threshold_contrast\n";

    #[test]
    fn the_committed_data_set_loads() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/meese2007");
        let s = load(&dir).unwrap();
        assert_eq!(s.len(), 2);
        assert_eq!(
            (s[0].observer.as_str(), s[0].spatial_frequency_cpd),
            ("DHB", 1.0)
        );
        assert_eq!(
            (s[1].observer.as_str(), s[1].spatial_frequency_cpd),
            ("DJH", 7.0)
        );
        assert_eq!(s.iter().map(|s| s.masked.len()).sum::<usize>(), 12);
        // The digitisation's dB re 1%: DHB's no-mask -1.67 dB, DJH's 8.175 dB.
        let db = |c: f64| 20.0 * (100.0 * c).log10();
        assert!((db(s[0].no_mask) + 1.6712).abs() < 1e-3);
        assert!((db(s[1].no_mask) - 8.175).abs() < 1e-3);
    }

    #[test]
    fn a_bad_file_is_refused_naming_file_line_and_field() {
        let e = err(&format!("{HEADER}A,1,0,0.01\nA,1,0.1,1.5\n"));
        assert!(e.contains("thresholds.csv line 3"), "{e}");
        assert!(e.contains("threshold_contrast"), "{e}");
        let e = err(&format!("{HEADER}A,-1,0,0.01\n"));
        assert!(
            e.contains("line 2") && e.contains("spatial_frequency_cpd"),
            "{e}"
        );
        let e = err(&format!("{HEADER}A,1,0,0.01\nA,1,x,0.02\n"));
        assert!(
            e.contains("line 3") && e.contains("expected observer"),
            "{e}"
        );
        let e = err(&format!("{HEADER}A,1,0,0.01\nA,1,0,0.02\nA,1,0.1,0.02\n"));
        assert!(e.contains("line 3") && e.contains("line 2"), "{e}");
        // The same masked row twice (a copy-paste slip would otherwise weigh it double).
        let e = err(&format!(
            "{HEADER}A,1,0,0.01\nA,1,0.1,0.02\nB,1,0.1,0.02\nA,1,0.1,0.03\n"
        ));
        assert!(e.contains("line 5") && e.contains("line 3"), "{e}");
        assert!(e.contains("mask_contrast 0.1"), "{e}");
        // A series without its no-mask row, or without a mask.
        let e = err(&format!("{HEADER}A,1,0.1,0.02\n"));
        assert!(e.contains("observer A") && e.contains("0 no-mask"), "{e}");
        let e = err(&format!("{HEADER}A,1,0,0.02\n"));
        assert!(e.contains("0 masked"), "{e}");
        let e = err(HEADER);
        assert!(e.contains("no thresholds"), "{e}");
        let e = format!("{:#}", load(Path::new("/nonexistent")).unwrap_err());
        assert!(e.contains("/nonexistent/thresholds.csv"), "{e}");
    }

    #[test]
    fn the_frame_is_the_two_gratings_in_their_window() {
        let f = frame(1.0, 0.02, 0.3);
        let c = SIDE / 2;
        let l0 = MEAN_LUMINANCE as f32;
        // Centre: both cosines at their peak.
        assert!((f[c * SIDE + c] / l0 - 1.32).abs() < 1e-6);
        // Half a cycle up (30 px at 1 c/deg, still on the flat top): the target at its trough.
        assert!((f[(c - 30) * SIDE + c] / l0 - (1.0 - 0.02 + 0.3)).abs() < 1e-5);
        // Beyond 2 cycles (120 px) the field is uniform.
        assert_eq!(f[c * SIDE + c + 121], l0);
        assert_eq!(f[0], l0);
        // At 7 c/deg the window is 7 times smaller: 2 cycles = 17.1 px.
        let g = frame(7.0, 0.0, 0.5);
        assert_eq!(g[c * SIDE + c + 18], l0);
        assert!(g[c * SIDE + c + 16] != l0);
    }

    #[test]
    fn the_threshold_search_lands_on_the_criterion() {
        // The difference stage on a blank field is linear in the target's contrast, so the
        // search's answer can be checked in closed form: d'(T) = d'_84 and d'(2T) = 2 d'_84.
        let mut f = filters(None).unwrap();
        let t = threshold(&mut f, 7.0, 0.0).unwrap().unwrap();
        let want = two_ifc_d_prime_for(CRITERION).unwrap();
        assert!((d_prime(&mut f, 7.0, t, 0.0).unwrap() / want - 1.0).abs() < 1e-4);
        assert!((d_prime(&mut f, 7.0, 2.0 * t, 0.0).unwrap() / want - 2.0).abs() < 1e-3);
        // A visible mask raises the threshold (the model has no facilitation), and the
        // static frame's unmasked threshold at 7 c/deg is a plausible 0.1-10%.
        let tm = threshold(&mut f, 7.0, 0.45).unwrap().unwrap();
        assert!(tm > 1.5 * t, "{tm} against {t}");
        assert!(t > 1e-3 && t < 0.1, "{t}");
    }

    #[test]
    fn an_orthogonal_mask_masks_little_once_orientations_are_compared_apart() {
        // Meese's strongest mask (45%, orthogonal) at 7 c/deg: the observer's elevation is
        // 0.85. Pooled before the comparison, the mask adds in quadrature to the target's
        // amplitude and raises its threshold about 20x; compared per orientation channel with
        // w = 0, the target's channel holds only what the small patch's spectrum spreads past
        // 45 deg from the mask's orientation (1.71 on 28 Nov): within the observers' range at
        // this mask (0.85 at 7 c/deg, 2.9 at 1 c/deg), a fifth or less of the pooled.
        let elevation = |orientation| {
            let s = SideBySide {
                orientation,
                ..SideBySide::committed(FITTED.space)
            };
            let mut f = filters(Some(s)).unwrap();
            let t0 = threshold(&mut f, 7.0, 0.0).unwrap().unwrap();
            threshold(&mut f, 7.0, 0.45).unwrap().unwrap() / t0
        };
        let pooled = elevation(None);
        let apart = elevation(Some(crate::observer::model::orientation::COMMITTED));
        assert!(pooled > 10.0, "{pooled}");
        assert!(apart > 0.9 && apart < 2.9, "{apart}");
        assert!(pooled > 5.0 * apart, "{pooled} against {apart}");
    }
}
