//! Calibrating the sensitivity constant k (d' = k Q) to real sessions, by maximum likelihood
//! over all their main trials:
//!
//! ```text
//! ln L(k) = sum over cells (condition x level) of  c ln p + (n - c) ln(1 - p),
//! p = Phi(k Q / 2)^2 + Phi(-k Q / 2)^2,
//! ```
//!
//! with c correct of n trials pooled over subjects and Q the cell's predicted visible
//! difference. k is the only free parameter: the model's shape (CSF, masking, pooling,
//! decision rule) stays as published. Honest accounting: leave-one-condition-out refits k
//! without each condition in turn and scores that condition's trials with it (proportion
//! correct error, log-likelihood per trial against always guessing), so the error reported is
//! a prediction error, not a fit.

use super::stimuli::Prediction;
use crate::data::{Dataset, Grouping};
use crate::observer::model::proportion_correct::two_pair_p_correct;
use anyhow::{Result, bail};
use serde::Serialize;

/// One condition x level: the prediction's Q and the sessions' counts.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Cell {
    /// `scene/point_set/time_filter`.
    pub condition: String,
    pub spp: u32,
    pub q: f64,
    pub correct: u32,
    pub trials: u32,
}

/// The held-out score of one condition.
#[derive(Clone, Debug, Serialize)]
pub struct HeldOut {
    pub condition: String,
    /// k fitted without this condition.
    pub k: f64,
    pub trials: u32,
    /// Trial-weighted root mean square of predicted minus observed proportion correct.
    pub rmse_p: f64,
    /// Mean log-likelihood per held-out trial, and that of guessing (ln 0.5).
    pub log_likelihood_per_trial: f64,
    pub guess_log_likelihood_per_trial: f64,
}

/// The fit and its cross-validation.
#[derive(Clone, Debug, Serialize)]
pub struct Calibration {
    pub k: f64,
    /// Approximate 95% interval of k from the curvature of ln L in ln k.
    pub k_interval: Option<[f64; 2]>,
    pub log_likelihood: f64,
    pub trials: u32,
    pub cells: Vec<Cell>,
    pub held_out: Vec<HeldOut>,
}

/// Join the prediction with the sessions' pooled counts per condition and level; every tested
/// cell must have a prediction.
pub fn cells(p: &Prediction, ds: &Dataset) -> Result<Vec<Cell>> {
    let mut out = Vec::new();
    for g in ds.groups_of(Grouping::Condition) {
        for lc in &g.pooled.points {
            let found = p.stimuli.iter().find(|s| {
                let r = &s.row;
                format!("{}/{}/{}", r.scene, r.point_set, r.time_filter) == g.key.label
                    && r.spp == lc.level
            });
            let Some(s) = found else {
                bail!(
                    "the sessions test condition {} at {} spp, which the prediction of {} does not hold",
                    g.key.label,
                    lc.level,
                    p.manifest_path.display()
                );
            };
            out.push(Cell {
                condition: g.key.label.clone(),
                spp: lc.level,
                q: s.row.q,
                correct: lc.correct,
                trials: lc.trials,
            });
        }
    }
    if out.is_empty() {
        bail!("the sessions hold no main trials to calibrate on");
    }
    Ok(out)
}

/// ln L(k) over cells.
pub fn log_likelihood(cells: &[Cell], k: f64) -> f64 {
    cells
        .iter()
        .map(|c| {
            let p = two_pair_p_correct(k * c.q).clamp(1e-12, 1.0 - 1e-12);
            c.correct as f64 * p.ln() + (c.trials - c.correct) as f64 * (1.0 - p).ln()
        })
        .sum()
}

/// The maximum-likelihood k over [1e-3, 1e3]: a grid in ln k, then golden-section search
/// around the best grid point (ln L may be flat in places, never multi-peaked in practice;
/// the grid guards against a local maximum).
pub fn fit_k(cells: &[Cell]) -> f64 {
    let f = |x: f64| log_likelihood(cells, x.exp());
    let (lo, hi, n) = (1e-3f64.ln(), 1e3f64.ln(), 240);
    let step = (hi - lo) / n as f64;
    let best = (0..=n)
        .map(|i| lo + step * i as f64)
        .max_by(|a, b| f(*a).total_cmp(&f(*b)))
        .unwrap_or(0.0);
    let (mut a, mut b) = ((best - step).max(lo), (best + step).min(hi));
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..100 {
        let c = b - g * (b - a);
        let d = a + g * (b - a);
        if f(c) >= f(d) {
            b = d;
        } else {
            a = c;
        }
    }
    (0.5 * (a + b)).exp()
}

