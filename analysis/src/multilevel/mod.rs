//! Analysis across subjects: a multilevel (mixed-effects) psychometric model.
//!
//! The pooled fit treats every trial as if one observer gave it, and its parametric bootstrap
//! resamples trials, so its interval ignores that people differ. Here each group's subjects get
//! their own threshold, normal in ln spp around the population's ([`model`]): the population
//! JND's interval then carries the between-subject variance, the between-subject SD is an
//! estimate of its own, and each subject's JND is shrunk towards the population's as far as
//! the subject's own data are weak (with 4 trials per level, far). Fitted by maximum likelihood
//! with adaptive Gauss-Hermite quadrature over each subject's offset (as lme4's `glmer` with
//! `nAGQ` > 1, the guess rate and lapse built into the link). Three intervals for the
//! population JND: the profile-likelihood interval ([`profile`], the reported one), Wald from
//! the observed information (both with Student t at subjects - 1 df), and a subject bootstrap
//! (resampling whole subjects and refitting), the simpler one.
//!
//! [`compare`] compares groups (scenes, point sets) within one model: differences in ln JND
//! with Wald and likelihood-ratio tests, and two one-sided tests of equivalence.

pub mod compare;
mod fit;
pub mod model;
pub mod profile;
pub mod quadrature;
mod subjects;

use crate::bootstrap::Bound;
use crate::data::{Curve, Dataset, Group, GroupKey};
use crate::jnd::Threshold;
use crate::psychometric::{FitSettings, fit as fit_pooled};
pub use fit::{Estimate, spd_inverse};
use model::{Counts, Layout, Likelihood, Params, free_lapse};
use quadrature::Rule;
use serde::Serialize;
use statrs::distribution::{ContinuousCDF, StudentsT};
pub use subjects::{SubjectBootstrap, resample_subjects};

/// How to fit and bootstrap the multilevel model.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MultilevelSettings {
    /// Gauss-Hermite nodes per subject (15; 1 is the Laplace approximation).
    pub nodes: usize,
    /// Subject-bootstrap resamples (0: none).
    pub resamples: usize,
    pub seed: u64,
    /// Coverage of the intervals (0.95).
    pub confidence: f64,
    /// Equivalence margin in ln JND for the two one-sided tests (`--equivalence`).
    pub equivalence: Option<f64>,
}

impl Default for MultilevelSettings {
    fn default() -> Self {
        MultilevelSettings {
            nodes: 15,
            resamples: 200,
            seed: 1,
            confidence: 0.95,
            equivalence: None,
        }
    }
}

/// What the fits share: the psychometric settings, the target, and the levels left out.
#[derive(Clone, Copy, Debug)]
pub struct Context<'a> {
    pub fit: &'a FitSettings,
    pub target: f64,
    pub settings: &'a MultilevelSettings,
    /// Levels whose trials showed the reference against itself ([`Dataset::same_video_levels`]):
    /// every observer is at chance there whatever its threshold, which the model's function
    /// (at chance only far above the threshold) would read as a lower threshold. Dropped once
    /// by [`informative`] where a model takes its groups' curves ([`estimate`], [`group_model`],
    /// [`compare::compare_pair`]); the fits, starts and bootstraps below see only the rest.
    pub same_video_levels: &'a [u32],
}

/// One subject's shrunken JND: the posterior of the subject's threshold given the data at the
/// estimate. Like the population's, it is never extrapolated: beyond the tested levels it is
/// `> top` or `< bottom` (issue 42: all-correct logs gave 15625 spp where levels end at 125).
#[derive(Clone, Debug, Serialize)]
pub struct ShrunkenJnd {
    pub subject: String,
    /// t + E[u | data], ln spp (for a caller that knows what it does with a value past the
    /// range).
    pub ln_jnd: f64,
    /// exp(t + E[u | data]) as the data support it.
    pub jnd: Threshold,
    /// ln JND -+ z sqrt(SD[u | data]^2 + SE[t]^2): the posterior's spread widened by the
    /// population threshold's own standard error (the uncertainty of sigma and the slope is
    /// still not included; the report says so).
    pub lower: Bound,
    pub upper: Bound,
}

