//! `predicted.csv` (format `blurlab-predicted/1`): how visible each test stimulus's difference
//! from its reference is, as `blurlab predict` computes it from the display frames, and the
//! proportion correct that visibility gives in the two-pair task. The analysis writes it; the
//! simulated observer (`simulate --observer predicted.csv`) answers from it.
//!
//! The file is CSV whose first line is `# format: blurlab-predicted/1`, then a header row and
//! one row per test stimulus (columns: [`PredictedRow`]). Readers refuse any other first line.
//!
//! The decision rule of version 1 is the differencing rule for the two-pair task (Macmillan &
//! Creelman 2005, ch. 9, "4IAX"/dual-pair, differencing strategy): the observer picks the pair
//! whose two videos differ more on one internal decision axis with unit-variance Gaussian noise
//! per presentation. With d' the separation of test and reference on that axis,
//!
//! ```text
//! p_c = Phi(d'/2)^2 + Phi(-d'/2)^2
//! ```
//!
//! (derivation and a Monte Carlo check of the task in
//! `analysis::observer::model::proportion_correct`).

use crate::trials::Condition;
use anyhow::{Context, Result, bail};
use renderer::condition::{PointSetKind, TimeFilter};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// The format tag on the first line of a prediction file.
pub const PREDICTED_FORMAT: &str = "blurlab-predicted/1";

/// The first line of every prediction file.
pub fn format_line() -> String {
    format!("# format: {PREDICTED_FORMAT}")
}

/// One test stimulus's prediction (one CSV row). Units: `q` is the pooled visible difference
/// in threshold units of the contrast model (1 = the CSF's detection threshold of a grating);
/// `d_prime = k q` with `k` the model's sensitivity constant.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PredictedRow {
    pub scene: String,
    pub point_set: PointSetKind,
    pub time_filter: TimeFilter,
    /// Samples per pixel of the test video.
    pub spp: u32,
    pub test_stimulus: String,
    pub reference_stimulus: String,
    /// Pooled visible difference over the whole video (space, time, bands, channels).
    pub q: f64,
    /// Sensitivity constant the row's d' was computed with.
    pub k: f64,
    pub d_prime: f64,
    /// Predicted proportion correct of the two-pair task.
    pub p_correct: f64,
    /// Spread over frames: proportion correct from single frames' visible difference.
    pub p_frame_min: f64,
    pub p_frame_median: f64,
    pub p_frame_max: f64,
    /// Frames compared.
    pub frames: u32,
}

impl PredictedRow {
    /// The row's condition. (The table keeps scene, point set and time filter as its first
    /// three columns.)
    pub fn condition(&self) -> Condition {
        Condition::new(self.scene.clone(), self.point_set, self.time_filter)
    }
}

/// The two-pair task's proportion correct at separation `d_prime` (differencing rule).
pub fn two_pair_p_correct(d_prime: f64) -> f64 {
    let a = phi(0.5 * d_prime);
    let b = phi(-0.5 * d_prime);
    a * a + b * b
}

/// Standard normal CDF of the decision rule (statrs' erfc).
///
/// The workspace has two normal CDFs, on purpose; this is where that is justified. The
/// analysis's `sigmoid::phi` (its own erfc, a few ulps relative in both tails) serves the
/// likelihood of a cumulative-normal fit, where a step-like fit evaluates Phi far in its tails
/// and statrs' erfc (1e-10 relative off near x = 0.5) would bias the optimum. This one serves
/// the two-pair decision rule and its inverses (`analysis::observer::model::proportion_correct`),
/// where d' is known to a few percent: statrs is accurate enough, and it fixes the bytes of every
/// `predicted.csv` written and of every predicted observer's answers, which the accurate erfc
/// would change in the last digits. The experiment crate sits below the analysis and does not
/// carry its special functions.
pub fn phi(z: f64) -> f64 {
    0.5 * statrs::function::erf::erfc(-z / std::f64::consts::SQRT_2)
}

/// A loaded prediction: each condition's d' at its rendered levels.
#[derive(Clone, Debug, PartialEq)]
pub struct PredictedTable {
    pub rows: Vec<PredictedRow>,
    curves: BTreeMap<Condition, Curve>,
}

/// d' at the rendered levels of one condition, sorted by spp.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    pub points: Vec<(f64, f64)>,
}