/// Fit k to all cells and cross-validate by condition.
pub fn calibrate(cells: Vec<Cell>) -> Calibration {
    let k = fit_k(&cells);
    let x = k.ln();
    let h = 1e-3;
    let f = |x: f64| log_likelihood(&cells, x.exp());
    let curvature = (f(x + h) - 2.0 * f(x) + f(x - h)) / (h * h);
    let k_interval = (curvature < 0.0).then(|| {
        let se = (-1.0 / curvature).sqrt();
        [(x - 1.96 * se).exp(), (x + 1.96 * se).exp()]
    });
    let mut conditions: Vec<&str> = cells.iter().map(|c| c.condition.as_str()).collect();
    conditions.sort_unstable();
    conditions.dedup();
    let held_out = if conditions.len() < 2 {
        Vec::new()
    } else {
        conditions
            .iter()
            .map(|&name| held_out(&cells, name))
            .collect()
    };
    Calibration {
        k,
        k_interval,
        log_likelihood: log_likelihood(&cells, k),
        trials: cells.iter().map(|c| c.trials).sum(),
        cells,
        held_out,
    }
}

fn held_out(cells: &[Cell], name: &str) -> HeldOut {
    let (test, train): (Vec<Cell>, Vec<Cell>) =
        cells.iter().cloned().partition(|c| c.condition == name);
    let k = fit_k(&train);
    let trials: u32 = test.iter().map(|c| c.trials).sum();
    let sq: f64 = test
        .iter()
        .map(|c| {
            c.trials as f64
                * (two_pair_p_correct(k * c.q) - c.correct as f64 / c.trials as f64).powi(2)
        })
        .sum();
    HeldOut {
        condition: name.to_string(),
        k,
        trials,
        rmse_p: (sq / trials as f64).sqrt(),
        log_likelihood_per_trial: log_likelihood(&test, k) / trials as f64,
        guess_log_likelihood_per_trial: 0.5f64.ln(),
    }
}

/// `calibration.md`.
pub fn markdown(c: &Calibration, default_k: f64) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let _ = writeln!(s, "# Calibration of the sensitivity constant\n");
    let _ = writeln!(
        s,
        "Maximum likelihood over {} main trials in {} condition x level cells: k = {:.4}{} \
         (default {default_k}; ln L = {:.2}). d' = k Q; `docs/predict.md` says what k can and \
         cannot absorb.\n",
        c.trials,
        c.cells.len(),
        c.k,
        c.k_interval.map_or(String::new(), |[a, b]| format!(
            ", 95% interval {a:.4} to {b:.4}"
        )),
        c.log_likelihood
    );
    let _ = writeln!(s, "## Leave-one-condition-out prediction error\n");
    let _ = writeln!(
        s,
        "| held-out condition | k without it | trials | RMSE of p | ln L per trial | guessing |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|");
    for h in &c.held_out {
        let _ = writeln!(
            s,
            "| {} | {:.4} | {} | {:.3} | {:.3} | {:.3} |",
            h.condition,
            h.k,
            h.trials,
            h.rmse_p,
            h.log_likelihood_per_trial,
            h.guess_log_likelihood_per_trial
        );
    }
    if c.held_out.is_empty() {
        let _ = writeln!(s, "(one condition only: nothing to hold out)");
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use renderer::hash::{hash, unit_f64};

    #[test]
    fn recovers_a_known_constant_from_simulated_counts() {
        // Cells whose Q spans the psychometric function; answers drawn with k = 0.8.
        let k_true = 0.8;
        let mut cells = Vec::new();
        for (ci, cond) in ["a/x/box", "a/y/box", "b/x/box"].iter().enumerate() {
            for (li, q) in [6.0, 3.0, 2.0, 1.2, 0.6].iter().enumerate() {
                let q = q * (1.0 + 0.3 * ci as f64);
                let p = two_pair_p_correct(k_true * q);
                let n = 400u32;
                let correct = (0..n)
                    .filter(|&t| unit_f64(hash(9, &[ci as u64, li as u64, t as u64])) < p)
                    .count() as u32;
                cells.push(Cell {
                    condition: cond.to_string(),
                    spp: li as u32 + 1,
                    q,
                    correct,
                    trials: n,
                });
            }
        }
        let c = calibrate(cells);
        let [lo, hi] = c.k_interval.unwrap();
        // The 95% interval holds the truth (checked at this seed; a wrong fit misses by far).
        assert!(lo < k_true && k_true < hi, "{} [{lo}, {hi}]", c.k);
        assert!((c.k / k_true - 1.0).abs() < 0.05, "{}", c.k);
        assert_eq!(c.held_out.len(), 3);
        for h in &c.held_out {
            assert!(h.log_likelihood_per_trial > h.guess_log_likelihood_per_trial);
            assert!(h.rmse_p < 0.05, "{h:?}");
        }
    }
}