/// The multilevel model of one group.
#[derive(Clone, Debug, Serialize)]
pub struct GroupModel {
    pub key: GroupKey,
    pub subjects: usize,
    /// The population JND (the typical subject's, u = 0) in ln spp, and its standard error.
    pub ln_jnd: f64,
    pub ln_jnd_se: Option<f64>,
    /// Its cluster-robust (sandwich, CR1) standard error, subjects as clusters.
    pub ln_jnd_robust_se: Option<f64>,
    /// The population JND as the data support it (never extrapolated).
    pub jnd: Threshold,
    /// The reported interval: profile likelihood at the Student t quantile with subjects - 1
    /// df ([`profile`]; it covers where the Wald interval falls short when subjects differ
    /// widely, `docs/analysis.md`).
    pub ci_lower: Option<Bound>,
    pub ci_upper: Option<Bound>,
    /// Wald interval, Student t with subjects - 1 df.
    pub wald_lower: Option<Bound>,
    pub wald_upper: Option<Bound>,
    pub slope: f64,
    /// Between-subject SD of the threshold in ln spp, with a Wald interval on ln sigma (none
    /// when sigma is at its lower bound 0.001: no spread detected).
    pub sigma: f64,
    pub sigma_ci: Option<(f64, f64)>,
    pub lapse: f64,
    pub log_likelihood: f64,
    pub bootstrap: Option<SubjectBootstrap>,
    pub shrunken: Vec<ShrunkenJnd>,
}

/// The Student t quantile with `df` degrees of freedom at `p`.
pub fn t_quantile(p: f64, df: f64) -> f64 {
    StudentsT::new(0.0, 1.0, df).expect("df > 0").inverse_cdf(p)
}

/// Starting vectors: each group's pooled fit (or the middle of the range with a moderate slope
/// when the pooled fit is a step), with a narrow and a wide between-subject SD.
fn starts(curves: &[&[Curve]], layout: Layout, cx: &Context, counts: &Counts) -> Vec<Vec<f64>> {
    let span = (counts.x_hi - counts.x_lo).max(1.0);
    let mid = 0.5 * (counts.x_lo + counts.x_hi);
    let per_group: Vec<(f64, f64)> = curves
        .iter()
        .map(|c| {
            let pooled = Curve::from_counts(
                c.iter()
                    .flat_map(|s| &s.points)
                    .map(|p| (p.level, p.correct, p.trials)),
            );
            let f = fit_pooled(&pooled, cx.fit);
            match f
                .model()
                .and_then(|m| m.x_at(cx.target).map(|x| (x, m.beta)))
            {
                Some((x, b)) => (x.clamp(counts.x_lo - span, counts.x_hi + span), b),
                None => (mid, 4.0 / span),
            }
        })
        .collect();
    [0.2, 0.8]
        .iter()
        .map(|&sigma| {
            let t: Vec<f64> = per_group.iter().map(|g| g.0).collect();
            let nt = layout.thresholds();
            let mean = t.iter().sum::<f64>() / t.len() as f64;
            layout.vector(&Params {
                thresholds: if nt == 1 { vec![mean; t.len()] } else { t },
                slopes: per_group.iter().map(|g| g.1).collect(),
                sigma,
                lapse: 0.01,
            })
        })
        .collect()
}

/// The curves without their points at the same-video levels: the one place they are dropped,
/// when a model's groups are taken from the data.
pub fn informative(curves: &[Curve], same_video_levels: &[u32]) -> Vec<Curve> {
    curves
        .iter()
        .map(|c| Curve {
            points: (c.points.iter())
                .filter(|p| !same_video_levels.contains(&p.level))
                .copied()
                .collect(),
        })
        .collect()
}

/// Fit one model of `curves[k][s]` (group k, subject s) with their same-video levels left out
/// ([`informative`]); `None` when it is not identified (fewer than two subjects with data, or
/// a single tested level).
pub fn estimate(
    curves: &[&[Curve]],
    shared_threshold: bool,
    cx: &Context,
    warm: Option<&[f64]>,
) -> Option<(Estimate, Counts)> {
    let kept: Vec<Vec<Curve>> = curves
        .iter()
        .map(|c| informative(c, cx.same_video_levels))
        .collect();
    let refs: Vec<&[Curve]> = kept.iter().map(|c| c.as_slice()).collect();
    fit_informative(&refs, shared_threshold, cx, warm)
}

/// [`estimate`] of curves already without their same-video levels.
fn fit_informative(
    curves: &[&[Curve]],
    shared_threshold: bool,
    cx: &Context,
    warm: Option<&[f64]>,
) -> Option<(Estimate, Counts)> {
    let counts = Counts::new(curves);
    if !counts.identified() {
        return None;
    }
    let layout = Layout {
        groups: curves.len(),
        shared_threshold,
        free_lapse: free_lapse(cx.fit),
    };
    let rule = Rule::new(cx.settings.nodes);
    let lik = Likelihood {
        counts: &counts,
        fit: *cx.fit,
        target: cx.target,
        rule: &rule,
    };
    let starts = match warm {
        Some(w) => vec![w.to_vec()],
        None => starts(curves, layout, cx, &counts),
    };
    let e = fit::estimate(&lik, layout, &starts, warm.is_none());
    Some((e, counts))
}

