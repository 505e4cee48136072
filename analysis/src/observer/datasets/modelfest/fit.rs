//! The model against human thresholds: ModelFest's 43 stimuli ([`super`]) through
//! the model's pipeline, its free parameters fitted by least squares on the log thresholds,
//! and the error reported overall, per stimulus, per family and leave-one-out.
//!
//! Free parameters: the sensitivity constant k (d' = k Q); the pooling ([`pooling`]): beta
//! over space and time and the spatial aperture's size (beta_c over bands and channels is held
//! at the first pass's fit, [`grid`]); the CSF's shape ([`shape`]): the oblique loss w, the
//! high-frequency roll-off f_h and the frequency scale s (the narrowing c and the roll-off's
//! power held, [`shapes`]). Everything else is fixed as published
//! (stelaCSF, the bands, the channels) or as chosen in docs/predict.md. For given parameters
//! the predicted log sensitivity is log10 S_i = log10 k + log10(Q1_i / d'_84) (Q1 the
//! response per unit peak contrast, d'_84 the 2IFC 84% point), so the least-squares log10 k is
//! the mean residual in closed form; the rest is the grid point ([`grid`], [`shapes`]) with
//! the least squared error. Leave-one-out refits everything without each stimulus and
//! predicts that one.
//!
//! [`pooling`]: crate::observer::model::pooling
//! [`shape`]: crate::observer::model::shape

use super::{Stimulus, response};
use crate::observer::model::pooling::{Grid, Pooling};
use crate::observer::model::proportion_correct::{CRITERION, two_ifc_d_prime_for};
use crate::observer::model::shape::Shape;
use anyhow::{Result, bail};
use rayon::prelude::*;
use renderer::progress::Progress;
use std::fmt::Write as _;

/// The fit's free parameters but k: the pooling and the CSF's shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    pub pooling: Pooling,
    pub shape: Shape,
}

/// Every point of a grid of poolings and shapes, in the order of
/// [`super::response`]: channel exponent, shape, space exponent, aperture.
pub fn params(grid: &Grid, shapes: &[Shape]) -> Vec<Params> {
    let mut out = Vec::new();
    for &channels in &grid.channels {
        for &shape in shapes {
            for pooling in grid.space_pairs(channels) {
                out.push(Params { pooling, shape });
            }
        }
    }
    out
}

/// The poolings the fit searches: beta_c = 2 (fitted from {1, 2, 3, 4} by the first pass and
/// kept: each value costs a pass of the pipeline), beta in 2.2-2.8 by 0.2 and the aperture's
/// sd none, 0.5 or 0.35 deg: both reach past the fit (beta 2.4, sd 0.5). The fourth pass's
/// wider grid (beta 1.8-3.0, sd down to 0.25 deg and 1 deg) put its optimum inside this one;
/// the 0.2 steps in beta keep the leave-one-out fits from jumping between far points.
pub fn grid() -> Grid {
    Grid {
        channels: vec![2.0],
        space: vec![2.2, 2.4, 2.6, 2.8],
        apertures: vec![f64::INFINITY, 0.5, 0.35],
    }
}

/// The CSF shapes the fit searches (fifth pass): the oblique loss w in 0.15, 0.3, 0.45; the
/// high-frequency roll-off f_h in 30, 34, 38 cpd at power 2; the frequency scale s in 0.8,
/// 0.85, 0.9. Each around the fit (w 0.3, f_h 34, s 0.85), which the fifth pass's exploration
/// grids (`analysis/examples/modelfest_shapes.rs`; f_h 24-48 and none, power 1.5-8, s
/// 0.7-1.15) put inside. Held: the power at 2 (1.5 and 2 fit alike, 0.948 and 0.946 dB; 3 and
/// above worse) and the narrowing at 0: on the fourth pass's grid it was 0 in the fit on all 43
/// stimuli and 0.015 around 8 cpd only when the smallest Gaussian blob (#26) was left out,
/// which it then missed by 6.4 dB: identified by that one stimulus alone, it bought nothing in
/// sample (docs/benchmarks/modelfest.md).
pub fn shapes() -> Vec<Shape> {
    let mut out = Vec::new();
    for w in [0.15, 0.3, 0.45] {
        for rolloff_cpd in [30.0, 34.0, 38.0] {
            for scale in [0.8, 0.85, 0.9] {
                out.push(Shape {
                    oblique: w,
                    rolloff_cpd,
                    rolloff_power: 2.0,
                    scale,
                    ..crate::observer::model::shape::NONE
                });
            }
        }
    }
    out
}

