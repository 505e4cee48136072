//! Forced-choice psychometric functions fitted by maximum likelihood on binomial counts.
//!
//! p(x) = g + (1 - g - lapse) S(beta (alpha - x)),  x = ln spp,  beta > 0,
//! so p falls from 1 - lapse (noise plainly visible) to the guess rate g (invisible): g = 1/2
//! for the thesis's two-pair task, 1/m for an m-alternative task. The lapse is fixed at 0 or
//! free in [0, 0.06].
//!
//! Robustness. With few trials per level (the thesis had 4 per subject) the likelihood is often
//! maximised only in the limit of an infinitely steep function: a *step* from 1 - lapse to g
//! between two tested levels, possibly with one level exactly on the step at any value between.
//! That limit is computed in closed form ([`best_step`]); the finite model is searched by
//! Nelder-Mead from several starts over a bounded reparameterisation (location within the tested
//! span +- one span, slope between nearly flat and a step across the smallest level gap). When
//! the step is as likely as the best finite fit, or the finite slope runs to its cap, the fit is
//! reported as a [`Shape::Step`], so its threshold becomes an interval, never a number.

use crate::data::Curve;
use crate::optimizer::{Tolerance, nelder_mead};
use crate::sigmoid::{Sigmoid, SigmoidValue};
use serde::Serialize;

mod starts;

/// The guess rate of the thesis's two-pair task (two alternatives), the default.
pub const GUESS: f64 = 0.5;
/// Upper bound of a free lapse rate.
pub const LAPSE_MAX: f64 = 0.06;

/// Whether the lapse rate is estimated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LapseMode {
    /// lapse = 0.
    Fixed,
    /// lapse free in [0, 0.06].
    Free,
}

renderer::named!(LapseMode, "lapse mode", [Fixed => "fixed", Free => "free"]);

/// What to fit.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FitSettings {
    pub sigmoid: Sigmoid,
    pub lapse: LapseMode,
    /// The lower asymptote: the proportion correct when the difference is invisible (1/m for
    /// m alternatives), in [0, 1).
    pub guess: f64,
}

impl Default for FitSettings {
    fn default() -> Self {
        FitSettings {
            sigmoid: Sigmoid::Logistic,
            lapse: LapseMode::Fixed,
            guess: GUESS,
        }
    }
}

/// A finite psychometric function.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Model {
    pub sigmoid: Sigmoid,
    /// Location in ln spp.
    pub alpha: f64,
    /// Slope in 1 / ln spp (> 0).
    pub beta: f64,
    pub lapse: f64,
    /// The guess rate g (lower asymptote).
    pub guess: f64,
}

impl Model {
    /// (ln p, ln (1 - p)) from the sigmoid's value: 1 - p = (1 - g)(1 - S) + lapse S, formed
    /// from 1 - S directly.
    fn ln_p_pair_of(&self, v: &SigmoidValue) -> (f64, f64) {
        let g = self.guess;
        let ln_1g = (-g).ln_1p();
        if self.lapse == 0.0 {
            // 1 - p = (1 - g)(1 - S) exactly: no underflow of 1 - S.
            return ((g + (1.0 - g) * v.s).ln(), ln_1g + v.ln_sc);
        }
        let ln_p = (g + (1.0 - g - self.lapse) * v.s).ln();
        let q = (1.0 - g) * v.sc + self.lapse * v.s;
        let ln_q = if q > 1e-300 { q.ln() } else { ln_1g + v.ln_sc };
        (ln_p, ln_q)
    }

    /// Binomial log-likelihood of `k` correct of `n` at x = ln spp (without the binomial
    /// coefficient), finite for every parameter value that is not against the data.
    pub(crate) fn log_likelihood_at(&self, x: f64, k: f64, n: f64) -> f64 {
        let v = self.sigmoid.eval(self.beta * (self.alpha - x));
        let (lp, lq) = self.ln_p_pair_of(&v);
        term(k, n, lp, lq)
    }

    /// Proportion correct at x = ln spp.
    pub fn p(&self, x: f64) -> f64 {
        let g = self.guess;
        g + (1.0 - g - self.lapse) * self.sigmoid.eval(self.beta * (self.alpha - x)).s
    }

