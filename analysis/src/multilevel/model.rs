//! The multilevel psychometric model's likelihood.
//!
//! K groups (one condition, scene or point set; two for a comparison) seen by the same
//! subjects. In group k subject s answers with
//!
//! ```text
//! p(x) = g + (1 - g - lapse) S(beta_k (alpha_k + u_s - x)),   u_s ~ N(0, sigma^2),
//! ```
//!
//! x = ln spp: u_s shifts the subject's threshold in ln spp, the same shift in every group of
//! the model. The parameters are the population thresholds t_k (ln spp where the function of
//! the typical subject, u = 0, crosses the target), so that their intervals come straight from
//! the likelihood; alpha_k = t_k + S^-1(q) / beta_k with q = (target - g) / (1 - g - lapse).
//! The marginal likelihood integrates each subject's u out by adaptive Gauss-Hermite
//! quadrature ([`super::quadrature`]).

use super::quadrature::{Integral, Rule};
use crate::data::Curve;
use crate::psychometric::{FitSettings, LAPSE_MAX, LapseMode, Model};

/// One count of one subject: group index, x = ln spp, correct, trials.
#[derive(Clone, Copy, Debug)]
struct Count {
    group: usize,
    x: f64,
    k: f64,
    n: f64,
}

/// The counts of a model: per subject (subjects without a trial in any group left out).
#[derive(Clone, Debug)]
pub struct Counts {
    /// Each kept subject's index into the caller's subject list.
    pub subjects: Vec<usize>,
    rows: Vec<Vec<Count>>,
    pub groups: usize,
    /// The lowest and highest tested level (1 and 1 without data).
    pub levels: (u32, u32),
    /// Tested range in ln spp, and the smallest gap between tested levels.
    pub x_lo: f64,
    pub x_hi: f64,
    pub min_gap: f64,
}

impl Counts {
    /// `curves[k][s]`: subject s's curve in group k (without the same-video levels:
    /// [`super::informative`]).
    pub fn new(curves: &[&[Curve]]) -> Self {
        let n_subjects = curves.iter().map(|c| c.len()).max().unwrap_or(0);
        let mut subjects = Vec::new();
        let mut rows = Vec::new();
        let mut xs = Vec::new();
        let mut levels: Option<(u32, u32)> = None;
        for s in 0..n_subjects {
            let row: Vec<Count> = curves
                .iter()
                .enumerate()
                .flat_map(|(group, c)| {
                    c.get(s)
                        .into_iter()
                        .flat_map(move |c| &c.points)
                        .map(move |p| Count {
                            group,
                            x: p.x(),
                            k: p.correct as f64,
                            n: p.trials as f64,
                        })
                })
                .collect();
            for p in curves
                .iter()
                .filter_map(|c| c.get(s))
                .flat_map(|c| &c.points)
            {
                let (lo, hi) = levels.get_or_insert((p.level, p.level));
                (*lo, *hi) = ((*lo).min(p.level), (*hi).max(p.level));
            }
            if !row.is_empty() {
                xs.extend(row.iter().map(|c| c.x));
                subjects.push(s);
                rows.push(row);
            }
        }
        xs.sort_by(f64::total_cmp);
        xs.dedup();
        let min_gap = xs
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min);
        Counts {
            subjects,
            rows,
            groups: curves.len(),
            levels: levels.unwrap_or((1, 1)),
            x_lo: xs.first().copied().unwrap_or(0.0),
            x_hi: xs.last().copied().unwrap_or(0.0),
            min_gap,
        }
    }

    /// Distinct tested levels.
    pub fn identified(&self) -> bool {
        self.min_gap.is_finite() && self.subjects.len() >= 2
    }
}

/// The model's parameters in natural units.
#[derive(Clone, Debug, PartialEq)]
pub struct Params {
    /// Population thresholds t_k, ln spp.
    pub thresholds: Vec<f64>,
    /// Slopes beta_k, 1 / ln spp.
    pub slopes: Vec<f64>,
    /// Between-subject SD of the threshold, ln spp.
    pub sigma: f64,
    pub lapse: f64,
}

/// How a parameter vector maps onto [`Params`]: `[t_0..t_K or one shared t, ln beta_0..K,
/// ln sigma, (lapse coordinate)]`, each clamped into its bounds.
#[derive(Clone, Copy, Debug)]
pub struct Layout {
    pub groups: usize,
    /// One threshold for every group (the null hypothesis of a likelihood-ratio test).
    pub shared_threshold: bool,
    pub free_lapse: bool,
}

/// Bounds of the search: thresholds within the tested span +- one span, slopes from "z
/// changes by 0.1 across the span" to "by 50 across the smallest gap" (as the single fits),
/// sigma from 0.001 to 5 ln spp.
#[derive(Clone, Copy, Debug)]
pub struct Bounds {
    pub t: (f64, f64),
    pub ln_beta: (f64, f64),
    pub ln_sigma: (f64, f64),
}