/// The model's response per unit contrast of every stimulus at every point of a grid.
#[derive(Clone, Debug)]
pub struct Responses {
    pub pairs: Vec<Params>,
    /// `q1[stimulus][pair]`.
    pub q1: Vec<Vec<f64>>,
}

/// Run the pipeline on every stimulus (in parallel; `progress` counts stimuli).
pub fn responses(
    stimuli: &[Stimulus],
    grid: &Grid,
    shapes: &[Shape],
    progress: &dyn Progress,
) -> Result<Responses> {
    progress.start(stimuli.len() as u64);
    progress.message("ModelFest stimuli");
    let q1 = stimuli
        .par_iter()
        .map(|s| {
            let r = response(s, grid, shapes);
            progress.advance(1);
            r
        })
        .collect::<Result<Vec<_>>>()?;
    progress.finish();
    Ok(Responses {
        pairs: params(grid, shapes),
        q1,
    })
}

/// Fitted parameters and the fit's error on the stimuli it was fitted to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
    pub params: Params,
    pub log10_k: f64,
    /// Root mean square of the log10 residuals.
    pub rms_log10: f64,
}

impl Fit {
    pub fn k(&self) -> f64 {
        10f64.powf(self.log10_k)
    }

    /// Predicted log10 sensitivity of a stimulus of response `q1` at this fit's parameters.
    pub fn predict(&self, q1: f64) -> f64 {
        self.log10_k + (q1 / d_prime_84()).log10()
    }
}

/// d' of the 2IFC 84% point.
pub fn d_prime_84() -> f64 {
    two_ifc_d_prime_for(CRITERION).expect("0.84 is inside (0.5, 1)")
}

/// Least-squares fit on the stimuli `use_` (indices into `measured` and `r.q1`).
pub fn fit(measured: &[f64], r: &Responses, use_: &[usize]) -> Result<Fit> {
    if use_.is_empty() {
        bail!("no stimuli to fit");
    }
    let mut best: Option<Fit> = None;
    for (j, &params) in r.pairs.iter().enumerate() {
        let base = |i: usize| (r.q1[i][j] / d_prime_84()).log10();
        let n = use_.len() as f64;
        let log10_k = use_.iter().map(|&i| measured[i] - base(i)).sum::<f64>() / n;
        let sse: f64 = use_
            .iter()
            .map(|&i| (measured[i] - base(i) - log10_k).powi(2))
            .sum();
        let f = Fit {
            params,
            log10_k,
            rms_log10: (sse / n).sqrt(),
        };
        if f.rms_log10.is_finite() && best.is_none_or(|b| f.rms_log10 < b.rms_log10) {
            best = Some(f);
        }
    }
    best.ok_or_else(|| anyhow::anyhow!("every response is zero or not finite"))
}

/// Predicted log10 sensitivity of stimulus `i` under fit `f`.
pub fn predicted(f: &Fit, r: &Responses, i: usize) -> f64 {
    let j = r
        .pairs
        .iter()
        .position(|&e| e == f.params)
        .expect("a fit's parameters are a point of the grid's");
    f.predict(r.q1[i][j])
}

/// One stimulus in the report.
#[derive(Clone, Debug)]
pub struct Line {
    pub number: u32,
    pub name: String,
    pub family: String,
    pub measured: f64,
    pub predicted: f64,
    /// Predicted by the fit without this stimulus.
    pub left_out: f64,
}

/// The validation: the fit on all stimuli and every stimulus's prediction.
#[derive(Clone, Debug)]
pub struct Validation {
    pub fit: Fit,
    pub lines: Vec<Line>,
}

/// dB of a log10 error: 20 log10.
pub fn db(log10_error: f64) -> f64 {
    20.0 * log10_error
}

fn rms(errors: impl Iterator<Item = f64>) -> f64 {
    let (mut s, mut n) = (0.0, 0usize);
    for e in errors {
        s += e * e;
        n += 1;
    }
    (s / n.max(1) as f64).sqrt()
}

impl Validation {
    /// RMS error in dB over all stimuli.
    pub fn rms_db(&self) -> f64 {
        db(rms(self.lines.iter().map(|l| l.predicted - l.measured)))
    }

    /// Leave-one-out RMS error in dB.
    pub fn loo_rms_db(&self) -> f64 {
        db(rms(self.lines.iter().map(|l| l.left_out - l.measured)))
    }
}