/// The multilevel model of one group of the data, with its subject bootstrap.
pub fn group_model(ds: &Dataset, g: &Group, cx: &Context) -> Option<GroupModel> {
    let kept = informative(&g.per_subject, cx.same_video_levels);
    let curves: [&[Curve]; 1] = [&kept];
    let (e, counts) = fit_informative(&curves, false, cx, None)?;
    let n = counts.subjects.len();
    let df = (n - 1) as f64;
    let z = 1.0 - 0.5 * (1.0 - cx.settings.confidence);
    let tq = t_quantile(z, df);
    let zq = t_quantile(z, 1e6);
    let t = e.params.thresholds[0];
    let se = e.se(0);
    let lo = counts.x_lo;
    let hi = counts.x_hi;
    let levels = counts.levels;
    let bound = |x: f64| bound_of(x, lo, hi, levels);
    let si = e.layout.sigma_index();
    let shrunken = counts
        .subjects
        .iter()
        .zip(&e.subjects)
        .map(|(&s, i)| {
            let x = t + i.mean;
            let sd = i.sd.hypot(se.unwrap_or(0.0));
            ShrunkenJnd {
                subject: ds.subjects[s].clone(),
                ln_jnd: x,
                jnd: threshold_of(x, lo, hi, levels),
                lower: bound(x - zq * sd),
                upper: bound(x + zq * sd),
            }
        })
        .collect();
    let (p_lo, p_hi) = profile::threshold_interval(&e, &counts, cx, 0, tq);
    let bootstrap = (cx.settings.resamples > 0)
        .then(|| subjects::bootstrap_group(&curves, cx, &e.vector, g.key.id()))
        .flatten()
        .map(|b| b.with_bounds(lo, hi, levels));
    Some(GroupModel {
        key: g.key.clone(),
        subjects: n,
        ln_jnd: t,
        ln_jnd_se: se,
        ln_jnd_robust_se: e.robust_se(0),
        jnd: threshold_of(t, lo, hi, levels),
        ci_lower: Some(bound(p_lo)),
        ci_upper: Some(bound(p_hi)),
        wald_lower: se.map(|s| bound(t - tq * s)),
        wald_upper: se.map(|s| bound(t + tq * s)),
        slope: e.params.slopes[0],
        sigma: e.params.sigma,
        sigma_ci: e.se(si).map(|s| {
            let ls = e.params.sigma.ln();
            ((ls - zq * s).exp(), (ls + zq * s).exp())
        }),
        lapse: e.params.lapse,
        log_likelihood: e.log_likelihood,
        bootstrap,
        shrunken,
    })
}

/// All groups' models (conditions, scenes, point sets, time filters), in the data's order.
pub fn group_models(ds: &Dataset, cx: &Context) -> Vec<GroupModel> {
    ds.groups
        .iter()
        .filter_map(|g| group_model(ds, g, cx))
        .collect()
}

/// ln spp as a threshold inside the tested range, or beyond it with the bound.
fn threshold_of(x: f64, lo: f64, hi: f64, levels: (u32, u32)) -> Threshold {
    match bound_of(x, lo, hi, levels) {
        Bound::BelowRange { bound } => Threshold::BelowRange { bound },
        Bound::AboveRange { bound } => Threshold::AboveRange { bound },
        Bound::Value { spp } => Threshold::Value { spp },
    }
}