impl Curve {
    /// d' at any spp: linear in (ln spp, ln d') between rendered levels, and beyond them along
    /// the nearest segment (noise amplitude follows a power of spp); linear in ln spp where a
    /// d' is 0 (a level identical to its reference).
    pub fn d_prime_at(&self, spp: f64) -> f64 {
        let p = &self.points;
        if p.len() == 1 {
            return p[0].1;
        }
        let x = spp.ln();
        let i = match p.iter().position(|&(s, _)| s.ln() >= x) {
            Some(0) => 0,
            Some(i) => i - 1,
            None => p.len() - 2,
        };
        let ((s0, d0), (s1, d1)) = (p[i], p[i + 1]);
        let w = (x - s0.ln()) / (s1.ln() - s0.ln());
        if d0 > 0.0 && d1 > 0.0 {
            (d0.ln() + w * (d1.ln() - d0.ln())).exp()
        } else {
            (d0 + w * (d1 - d0)).max(0.0)
        }
    }

    /// Proportion correct at `spp`.
    pub fn p_correct_at(&self, spp: f64) -> f64 {
        two_pair_p_correct(self.d_prime_at(spp))
    }

    /// The spp where the proportion correct falls to `target` (bisection in ln spp over
    /// [1e-6, 1e9] spp: d' falls with spp along every segment); `None` if it never does there.
    pub fn spp_at(&self, target: f64) -> Option<f64> {
        self.spp_between(target, 1e-6, 1e9)
    }

    /// As [`Curve::spp_at`], searching between `from` and `to` spp only (one segment between
    /// two rendered levels: no extrapolation).
    pub fn spp_between(&self, target: f64, from: f64, to: f64) -> Option<f64> {
        let (mut lo, mut hi) = (from.ln(), to.ln());
        let f = |x: f64| self.p_correct_at(x.exp()) - target;
        if f(lo) < 0.0 || f(hi) > 0.0 {
            return None;
        }
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if f(mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Some((0.5 * (lo + hi)).exp())
    }
}

impl PredictedTable {
    pub fn load(path: &Path) -> Result<Self> {
        let text = renderer::utf8::read(path, "prediction file")?;
        Self::parse(path, &text)
    }

    pub fn parse(path: &Path, text: &str) -> Result<Self> {
        let first = text.lines().next().unwrap_or("");
        if first.trim() != format_line() {
            bail!(
                "{}: line 1 is {:?}; a prediction file starts with {:?}",
                path.display(),
                renderer::quote::short(first),
                format_line()
            );
        }
        let body = &text[first.len()..];
        let mut reader = csv::Reader::from_reader(body.trim_start_matches(['\r', '\n']).as_bytes());
        let mut rows = Vec::new();
        for (i, r) in reader.deserialize::<PredictedRow>().enumerate() {
            // Line 1 is the format, line 2 the header.
            let row = r.with_context(|| format!("{}: line {}", path.display(), i + 3))?;
            check_row(&row)
                .map_err(|e| anyhow::anyhow!("{}: line {}: {e}", path.display(), i + 3))?;
            rows.push(row);
        }
        if rows.is_empty() {
            bail!(
                "{}: no prediction rows after the header line",
                path.display()
            );
        }
        Ok(Self::from_rows(rows))
    }

    pub fn from_rows(rows: Vec<PredictedRow>) -> Self {
        let mut curves: BTreeMap<Condition, Curve> = BTreeMap::new();
        for r in &rows {
            let c = r.condition();
            curves
                .entry(c)
                .or_insert(Curve { points: Vec::new() })
                .points
                .push((r.spp as f64, r.d_prime));
        }
        for c in curves.values_mut() {
            c.points.sort_by(|a, b| a.0.total_cmp(&b.0));
            c.points.dedup_by(|a, b| a.0 == b.0);
        }
        Self { rows, curves }
    }

    /// The CSV text, format line first.
    pub fn to_csv(&self) -> Result<String> {
        let mut w = csv::Writer::from_writer(Vec::new());
        for r in &self.rows {
            w.serialize(r)?;
        }
        let body = String::from_utf8(w.into_inner()?)?;
        Ok(format!("{}\n{body}", format_line()))
    }