/// Fit on all stimuli and leave each out in turn.
pub fn validate(stimuli: &[Stimulus], r: &Responses) -> Result<Validation> {
    let measured: Vec<f64> = stimuli.iter().map(|s| s.measured).collect();
    let all: Vec<usize> = (0..stimuli.len()).collect();
    let f = fit(&measured, r, &all)?;
    let lines = stimuli
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let rest: Vec<usize> = all.iter().copied().filter(|&j| j != i).collect();
            let left_out = if rest.is_empty() {
                f64::NAN
            } else {
                predicted(&fit(&measured, r, &rest)?, r, i)
            };
            Ok(Line {
                number: s.number,
                name: s.name.clone(),
                family: s.family.clone(),
                measured: s.measured,
                predicted: predicted(&f, r, i),
                left_out,
            })
        })
        .collect::<Result<_>>()?;
    Ok(Validation { fit: f, lines })
}

/// Per family (in order of first appearance): stimuli, mean error and RMS error, dB.
pub fn families(v: &Validation) -> Vec<(String, usize, f64, f64)> {
    let mut order: Vec<&str> = Vec::new();
    for l in &v.lines {
        if !order.contains(&l.family.as_str()) {
            order.push(&l.family);
        }
    }
    order
        .into_iter()
        .map(|fam| {
            let errs: Vec<f64> = v
                .lines
                .iter()
                .filter(|l| l.family == fam)
                .map(|l| l.predicted - l.measured)
                .collect();
            let mean = errs.iter().sum::<f64>() / errs.len() as f64;
            (
                fam.to_string(),
                errs.len(),
                db(mean),
                db(rms(errs.into_iter())),
            )
        })
        .collect()
}

/// A size to two decimals, or "none (infinite)".
fn finite_or_none(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.2}")
    } else {
        "none (infinite)".into()
    }
}