    /// x where p(x) = target, if the function reaches it (target strictly between the guess
    /// rate and 1 - lapse).
    pub fn x_at(&self, target: f64) -> Option<f64> {
        let q = (target - self.guess) / (1.0 - self.guess - self.lapse);
        (q > 0.0 && q < 1.0).then(|| self.alpha - self.sigmoid.inverse(q) / self.beta)
    }
}

/// The likelihood's maximum in the infinite-slope limit.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Step {
    /// Number of tested levels (from the lowest) on the upper plateau 1 - lapse.
    pub plateau_levels: usize,
    pub lapse: f64,
}

/// The fitted shape.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Shape {
    Finite(Model),
    Step(Step),
    /// Fewer than two tested levels: location and slope cannot both be estimated.
    Unidentified {
        reason: String,
    },
}

/// A maximum-likelihood fit.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Fit {
    pub settings: FitSettings,
    pub shape: Shape,
    /// The data fitted.
    pub curve: Curve,
    /// Fitted proportion correct at each level of `curve`.
    pub fitted: Vec<f64>,
    /// Binomial log-likelihood (without the constant binomial coefficients).
    pub log_likelihood: f64,
    /// 2 (log-likelihood of the saturated model - log-likelihood).
    pub deviance: f64,
    /// The finite location ran to the edge of its search range (the curve lies far outside
    /// the tested levels).
    pub location_at_bound: bool,
}

impl Fit {
    /// The finite model, if the fit has one.
    pub fn model(&self) -> Option<&Model> {
        match &self.shape {
            Shape::Finite(m) => Some(m),
            _ => None,
        }
    }

    /// Where to start refitting data drawn from this fit (a bootstrap replicate): the finite
    /// model, or for a step a steep function placed on it (z changes by 10 across the
    /// smallest level gap).
    pub fn warm_start(&self) -> Option<Model> {
        let x: Vec<f64> = self.curve.points.iter().map(|p| p.x()).collect();
        let gap = x
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min);
        match &self.shape {
            Shape::Finite(m) => Some(*m),
            Shape::Step(s) if gap.is_finite() => {
                let k = s.plateau_levels;
                let alpha = match k {
                    0 => x[0] - gap,
                    k if k == x.len() => x[k - 1] + gap,
                    k => 0.5 * (x[k - 1] + x[k]),
                };
                Some(Model {
                    sigmoid: self.settings.sigmoid,
                    alpha,
                    beta: 10.0 / gap,
                    lapse: s.lapse,
                    guess: self.settings.guess,
                })
            }
            _ => None,
        }
    }

    pub fn kind(&self) -> &'static str {
        match self.shape {
            Shape::Finite(_) => "finite",
            Shape::Step(_) => "step",
            Shape::Unidentified { .. } => "unidentified",
        }
    }
}

/// k ln p + (n - k) ln(1 - p) with 0 ln 0 = 0 (may be -inf when p is 0 or 1 against data).
fn term(k: f64, n: f64, ln_p: f64, ln_q: f64) -> f64 {
    let a = if k > 0.0 { k * ln_p } else { 0.0 };
    let b = if n - k > 0.0 { (n - k) * ln_q } else { 0.0 };
    a + b
}

fn term_p(k: f64, n: f64, p: f64) -> f64 {
    term(k, n, p.ln(), (1.0 - p).ln())
}

/// Log-likelihood of the saturated model (each level at its observed proportion).
pub fn saturated_log_likelihood(curve: &Curve) -> f64 {
    curve
        .points
        .iter()
        .map(|c| term_p(c.correct as f64, c.trials as f64, c.proportion()))
        .sum()
}

/// The data in the form the objective reads.
struct Data {
    x: Vec<f64>,
    k: Vec<f64>,
    n: Vec<f64>,
}

impl Data {
    fn new(curve: &Curve) -> Self {
        Data {
            x: curve.points.iter().map(|p| p.x()).collect(),
            k: curve.points.iter().map(|p| p.correct as f64).collect(),
            n: curve.points.iter().map(|p| p.trials as f64).collect(),
        }
    }

    fn log_likelihood(&self, m: &Model) -> f64 {
        self.log_likelihood_flat(m).0
    }