    pub fn curve(&self, c: &Condition) -> Option<&Curve> {
        self.curves.get(c)
    }

    pub fn conditions(&self) -> impl Iterator<Item = (&Condition, &Curve)> {
        self.curves.iter()
    }
}

fn check_row(r: &PredictedRow) -> Result<()> {
    if r.spp == 0 {
        bail!("field `spp` is 0; expected samples per pixel >= 1");
    }
    for (name, v) in [("q", r.q), ("k", r.k), ("d_prime", r.d_prime)] {
        if !(v.is_finite() && v >= 0.0) {
            bail!("field `{name}` is {v}; expected a finite number >= 0");
        }
    }
    for (name, v) in [
        ("p_correct", r.p_correct),
        ("p_frame_min", r.p_frame_min),
        ("p_frame_median", r.p_frame_median),
        ("p_frame_max", r.p_frame_max),
    ] {
        if !(0.5..=1.0).contains(&v) {
            bail!("field `{name}` is {v}; expected a proportion correct in [0.5, 1]");
        }
    }
    Ok(())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    pub(crate) fn row(scene: &str, ps: &str, spp: u32, d: f64) -> PredictedRow {
        let p = two_pair_p_correct(d);
        PredictedRow {
            scene: scene.into(),
            point_set: ps.parse().unwrap(),
            time_filter: TimeFilter::Box,
            spp,
            test_stimulus: format!("{scene}-{ps}-box-{spp}"),
            reference_stimulus: format!("{scene}-reference"),
            q: d,
            k: 1.0,
            d_prime: d,
            p_correct: p,
            p_frame_min: p,
            p_frame_median: p,
            p_frame_max: p,
            frames: 1,
        }
    }

    #[test]
    fn decision_rule_limits() {
        assert_eq!(two_pair_p_correct(0.0), 0.5);
        assert!((two_pair_p_correct(40.0) - 1.0).abs() < 1e-12);
        // d' where p = 0.75: Phi(d/2) = (1 + sqrt(1/2)) / 2.
        let a: f64 = (1.0 + 0.5f64.sqrt()) / 2.0;
        let d = 2.0 * 1.051_795_860_165_225;
        assert!((phi(d / 2.0) - a).abs() < 1e-9);
        assert!((two_pair_p_correct(d) - 0.75).abs() < 1e-9);
    }

    #[test]
    fn curve_interpolates_log_log_and_extrapolates_the_end_segments() {
        // d' = 8 spp^-1/2: a straight line in log-log, reproduced inside and beyond the levels.
        let rows = [1, 8, 27, 64]
            .map(|s| row("plane", "poisson", s, 8.0 / (s as f64).sqrt()))
            .to_vec();
        let t = PredictedTable::from_rows(rows);
        let c = t.curve(&Condition::new(
            "plane",
            PointSetKind::Poisson,
            TimeFilter::Box,
        ));
        let c = c.unwrap();
        for s in [0.5, 1.0, 3.0, 40.0, 200.0] {
            assert!((c.d_prime_at(s) - 8.0 / s.sqrt()).abs() < 1e-9, "{s}");
        }
        // p = 0.75 where d' = 2.104: spp = (8 / 2.104)^2.
        let spp = c.spp_at(0.75).unwrap();
        assert!(
            (spp - (8.0 / 2.103_591_720_330_45f64).powi(2)).abs() < 1e-6,
            "{spp}"
        );
    }

    #[test]
    fn round_trips_and_refuses_bad_files_naming_the_line() {
        let t =
            PredictedTable::from_rows(vec![row("a", "sobol", 8, 1.0), row("a", "sobol", 27, 0.5)]);
        let text = t.to_csv().unwrap();
        let back = PredictedTable::parse(Path::new("p.csv"), &text).unwrap();
        assert_eq!(back, t);
        let e = PredictedTable::parse(Path::new("p.csv"), "scene\n").unwrap_err();
        assert!(format!("{e:#}").contains("line 1"), "{e:#}");
        let bad = text.replacen(",1.0,1.0,1.0,", ",1.0,-1.0,1.0,", 1);
        let e = format!(
            "{:#}",
            PredictedTable::parse(Path::new("p.csv"), &bad).unwrap_err()
        );
        assert!(e.contains("p.csv") && e.contains("line 3"), "{e}");
    }
}