/// The report as Markdown; its last line is `RMS error: X dB over N stimuli`.
pub fn markdown(v: &Validation) -> String {
    let mut s = String::new();
    let f = &v.fit;
    let (p, sh) = (f.params.pooling, f.params.shape);
    let _ = writeln!(
        s,
        "# ModelFest validation\n\nFitted by least squares on log10 thresholds: k = {:.4} \
         (log10 k = {:.4}); pooling exponents beta_c = {:.0} (bands and channels), beta = {:.1} \
         (space and time); aperture sd {} deg; CSF narrowing c = {:.3} log10 per octave^2 \
         around {:.2} cpd, oblique loss w = {:.2}, high-frequency roll-off f_h = {} cpd \
         (power {:.1}), frequency scale s = {:.3}. Decision: 2IFC, 84% correct at d' = {:.4}.\n",
        f.k(),
        f.log10_k,
        p.channels,
        p.space,
        finite_or_none(p.aperture_deg),
        sh.narrowing,
        sh.centre_cpd,
        sh.oblique,
        finite_or_none(sh.rolloff_cpd),
        sh.rolloff_power,
        sh.scale,
        d_prime_84()
    );
    s.push_str(
        "| # | stimulus | measured log10 S | predicted | error dB | left out: predicted | error dB |\n\
         |---|---|---|---|---|---|---|\n",
    );
    for l in &v.lines {
        let _ = writeln!(
            s,
            "| {} | {} | {:.3} | {:.3} | {:+.2} | {:.3} | {:+.2} |",
            l.number,
            l.name,
            l.measured,
            l.predicted,
            db(l.predicted - l.measured),
            l.left_out,
            db(l.left_out - l.measured)
        );
    }
    s.push_str("\n| family | stimuli | mean error dB | RMS error dB |\n|---|---|---|---|\n");
    for (fam, n, mean, r) in families(v) {
        let _ = writeln!(s, "| {fam} | {n} | {mean:+.2} | {r:.2} |");
    }
    let _ = writeln!(
        s,
        "\nLeave-one-out RMS error: {:.2} dB over {} stimuli",
        v.loo_rms_db(),
        v.lines.len()
    );
    let _ = write!(
        s,
        "RMS error: {:.2} dB over {} stimuli",
        v.rms_db(),
        v.lines.len()
    );
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small grid for the synthetic fits.
    fn test_grid() -> (Grid, Vec<Shape>) {
        let grid = Grid {
            channels: vec![2.0, 3.0],
            space: vec![2.4, 2.6, 2.8],
            apertures: vec![f64::INFINITY, 1.0],
        };
        let shapes = [(0.0, 0.0), (0.02, 0.0), (0.0, 0.2), (0.02, 0.2)]
            .map(|(narrowing, oblique)| Shape {
                narrowing,
                centre_cpd: 4.0,
                oblique,
                ..crate::observer::model::shape::NONE
            })
            .to_vec();
        (grid, shapes)
    }

    /// Responses following q1 = 50 a^(1/beta) b^(1/beta_c) (1 - w o) 10^(-c n) / (1 + e / sd)
    /// exactly, each stimulus with its own (a, b, o, n, e): the fit must find the truth and k.
    fn synthetic(truth: Params, log10_k: f64) -> (Vec<f64>, Responses) {
        let x = [
            (0.5, 1.0, 0.0, 1.0, 0.1),
            (2.0, 3.0, 1.0, 0.0, 0.5),
            (8.0, 1.0, 0.5, 4.0, 0.0),
            (30.0, 0.2, 0.0, 2.0, 2.0),
            (100.0, 7.0, 0.2, 6.0, 0.3),
            (3.0, 2.0, 1.0, 0.5, 1.0),
            (1.0, 5.0, 0.7, 3.0, 0.2),
            (9.0, 0.5, 0.1, 9.0, 3.0),
        ];
        let (grid, shapes) = test_grid();
        let pairs = params(&grid, &shapes);
        let q = |(a, b, o, n, e): (f64, f64, f64, f64, f64), p: &Params| {
            let (pl, sh) = (p.pooling, p.shape);
            50.0 * f64::powf(a, 1.0 / pl.space)
                * f64::powf(b, 1.0 / pl.channels)
                * (1.0 - sh.oblique * o)
                * 10f64.powf(-sh.narrowing * n)
                / (1.0 + e / pl.aperture_deg)
        };
        let q1 = x
            .iter()
            .map(|&x| pairs.iter().map(|p| q(x, p)).collect())
            .collect();
        let measured = x
            .iter()
            .map(|&x| log10_k + (q(x, &truth) / d_prime_84()).log10())
            .collect();
        (measured, Responses { pairs, q1 })
    }

    fn truth() -> Params {
        let (grid, shapes) = test_grid();
        Params {
            pooling: grid.space_pairs(3.0)[3],
            shape: shapes[3],
        }
    }

    #[test]
    fn the_fit_recovers_known_parameters() {
        let t = truth();
        assert_eq!((t.pooling.space, t.pooling.aperture_deg), (2.6, 1.0));
        let (measured, r) = synthetic(t, -0.3);
        let all: Vec<usize> = (0..measured.len()).collect();
        let f = fit(&measured, &r, &all).unwrap();
        assert_eq!(f.params, t, "{f:?}");
        assert!((f.log10_k + 0.3).abs() < 1e-9, "{f:?}");
        assert!(f.rms_log10 < 1e-9);
    }

    #[test]
    fn the_grids_are_in_the_responses_order() {
        let ps = params(&grid(), &shapes());
        assert_eq!(ps.len(), 4 * 3 * 27);
        assert_eq!(ps[1].pooling.aperture_deg, 0.5);
        assert_eq!(ps[3].pooling.space, 2.4);
        assert_eq!(ps[13].shape, shapes()[1]);
        // The committed model is a point of the grid, not on its edge.
        let committed = Params {
            pooling: crate::observer::model::pooling::FITTED,
            shape: crate::observer::model::shape::FITTED,
        };
        assert!(ps.contains(&committed));
    }

    #[test]
    fn leave_one_out_predicts_an_exact_model_exactly_and_reports_in_db() {
        let (measured, r) = synthetic(truth(), 0.2);
        let stimuli: Vec<Stimulus> = measured
            .iter()
            .enumerate()
            .map(|(i, &m)| Stimulus {
                number: i as u32 + 1,
                name: format!("S{}", i + 1),
                family: "S".into(),
                width: 1,
                height: 1,
                contrast: vec![1.0],
                measured: m,
                observations: 1,
            })
            .collect();
        let v = validate(&stimuli, &r).unwrap();
        assert!(v.rms_db() < 1e-6 && v.loo_rms_db() < 1e-6);
        assert!(markdown(&v).ends_with("RMS error: 0.00 dB over 8 stimuli"));
        // A stimulus measured 0.1 log units (2 dB) too sensitive shows in its own line.
        let mut moved = stimuli.clone();
        moved[2].measured += 0.1;
        let v = validate(&moved, &r).unwrap();
        assert!((v.lines[2].left_out - v.lines[2].measured + 0.1).abs() < 0.02);
        assert!((db(0.1) - 2.0).abs() < 1e-12);
    }
}