    /// The log-likelihood, and whether the function is on a plateau at every level
    /// (min(S, 1 - S) < 1e-6: indistinguishable there from a step).
    fn log_likelihood_flat(&self, m: &Model) -> (f64, bool) {
        let mut ll = 0.0;
        let mut flat = true;
        for i in 0..self.x.len() {
            let v = m.sigmoid.eval(m.beta * (m.alpha - self.x[i]));
            flat &= v.s.min(v.sc) < 1e-6;
            let (lp, lq) = m.ln_p_pair_of(&v);
            ll += term(self.k[i], self.n[i], lp, lq);
        }
        (ll, flat)
    }
}

/// Best step (infinite slope) from 1 - lapse down to the guess rate, and its fitted values.
pub fn best_step(curve: &Curve, lapse: LapseMode, guess: f64) -> (Step, Vec<f64>, f64) {
    let pts = &curve.points;
    let mut best: Option<(Step, Vec<f64>, f64)> = None;
    for plateau in 0..=pts.len() {
        let lam = match lapse {
            LapseMode::Fixed => 0.0,
            LapseMode::Free => {
                let (err, n) = pts[..plateau].iter().fold((0u32, 0u32), |(e, n), p| {
                    (e + p.trials - p.correct, n + p.trials)
                });
                if n == 0 {
                    0.0
                } else {
                    (err as f64 / n as f64).clamp(0.0, LAPSE_MAX)
                }
            }
        };
        let top = 1.0 - lam;
        let fitted: Vec<f64> = (0..pts.len())
            .map(|i| match i.cmp(&plateau) {
                std::cmp::Ordering::Less => top,
                // The level on the step may sit anywhere between the plateaus.
                std::cmp::Ordering::Equal => pts[i].proportion().clamp(guess, top),
                std::cmp::Ordering::Greater => guess,
            })
            .collect();
        let ll: f64 = pts
            .iter()
            .zip(&fitted)
            .map(|(c, &p)| term_p(c.correct as f64, c.trials as f64, p))
            .sum();
        if best.as_ref().is_none_or(|b| ll > b.2) {
            // A level on the step at the top value is on the plateau: count what the fit shows.
            let plateau_levels = fitted.iter().take_while(|&&p| p >= top).count();
            best = Some((
                Step {
                    plateau_levels,
                    lapse: lam,
                },
                fitted,
                ll,
            ));
        }
    }
    // plateau = 0 (all at g < 1) always has a finite likelihood, so `best` is finite.
    best.expect("at least one step position")
}

/// The bounded search space and its unconstrained coordinates u.
struct Space {
    mid: f64,
    half: f64,
    ln_b_lo: f64,
    ln_b_hi: f64,
    free_lapse: bool,
    sigmoid: Sigmoid,
    guess: f64,
}

fn logistic(u: f64) -> f64 {
    1.0 / (1.0 + (-u).exp())
}

fn logit(p: f64) -> f64 {
    let p = p.clamp(1e-9, 1.0 - 1e-9);
    (p / (1.0 - p)).ln()
}

impl Space {
    fn new(data: &Data, settings: &FitSettings) -> Self {
        let lo = data.x[0];
        let hi = *data.x.last().unwrap_or(&lo);
        let span = hi - lo;
        let min_gap = data
            .x
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min);
        Space {
            mid: 0.5 * (lo + hi),
            half: 0.5 * span + span.max(1.0),
            // Nearly flat: z changes by 0.01 across the whole span.
            ln_b_lo: (0.01 / span.max(1.0)).ln(),
            // A step: z changes by 50 across the smallest gap (S goes from 2e-22 to 1 - 2e-22).
            ln_b_hi: (50.0 / min_gap).ln(),
            free_lapse: settings.lapse == LapseMode::Free,
            sigmoid: settings.sigmoid,
            guess: settings.guess,
        }
    }

    fn model(&self, u: &[f64; 3]) -> Model {
        Model {
            sigmoid: self.sigmoid,
            alpha: self.mid + self.half * u[0].tanh(),
            beta: (self.ln_b_lo + (self.ln_b_hi - self.ln_b_lo) * logistic(u[1])).exp(),
            lapse: if self.free_lapse {
                LAPSE_MAX * logistic(u[2])
            } else {
                0.0
            },
            guess: self.guess,
        }
    }

    fn coords(&self, alpha: f64, beta: f64, lapse: f64) -> [f64; 3] {
        let a = ((alpha - self.mid) / self.half).clamp(-0.999_999, 0.999_999);
        [
            a.atanh(),
            logit((beta.ln() - self.ln_b_lo) / (self.ln_b_hi - self.ln_b_lo)),
            logit(lapse / LAPSE_MAX),
        ]
    }

    /// The slope ran to its cap: the function is a step for all practical purposes.
    fn slope_at_cap(&self, m: &Model) -> bool {
        self.ln_b_hi - m.beta.ln() < 0.1
    }

    fn location_at_bound(&self, m: &Model) -> bool {
        ((m.alpha - self.mid) / self.half).abs() > 0.999
    }
}