impl Bounds {
    pub fn new(c: &Counts) -> Self {
        let span = (c.x_hi - c.x_lo).max(1.0);
        Bounds {
            t: (c.x_lo - span, c.x_hi + span),
            ln_beta: ((0.1 / span).ln(), (50.0 / c.min_gap).ln()),
            ln_sigma: (1e-3f64.ln(), 5f64.ln()),
        }
    }
}

impl Layout {
    pub fn thresholds(&self) -> usize {
        if self.shared_threshold {
            1
        } else {
            self.groups
        }
    }

    /// Number of coordinates of the parameter vector.
    pub fn dimension(&self) -> usize {
        self.thresholds() + self.groups + 1 + self.free_lapse as usize
    }

    pub fn sigma_index(&self) -> usize {
        self.thresholds() + self.groups
    }

    pub fn params(&self, v: &[f64], b: &Bounds) -> Params {
        let nt = self.thresholds();
        let t = |i: usize| v[i].clamp(b.t.0, b.t.1);
        Params {
            thresholds: (0..self.groups)
                .map(|k| t(if self.shared_threshold { 0 } else { k }))
                .collect(),
            slopes: (0..self.groups)
                .map(|k| v[nt + k].clamp(b.ln_beta.0, b.ln_beta.1).exp())
                .collect(),
            sigma: v[self.sigma_index()]
                .clamp(b.ln_sigma.0, b.ln_sigma.1)
                .exp(),
            lapse: if self.free_lapse {
                LAPSE_MAX / (1.0 + (-v[self.sigma_index() + 1]).exp())
            } else {
                0.0
            },
        }
    }

    /// The vector of `p` (its inverse map).
    pub fn vector(&self, p: &Params) -> Vec<f64> {
        let mut v: Vec<f64> = p.thresholds[..self.thresholds()].to_vec();
        v.extend(p.slopes.iter().map(|b| b.ln()));
        v.push(p.sigma.ln());
        if self.free_lapse {
            let q = (p.lapse / LAPSE_MAX).clamp(1e-6, 1.0 - 1e-6);
            v.push((q / (1.0 - q)).ln());
        }
        v
    }

    /// Coordinates held at a bound of [`Bounds`] (where the likelihood is flat, so the
    /// curvature says nothing): left out of the covariance.
    pub fn at_bound(&self, v: &[f64], b: &Bounds) -> Vec<bool> {
        let nt = self.thresholds();
        let near = |x: f64, (lo, hi): (f64, f64)| x <= lo + 1e-3 || x >= hi - 1e-3;
        (0..self.dimension())
            .map(|i| match i {
                i if i < nt => near(v[i], b.t),
                i if i < nt + self.groups => near(v[i], b.ln_beta),
                i if i == self.sigma_index() => near(v[i], b.ln_sigma),
                // The lapse coordinate is unbounded, its value at 0 or 0.06 only in the limit.
                _ => v[i].abs() > 12.0,
            })
            .collect()
    }
}

/// The typical subject's function in each group, and the marginal likelihood.
pub struct Likelihood<'a> {
    pub counts: &'a Counts,
    pub fit: FitSettings,
    pub target: f64,
    pub rule: &'a Rule,
}

impl Likelihood<'_> {
    /// The function of the typical subject (u = 0) in each group.
    pub fn models(&self, p: &Params) -> Vec<Model> {
        let q = (self.target - self.fit.guess) / (1.0 - self.fit.guess - p.lapse);
        let s_inv = self.fit.sigmoid.inverse(q);
        p.thresholds
            .iter()
            .zip(&p.slopes)
            .map(|(&t, &beta)| Model {
                sigmoid: self.fit.sigmoid,
                alpha: t + s_inv / beta,
                beta,
                lapse: p.lapse,
                guess: self.fit.guess,
            })
            .collect()
    }

    /// Each subject's integral (ln marginal likelihood, posterior mean and SD of u).
    pub fn subjects(&self, p: &Params) -> Vec<Integral> {
        let models = self.models(p);
        self.counts
            .rows
            .iter()
            .map(|row| {
                self.rule.integrate(p.sigma, |u| {
                    row.iter()
                        .map(|c| {
                            let m = Model {
                                alpha: models[c.group].alpha + u,
                                ..models[c.group]
                            };
                            m.log_likelihood_at(c.x, c.k, c.n)
                        })
                        .sum()
                })
            })
            .collect()
    }

    /// ln of the marginal likelihood (without the binomial coefficients).
    pub fn ln_value(&self, p: &Params) -> f64 {
        self.subjects(p).iter().map(|i| i.ln_value).sum()
    }
}

/// The lapse mode's layout flag.
pub fn free_lapse(fit: &FitSettings) -> bool {
    fit.lapse == LapseMode::Free
}
