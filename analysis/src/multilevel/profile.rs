//! The profile-likelihood interval of a population threshold.
//!
//! The Wald interval reads the likelihood's shape from its curvature at the estimate, with the
//! between-subject SD where the estimate left it (and left out where it sits at its bound).
//! With the thesis's 12 subjects of 28 informative trials each, sigma is poorly located: low
//! on average and at its bound in some data sets (`docs/benchmarks/multilevel.md`,
//! "Results"). The profile interval lets every other parameter move: it is the set of thresholds t
//! whose profile deviance 2 (ln L(estimate) - max over the others of ln L(t, others)) is at
//! most q^2, q the Wald interval's Student t quantile, so that the two agree where the
//! likelihood is quadratic.

use super::Context;
use super::fit::{Estimate, minimise};
use super::model::{Counts, Likelihood};
use super::quadrature::Rule;
use crate::optimizer::Tolerance;

/// The profile interval of threshold coordinate `index` of `e` (a model of `counts`), ln spp,
/// at `q` on the signed root of the deviance; an end is infinite where the deviance stays below
/// q^2 up to the threshold's bound (the tested span +- one span).
pub fn threshold_interval(
    e: &Estimate,
    counts: &Counts,
    cx: &Context,
    index: usize,
    q: f64,
) -> (f64, f64) {
    let rule = Rule::new(cx.settings.nodes);
    let lik = Likelihood {
        counts,
        fit: *cx.fit,
        target: cx.target,
        rule: &rule,
    };
    let mut profile = Profile {
        lik: &lik,
        e,
        index,
        warm: Vec::new(),
    };
    // Without a Wald SE (a singular curvature) the search starts half a ln unit out.
    let step = q * e.se(index).unwrap_or(0.5 / q);
    (profile.end(-1.0, q, step), profile.end(1.0, q, step))
}

/// The deviance of one threshold held, the other parameters maximised from a warm start.
struct Profile<'a> {
    lik: &'a Likelihood<'a>,
    e: &'a Estimate,
    index: usize,
    /// The others' last maximum, the start of the next.
    warm: Vec<f64>,
}

impl Profile<'_> {
    /// The estimate's other coordinates, sigma at least 0.05 so that the simplex can leave a
    /// sigma at its bound (where the likelihood is flat in ln sigma).
    fn reset(&mut self) {
        let si = self.e.layout.sigma_index();
        let floor = 0.05f64.ln();
        self.warm = (self.e.vector.iter().enumerate())
            .filter(|&(i, _)| i != self.index)
            .map(|(i, &x)| if i == si { x.max(floor) } else { x })
            .collect();
    }

    /// The signed root's size sqrt(2 (ln L(estimate) - ln L_profile(t))), 0 where the profile
    /// is higher (the estimate a little short of the maximum).
    fn root(&mut self, t: f64) -> f64 {
        let (layout, bounds, index) = (self.e.layout, self.e.bounds, self.index);
        let lik = self.lik;
        let f = |w: &[f64]| {
            let mut v = w.to_vec();
            v.insert(index, t);
            -lik.ln_value(&layout.params(&v, &bounds))
        };
        // The deviance is wanted to about 1e-3 (the ends to a thousandth of q).
        let tol = Tolerance {
            value: 1e-11,
            position: 1e-5,
            max_evaluations: 1500,
        };
        let (w, value) = minimise(&f, &self.warm, 0.2, tol);
        self.warm = w;
        (2.0 * (value + self.e.log_likelihood)).max(0.0).sqrt()
    }

    /// The end on side `dir` (-1 or +1): out from the estimate in steps doubling from `step`
    /// until the root passes q (or the bound does not), then false position, each new point
    /// kept at least a tenth of the bracket from its ends.
    fn end(&mut self, dir: f64, q: f64, step: f64) -> f64 {
        self.reset();
        let t0 = self.e.params.thresholds[self.index];
        let (lo, hi) = self.e.bounds.t;
        let limit = if dir < 0.0 { lo } else { hi };
        let mut inside = (t0, 0.0);
        let mut step = step.max(1e-3);
        let mut outside = loop {
            let t = t0 + dir * step;
            if (t - limit) * dir >= 0.0 {
                let r = self.root(limit);
                if r < q {
                    return dir * f64::INFINITY;
                }
                break (limit, r);
            }
            let r = self.root(t);
            if r >= q {
                break (t, r);
            }
            inside = (t, r);
            step *= 2.0;
        };
        for _ in 0..30 {
            let ((a, ra), (b, rb)) = (inside, outside);
            let at = (q - ra) / (rb - ra);
            let t = a + (b - a) * at.clamp(0.1, 0.9);
            let r = self.root(t);
            if (r - q).abs() < 1e-3 || (b - a).abs() < 1e-5 {
                return t;
            }
            if r < q {
                inside = (t, r);
            } else {
                outside = (t, r);
            }
        }
        let ((a, ra), (b, rb)) = (inside, outside);
        a + (b - a) * (q - ra) / (rb - ra)
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{cx, subjects};
    use super::super::{MultilevelSettings, estimate, t_quantile};
    use super::*;
    use crate::data::Curve;
    use crate::simulate::{THESIS_LEVELS as THESIS, expected_curve, thesis_plane_model};

    #[test]
    fn where_the_likelihood_is_quadratic_the_profile_is_the_wald_interval() {
        // 40 subjects of 40 trials per level (the recovery test's data): the estimate's
        // sampling distribution is close to normal, the log-likelihood close to quadratic in
        // the threshold, so both intervals' half-widths agree; 5% allows for the cubic term
        // of a binomial likelihood, which the Wald interval ignores.
        let settings = MultilevelSettings {
            resamples: 0,
            ..MultilevelSettings::default()
        };
        let (curves, _) = subjects(40, 60.0, 0.5, 40, 1);
        let cx = cx(&settings);
        let (e, counts) = estimate(&[&curves], false, &cx, None).unwrap();
        let q = t_quantile(0.975, 39.0);
        let (lo, hi) = threshold_interval(&e, &counts, &cx, 0, q);
        let (t, half) = (e.params.thresholds[0], q * e.se(0).unwrap());
        for (end, wald) in [(lo, t - half), (hi, t + half)] {
            assert!(
                (end - wald).abs() < 0.05 * half,
                "{end} vs {wald} (+-{half})"
            );
        }
    }

    #[test]
    fn with_sigma_at_its_bound_the_profile_is_no_narrower() {
        // Identical subjects: sigma at its bound, left out of the Wald covariance. The profile
        // maximises over sigma as well, so its deviance is at most that with sigma held, whose
        // interval the Wald one approximates: no narrower (up to the cubic term, 5%), finite,
        // and around the estimate.
        let one = expected_curve(&thesis_plane_model(), &THESIS, 24);
        let curves: Vec<Curve> = vec![one; 8];
        let settings = MultilevelSettings {
            resamples: 0,
            ..MultilevelSettings::default()
        };
        let cx = cx(&settings);
        let (e, counts) = estimate(&[&curves], false, &cx, None).unwrap();
        assert!(e.params.sigma < 0.01, "{:?}", e.params);
        let q = t_quantile(0.975, 7.0);
        let (lo, hi) = threshold_interval(&e, &counts, &cx, 0, q);
        let t = e.params.thresholds[0];
        let half = q * e.se(0).unwrap();
        assert!(lo.is_finite() && hi.is_finite(), "{lo} {hi}");
        assert!(lo < t && t < hi, "{lo} {t} {hi}");
        assert!(hi - lo > 0.95 * 2.0 * half, "{lo} {hi} vs {t} +- {half}");
    }
}