/// Fit a curve from a default set of starts.
pub fn fit(curve: &Curve, settings: &FitSettings) -> Fit {
    fit_with(curve, settings, None)
}

/// Fit a curve, trying `warm` (a previous fit's model, e.g. the original fit when refitting a
/// bootstrap resample) first. With a warm start fewer default starts are tried.
pub fn fit_with(curve: &Curve, settings: &FitSettings, warm: Option<&Model>) -> Fit {
    if curve.points.len() < 2 {
        return unidentified(curve, settings);
    }
    let data = Data::new(curve);
    let space = Space::new(&data, settings);
    // (start, initial simplex edge): a warm start is near the optimum, so a small simplex.
    let starts: Vec<([f64; 3], f64)> = match warm {
        Some(m) => vec![
            (space.coords(m.alpha, m.beta, m.lapse), 0.25),
            (starts::warm(&space, &data), 0.5),
        ],
        None => starts::cold(curve, &space, &data)
            .into_iter()
            .map(|s| (s, 0.5))
            .collect(),
    };

    let mut best: Option<([f64; 3], f64)> = None;
    for (s, edge) in starts {
        let (u, v) = minimise(&data, &space, s, edge);
        if best.is_none_or(|b| v < b.1) {
            best = Some((u, v));
        }
    }
    let (u, _) = best.expect("at least one start");
    // Restart once from the best point: Nelder-Mead can stall on a collapsed simplex.
    let (u, _) = minimise(&data, &space, u, 0.3);
    let model = space.model(&u);
    let ll_finite = data.log_likelihood(&model);
    let (step, step_fitted, ll_step) = best_step(curve, settings.lapse, settings.guess);
    let sat = saturated_log_likelihood(curve);
    let is_step = space.slope_at_cap(&model) || ll_step >= ll_finite - 1e-7;
    if is_step {
        Fit {
            settings: *settings,
            shape: Shape::Step(step),
            curve: curve.clone(),
            fitted: step_fitted,
            log_likelihood: ll_step,
            deviance: (2.0 * (sat - ll_step)).max(0.0),
            location_at_bound: false,
        }
    } else {
        Fit {
            settings: *settings,
            shape: Shape::Finite(model),
            curve: curve.clone(),
            fitted: data.x.iter().map(|&x| model.p(x)).collect(),
            log_likelihood: ll_finite,
            deviance: (2.0 * (sat - ll_finite)).max(0.0),
            location_at_bound: space.location_at_bound(&model),
        }
    }
}

fn unidentified(curve: &Curve, settings: &FitSettings) -> Fit {
    let reason = if curve.points.is_empty() {
        "no trials".to_string()
    } else {
        format!(
            "a single tested level ({} spp): location and slope cannot both be estimated",
            curve.points[0].level
        )
    };
    // The best any model can do at one level: its proportion, clamped to the model's range.
    let fitted: Vec<f64> = curve
        .points
        .iter()
        .map(|p| p.proportion().clamp(settings.guess, 1.0))
        .collect();
    let ll: f64 = curve
        .points
        .iter()
        .zip(&fitted)
        .map(|(c, &p)| term_p(c.correct as f64, c.trials as f64, p))
        .sum();
    Fit {
        settings: *settings,
        shape: Shape::Unidentified { reason },
        curve: curve.clone(),
        fitted,
        log_likelihood: ll,
        deviance: (2.0 * (saturated_log_likelihood(curve) - ll)).max(0.0),
        location_at_bound: false,
    }
}