/// ln spp as an interval end inside the tested range, or beyond it with the bound.
fn bound_of(x: f64, lo: f64, hi: f64, (first, last): (u32, u32)) -> Bound {
    if x < lo {
        Bound::BelowRange { bound: first }
    } else if x > hi {
        Bound::AboveRange { bound: last }
    } else {
        Bound::Value { spp: x.exp() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::psychometric::{GUESS, LapseMode, Model};
    use crate::sigmoid::Sigmoid;
    use crate::simulate::{
        THESIS_LEVELS as THESIS, expected_curve, simulate_curve, thesis_plane_model,
    };
    use renderer::hash::{hash, unit_f64};

    pub(super) fn cx(settings: &MultilevelSettings) -> Context<'_> {
        static FIT: FitSettings = FitSettings {
            sigmoid: Sigmoid::Logistic,
            lapse: LapseMode::Fixed,
            guess: GUESS,
        };
        Context {
            fit: &FIT,
            target: 0.75,
            settings,
            same_video_levels: &[],
        }
    }

    /// Subjects with thresholds normal around `jnd` spp (SD `sigma` in ln spp), logistic slope
    /// 1.5, `trials` per thesis level; returns the curves and the subjects' true ln thresholds.
    pub(super) fn subjects(
        n: usize,
        jnd: f64,
        sigma: f64,
        trials: u32,
        seed: u64,
    ) -> (Vec<Curve>, Vec<f64>) {
        (0..n as u64)
            .map(|s| {
                let z = Sigmoid::Normal.inverse(unit_f64(hash(seed, &[0x0ff5, s])).max(1e-12));
                let t = jnd.ln() + sigma * z;
                // alpha is the threshold at 0.75 for the logistic with g = 1/2.
                let m = Model {
                    sigmoid: Sigmoid::Logistic,
                    alpha: t,
                    beta: 1.5,
                    lapse: 0.0,
                    guess: GUESS,
                };
                (simulate_curve(&m, &THESIS, trials, seed, &[s]), t)
            })
            .unzip()
    }

    #[test]
    fn identical_subjects_give_the_pooled_fit_and_no_spread() {
        // Every subject has the same exact expected counts: the marginal likelihood is at most
        // (max_u L(u))^S, reached only as sigma -> 0 at the pooled optimum, so the model must
        // find sigma at its bound, the pooled threshold and the pooled likelihood.
        let one = expected_curve(&thesis_plane_model(), &THESIS, 1000);
        let curves = vec![one.clone(); 6];
        let settings = MultilevelSettings::default();
        let (e, _) = estimate(&[&curves], false, &cx(&settings), None).unwrap();
        let pooled = fit_pooled(
            &Curve::from_counts(
                curves
                    .iter()
                    .flat_map(|c| c.points.iter().map(|p| (p.level, p.correct, p.trials))),
            ),
            &FitSettings::default(),
        );
        let m = pooled.model().unwrap();
        assert!(e.params.sigma < 0.01, "{:?}", e.params);
        assert!(
            (e.params.thresholds[0] - m.x_at(0.75).unwrap()).abs() < 1e-3,
            "{:?}",
            e.params
        );
        assert!(
            (e.params.slopes[0] - m.beta).abs() < 1e-2,
            "{:?} {m:?}",
            e.params
        );
        assert!((e.log_likelihood - pooled.log_likelihood).abs() < 1e-3 * 6.0);
    }

    #[test]
    fn parameters_are_recovered_within_their_standard_errors() {
        // 40 subjects, spread 0.5 ln spp, 40 trials per level: the population threshold and ln
        // sigma within 3 of their own standard errors of the truth (a 0.3% chance each of a
        // false failure if the errors are right), and the shrunken offsets follow the true
        // ones.
        let settings = MultilevelSettings {
            resamples: 0,
            ..MultilevelSettings::default()
        };
        for (seed, sigma) in [(1u64, 0.5), (2, 0.3)] {
            let (curves, truth) = subjects(40, 60.0, sigma, 40, seed);
            let (e, _) = estimate(&[&curves], false, &cx(&settings), None).unwrap();
            let t_se = e.se(0).unwrap();
            let ls_se = e.se(e.layout.sigma_index()).unwrap();
            assert!(
                (e.params.thresholds[0] - 60f64.ln()).abs() < 3.0 * t_se,
                "{e:?}"
            );
            assert!(
                (e.params.sigma.ln() - sigma.ln()).abs() < 3.0 * ls_se,
                "{e:?}"
            );
            let lb_se = e.se(1).unwrap();
            assert!(
                (e.params.slopes[0].ln() - 1.5f64.ln()).abs() < 3.0 * lb_se,
                "{e:?}"
            );
            // The SE of the population threshold includes the spread: at least sigma / sqrt(S).
            assert!(t_se > 0.9 * e.params.sigma / 40f64.sqrt(), "{t_se}");
            // Where the model is right the robust (sandwich) SE estimates the same variance:
            // a variance estimated from n clusters has a relative SD of about sqrt(2 / (n -
            // 1)), so the ratio of SEs is within 3 x sqrt(1 / (2 (n - 1))) = 0.34 of 1. The
            // scores sum to the total likelihood's gradient, 0 at the optimum.
            let robust = e.robust_se(0).unwrap();
            assert!((robust / t_se - 1.0).abs() < 0.34, "{robust} vs {t_se}");
            let total: f64 = e.scores.iter().map(|g| g[0]).sum();
            let spread = e.scores.iter().map(|g| g[0] * g[0]).sum::<f64>().sqrt();
            assert!(total.abs() < 0.05 * spread, "{total} vs {spread}");
            // Normal-normal shrinkage: corr(E[u | y], u)^2 = 1 - E[Var(u | y)] / sigma^2; the
            // sample correlation of 40 pairs within 3 of its standard errors (1 - rho^2) /
            // sqrt(n) of that.
            let est: Vec<f64> = e.subjects.iter().map(|i| i.mean).collect();
            let post_var = e.subjects.iter().map(|i| i.sd * i.sd).sum::<f64>() / 40.0;
            let rho = (1.0 - post_var / (sigma * sigma)).max(0.0).sqrt();
            let r = correlation(&est, &truth);
            let tol = 3.0 * (1.0 - rho * rho) / 40f64.sqrt();
            assert!(
                (r - rho).abs() < tol,
                "shrunken vs true r = {r}, expected {rho} +- {tol}"
            );
        }
    }

    fn correlation(a: &[f64], b: &[f64]) -> f64 {
        let n = a.len() as f64;
        let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
        let cov: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
        let va: f64 = a.iter().map(|x| (x - ma).powi(2)).sum();
        let vb: f64 = b.iter().map(|y| (y - mb).powi(2)).sum();
        cov / (va * vb).sqrt()
    }

    /// Like [`subjects`] over the thesis's levels below 512, with the top level's trials at
    /// chance whatever the threshold: test and reference the same video, as the thesis design
    /// (`highest_level` reference) shows them and the experiment's simulated observer answers.
    fn with_same_video_top(n: usize, jnd: f64, sigma: f64, trials: u32, seed: u64) -> Vec<Curve> {
        let chance = Model {
            alpha: -1e3,
            ..thesis_plane_model()
        };
        let (curves, _) = subjects(n, jnd, sigma, trials, seed);
        let mut out = Vec::new();
        for (s, c) in curves.into_iter().enumerate() {
            let top = simulate_curve(&chance, &[512], trials, seed, &[0x70b, s as u64]);
            let mut c = c;
            c.points.retain(|p| p.level != 512);
            c.points.extend(top.points); // 512 is the highest level: the order holds
            out.push(c);
        }
        out
    }

    #[test]
    fn same_video_trials_are_left_out_and_the_threshold_recovered() {
        // Subjects around 150 spp with SD 0.9 in ln spp: a third of them above 343, the last
        // informative level. Leaving the 512 trials out must give exactly the fit of data
        // without them; that fit recovers the population threshold within 3 of its standard
        // errors, while fitting the chance trials as if informative pulls it down (the model's
        // function is at chance only far above a threshold, so chance at 512 reads as a lower
        // threshold).
        let settings = MultilevelSettings {
            resamples: 0,
            ..MultilevelSettings::default()
        };
        let curves = with_same_video_top(60, 150.0, 0.9, 24, 5);
        let skip = Context {
            same_video_levels: &[512],
            ..cx(&settings)
        };
        let (left_out, _) = estimate(&[&curves], false, &skip, None).unwrap();
        let without: Vec<Curve> = curves
            .iter()
            .map(|c| Curve {
                points: c
                    .points
                    .iter()
                    .filter(|p| p.level != 512)
                    .copied()
                    .collect(),
            })
            .collect();
        let (absent, _) = estimate(&[&without], false, &cx(&settings), None).unwrap();
        assert_eq!(left_out.params, absent.params);
        let t_se = left_out.se(0).unwrap();
        let t = left_out.params.thresholds[0];
        assert!((t - 150f64.ln()).abs() < 3.0 * t_se, "{t} +- {t_se}");
        let (fitted, _) = estimate(&[&curves], false, &cx(&settings), None).unwrap();
        // Measured: left out 4.984 +- 0.132 (truth 5.011); fitted 4.856, 14% low.
        assert!(
            fitted.params.thresholds[0] < t - 0.5 * t_se,
            "{:?}",
            fitted.params
        );
    }

    #[test]
    fn a_lone_subject_or_a_single_level_is_not_identified() {
        let settings = MultilevelSettings::default();
        let (curves, _) = subjects(1, 60.0, 0.5, 4, 3);
        assert!(estimate(&[&curves], false, &cx(&settings), None).is_none());
        let single = vec![Curve::from_counts([(64, 3, 4)]); 5];
        assert!(estimate(&[&single], false, &cx(&settings), None).is_none());
    }
}