fn minimise(data: &Data, space: &Space, start: [f64; 3], step: f64) -> ([f64; 3], f64) {
    let tol = Tolerance::default();
    if space.free_lapse {
        let mut f = |u: &[f64; 3]| -data.log_likelihood(&space.model(u));
        let m = nelder_mead(&mut f, start, step, tol);
        (m.x, m.value)
    } else {
        let mut f = |u: &[f64; 2]| -data.log_likelihood(&space.model(&[u[0], u[1], 0.0]));
        let m = nelder_mead(&mut f, [start[0], start[1]], step, tol);
        ([m.x[0], m.x[1], start[2]], m.value)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::{THESIS_LEVELS as THESIS, expected_curve, thesis_plane_model};

    fn curve(levels: &[u32], correct: &[u32], n: u32) -> Curve {
        Curve::from_counts(levels.iter().zip(correct).map(|(&l, &k)| (l, k, n)))
    }

    #[test]
    fn exact_logistic_data_recovers_parameters() {
        // Counts exactly n p(x) (n = 1e8 per level, p rounded to 1e-8): the MLE equals the
        // truth up to the rounding, i.e. ~1e-7 relative in p; alpha and beta to ~1e-4.
        let truth = thesis_plane_model();
        let c = expected_curve(&truth, &THESIS, 100_000_000);
        let f = fit(&c, &FitSettings::default());
        let m = f.model().expect("finite fit");
        assert!((m.alpha - truth.alpha).abs() < 1e-4, "{m:?}");
        assert!((m.beta - truth.beta).abs() < 1e-4, "{m:?}");
        assert!(f.deviance < 1e-3, "deviance {}", f.deviance);
    }

    #[test]
    fn all_correct_is_a_step_above_the_range() {
        let c = curve(&THESIS, &[4; 8], 4);
        for lapse in [LapseMode::Fixed, LapseMode::Free] {
            for sigmoid in Sigmoid::ALL {
                let f = fit(
                    &c,
                    &FitSettings {
                        sigmoid,
                        lapse,
                        guess: GUESS,
                    },
                );
                assert_eq!(f.kind(), "step", "{sigmoid:?} {lapse:?}");
                assert!(f.fitted.iter().all(|&p| p == 1.0));
                assert!(f.log_likelihood == 0.0 && f.deviance == 0.0);
            }
        }
    }

    #[test]
    fn all_at_chance_is_a_step_below_the_range() {
        let c = curve(&THESIS, &[2; 8], 4);
        let f = fit(&c, &FitSettings::default());
        assert_eq!(f.kind(), "step");
        assert!(f.fitted.iter().all(|&p| p == 0.5), "{:?}", f.fitted);
        assert!(f.deviance.abs() < 1e-12);
    }

    #[test]
    fn separated_subject_data_is_a_step_between_levels() {
        // 4 trials per level, perfect up to 27 spp, at or below chance above.
        let c = curve(&THESIS, &[4, 4, 4, 2, 1, 2, 2, 1], 4);
        let f = fit(&c, &FitSettings::default());
        match f.shape {
            Shape::Step(s) => assert_eq!(s.plateau_levels, 3),
            _ => panic!("expected a step, got {:?}", f.shape),
        }
        assert!(f.fitted.iter().all(|p| p.is_finite()));
    }

    #[test]
    fn step_likelihood_matches_closed_form() {
        // Plateau [1, 8], level 27 on the step at its own proportion 3/4, rest at 0.5.
        let c = curve(&THESIS[..5], &[4, 4, 3, 2, 2], 4);
        let (s, fitted, ll) = best_step(&c, LapseMode::Fixed, GUESS);
        assert_eq!(s.plateau_levels, 2);
        assert_eq!(fitted, vec![1.0, 1.0, 0.75, 0.5, 0.5]);
        let expect = 3.0 * 0.75f64.ln() + 0.25f64.ln() + 8.0 * 0.5f64.ln();
        assert!((ll - expect).abs() < 1e-12);
    }

    #[test]
    fn grid_search_agrees_with_the_fit() {
        // Independent reference: a brute-force grid over (alpha, beta), no optimizer involved:
        // a 0.02 pass over [0, 6] x (0, 4], then a 2e-4 pass over +-0.03 around its best. The
        // fit must be at least as likely as the best grid point, and its parameters within a
        // few fine-grid steps (the grid point nearest the optimum is within 1e-4 of it; allow
        // 5e-4 for the flatness of the likelihood along the alpha-beta ridge).
        let c = Curve::from_counts([
            (1, 47, 48),
            (8, 44, 48),
            (27, 38, 48),
            (64, 30, 48),
            (125, 27, 48),
            (216, 25, 48),
            (343, 26, 48),
            (512, 23, 48),
        ]);
        for sigmoid in Sigmoid::ALL {
            let f = fit(
                &c,
                &FitSettings {
                    sigmoid,
                    lapse: LapseMode::Fixed,
                    guess: GUESS,
                },
            );
            let m = *f.model().expect("finite");
            let data = Data::new(&c);
            let ll_at = |a: f64, b: f64| {
                data.log_likelihood(&Model {
                    sigmoid,
                    alpha: a,
                    beta: b,
                    lapse: 0.0,
                    guess: GUESS,
                })
            };
            let mut best = (f64::NEG_INFINITY, 0.0, 0.0);
            for i in 0..=300 {
                for j in 1..=200 {
                    let (a, b) = (i as f64 * 0.02, j as f64 * 0.02);
                    let v = ll_at(a, b);
                    if v > best.0 {
                        best = (v, a, b);
                    }
                }
            }
            let (_, a0, b0) = best;
            for i in -150..=150 {
                for j in -150..=150 {
                    let (a, b) = (a0 + i as f64 * 2e-4, b0 + j as f64 * 2e-4);
                    if b > 0.0 {
                        let v = ll_at(a, b);
                        if v > best.0 {
                            best = (v, a, b);
                        }
                    }
                }
            }
            assert!(
                f.log_likelihood >= best.0 - 1e-9,
                "{sigmoid:?} {} {best:?}",
                f.log_likelihood
            );
            assert!(
                (m.alpha - best.1).abs() < 5e-4,
                "{sigmoid:?} {m:?} {best:?}"
            );
            assert!((m.beta - best.2).abs() < 5e-4, "{sigmoid:?} {m:?} {best:?}");
        }
    }

    #[test]
    fn free_lapse_stays_in_bounds_and_helps_with_lapses() {
        // A lapse at the easiest level: fixed lapse must bend the curve, free lapse absorbs it.
        let c = Curve::from_counts([
            (1, 45, 48),
            (8, 45, 48),
            (27, 40, 48),
            (64, 30, 48),
            (125, 25, 48),
            (216, 24, 48),
        ]);
        let fixed = fit(&c, &FitSettings::default());
        let free = fit(
            &c,
            &FitSettings {
                lapse: LapseMode::Free,
                ..FitSettings::default()
            },
        );
        let m = free.model().expect("finite");
        assert!((0.0..=LAPSE_MAX).contains(&m.lapse));
        assert!(m.lapse > 0.02, "{m:?}");
        assert!(free.log_likelihood >= fixed.log_likelihood - 1e-9);
    }

    #[test]
    fn single_level_and_empty_curves_are_unidentified() {
        let one = curve(&[64], &[3], 4);
        let f = fit(&one, &FitSettings::default());
        assert_eq!(f.kind(), "unidentified");
        assert_eq!(f.fitted, vec![0.75]);
        let empty = Curve::default();
        let f = fit(&empty, &FitSettings::default());
        assert_eq!(f.kind(), "unidentified");
        assert!(f.deviance == 0.0 && f.log_likelihood == 0.0);
    }

    #[test]
    fn non_monotone_data_fits_finitely_with_large_deviance() {
        // Rising instead of falling: the best decreasing function is flat-ish at the mean or a
        // step; either way everything is finite and the deviance shows the misfit.
        let c = Curve::from_counts([(1, 24, 48), (8, 30, 48), (27, 36, 48), (64, 44, 48)]);
        let f = fit(&c, &FitSettings::default());
        assert!(f.log_likelihood.is_finite() && f.deviance.is_finite());
        assert!(f.deviance > 10.0, "{}", f.deviance);
        assert!(f.fitted.iter().all(|p| (0.5..=1.0).contains(p)));
    }

    /// The best log-likelihood on a grid over the whole bounded search space (alpha x ln beta,
    /// x lapse when free): an optimizer-free lower bound on the maximum.
    fn grid_best(c: &Curve, settings: &FitSettings) -> f64 {
        let data = Data::new(c);
        let space = Space::new(&data, settings);
        let lapses: &[f64] = match settings.lapse {
            LapseMode::Fixed => &[0.0],
            LapseMode::Free => &[0.0, 0.02, 0.04, LAPSE_MAX],
        };
        let n = 40;
        let mut best = f64::NEG_INFINITY;
        for i in 0..=n {
            let alpha = space.mid - space.half + 2.0 * space.half * i as f64 / n as f64;
            for j in 0..=n {
                let ln_b = space.ln_b_lo + (space.ln_b_hi - space.ln_b_lo) * j as f64 / n as f64;
                for &lapse in lapses {
                    let m = Model {
                        sigmoid: settings.sigmoid,
                        alpha,
                        beta: ln_b.exp(),
                        lapse,
                        guess: settings.guess,
                    };
                    best = best.max(data.log_likelihood(&m));
                }
            }
        }
        best
    }

    /// Tables on which the property test below once found the fit short of the grid (each a
    /// Nelder-Mead start problem, see `psychometric/starts.rs`), kept as fixed regressions.
    #[test]
    fn hard_tables_found_by_the_stress_test() {
        use LapseMode::{Fixed, Free};
        use Sigmoid::{Logistic, Normal, Weibull};
        type Case<'a> = (&'a [(u32, u32, u32)], Sigmoid, LapseMode);
        let cases: [Case; 5] = [
            (
                &[(741, 60, 95), (1934, 91, 109), (2787, 12, 17)],
                Weibull,
                Free,
            ),
            (
                &[
                    (194, 1, 7),
                    (292, 42, 73),
                    (917, 17, 26),
                    (1489, 0, 1),
                    (1641, 0, 20),
                    (1782, 0, 1),
                ],
                Normal,
                Fixed,
            ),
            (
                &[
                    (180, 1, 7),
                    (319, 49, 85),
                    (1114, 22, 34),
                    (1497, 0, 1),
                    (1628, 0, 28),
                    (2730, 0, 1),
                ],
                Normal,
                Fixed,
            ),
            (
                &[
                    (256, 15, 25),
                    (1701, 113, 159),
                    (1708, 0, 5),
                    (1963, 99, 105),
                    (2107, 41, 93),
                    (2843, 70, 139),
                    (4069, 64, 145),
                ],
                Logistic,
                Free,
            ),
            (
                &[
                    (279, 23, 38),
                    (1755, 113, 159),
                    (1853, 51, 54),
                    (2112, 38, 86),
                    (2162, 0, 137),
                    (2512, 7, 18),
                    (2928, 60, 136),
                ],
                Logistic,
                Free,
            ),
        ];
        for (table, sigmoid, lapse) in cases {
            let c = Curve::from_counts(table.iter().copied());
            let settings = FitSettings {
                sigmoid,
                lapse,
                guess: GUESS,
            };
            let f = fit(&c, &settings);
            let grid = grid_best(&c, &settings);
            assert!(
                f.log_likelihood >= grid - 1e-9 * (1.0 + grid.abs()),
                "{table:?} {sigmoid:?} {lapse:?}: {} < {grid}",
                f.log_likelihood
            );
        }
        // The fourth table's optimum, located independently by a 100 x 100 scan in Python
        // (alpha 7.30..7.70 x ln beta 0..4, lapse at its bound 0.06): ln L = -446.8532 at
        // alpha = 7.492, ln beta = 1.68; the old starts stopped at -448.2509.
        let c = Curve::from_counts(cases[3].0.iter().copied());
        let f = fit(
            &c,
            &FitSettings {
                sigmoid: Logistic,
                lapse: Free,
                guess: GUESS,
            },
        );
        assert!(f.log_likelihood >= -446.8532, "{}", f.log_likelihood);
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig {
            cases: 48,
            rng_seed: proptest::test_runner::RngSeed::Fixed(0x5eed),
            failure_persistence: None,
            ..proptest::prelude::ProptestConfig::default()
        })]
        /// Numerical stability on arbitrary count tables: 1-8 levels anywhere in 1..4096 spp,
        /// 1-200 trials per level (so both separated and near-asymptotic data), any counts,
        /// every sigmoid and lapse mode, guess rates of 2, 3, 4 and 10 alternatives. The fit is
        /// finite, its fitted values lie in the model's range [g, 1], and its likelihood is at least that of the best point of an independent grid
        /// over the whole search space and that of the closed-form step. Tolerance: the
        /// optimizer stops when the simplex's values agree to 1e-11 relative, so 1e-9 (1 + |ll|)
        /// leaves two orders of magnitude for the last simplex's spread.
        #[test]
        fn fit_is_at_least_as_likely_as_any_grid_point(
            table in proptest::collection::vec((1u32..4096, 1u32..=200, 0.0f64..=1.0), 1..=8),
            sig in 0..Sigmoid::ALL.len(),
            free in proptest::bool::ANY,
            m in proptest::sample::select(vec![2u32, 3, 4, 10]),
        ) {
            let c = Curve::from_counts(
                table.iter().map(|&(l, n, u)| (l, (u * n as f64).round() as u32, n)),
            );
            let settings = FitSettings {
                sigmoid: Sigmoid::ALL[sig],
                lapse: if free { LapseMode::Free } else { LapseMode::Fixed },
                guess: 1.0 / m as f64,
            };
            let f = fit(&c, &settings);
            proptest::prop_assert!(f.log_likelihood.is_finite() && f.log_likelihood <= 0.0);
            proptest::prop_assert!(f.deviance.is_finite() && f.deviance >= 0.0);
            proptest::prop_assert!(f.fitted.iter().all(|p| (settings.guess..=1.0).contains(p)));
            if c.points.len() >= 2 {
                let tol = |ll: f64| 1e-9 * (1.0 + ll.abs());
                let grid = grid_best(&c, &settings);
                proptest::prop_assert!(
                    f.log_likelihood >= grid - tol(grid),
                    "fit {} ({}) < grid {grid} on {:?}", f.log_likelihood, f.kind(), c.points
                );
                let (_, _, ll_step) = best_step(&c, settings.lapse, settings.guess);
                proptest::prop_assert!(f.log_likelihood >= ll_step - tol(ll_step));
            }
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig {
            cases: 64,
            rng_seed: proptest::test_runner::RngSeed::Fixed(0x5eed),
            failure_persistence: None,
            ..proptest::prelude::ProptestConfig::default()
        })]
        /// Subject-sized data (0-4 of 4 per level, 1-8 thesis levels), every sigmoid and lapse
        /// mode: everything finite, fitted values inside the model's range, deviance >= 0, and
        /// a numeric threshold only inside the tested levels.
        #[test]
        fn subject_sized_data_never_gives_nonsense(
            ks in proptest::collection::vec(0u32..=4, 1..=8),
            sig in 0..Sigmoid::ALL.len(),
            free in proptest::bool::ANY,
        ) {
            let c = curve(&THESIS[..ks.len()], &ks, 4);
            let settings = FitSettings {
                sigmoid: Sigmoid::ALL[sig],
                lapse: if free { LapseMode::Free } else { LapseMode::Fixed },
                guess: GUESS,
            };
            let f = fit(&c, &settings);
            proptest::prop_assert!(f.log_likelihood.is_finite() && f.log_likelihood <= 0.0);
            proptest::prop_assert!(f.deviance.is_finite() && f.deviance >= 0.0);
            proptest::prop_assert!(f.fitted.iter().all(|p| (0.5..=1.0).contains(p)));
            let (_, _, ll_step) = best_step(&c, settings.lapse, settings.guess);
            proptest::prop_assert!(f.log_likelihood >= ll_step - 1e-9);
            if let crate::jnd::Threshold::Value { spp } = crate::jnd::model_threshold(&f, 0.75) {
                proptest::prop_assert!(spp >= 1.0 && spp <= THESIS[ks.len() - 1] as f64);
            }
        }
    }
}
