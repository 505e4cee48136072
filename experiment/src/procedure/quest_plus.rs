//! QUEST+ (Watson 2017, JOV 17(3):10) over the rendered levels: a posterior over (ln threshold,
//! slope) on a grid; each trial takes the level whose answer is expected to leave the least
//! posterior entropy. The psychometric function is the two-pair task's
//! ([`crate::psychometric::p_correct`]: guess rate 1/2, the design's fixed lapse rate, threshold at
//! p = 0.75), the function the simulated observers answer with and the analysis fits.
//!
//! Choices the paper leaves to the user (docs/experiment.md): the threshold grid spans ln spp
//! from one below the lowest level to one above the highest in steps of 0.05 with a flat prior
//! (a threshold outside the rendered levels is only known to be outside), or flat over the
//! spec's `threshold` range and 0 outside it; the slope grid has 9
//! values at the prior median x e^(sd z), z = -2 ... 2, weighted by the normal density of z.

use super::interleave::{Interleaved, Track};
use crate::design::Design;
use crate::design::procedure::{QuestGoal, QuestPlusSpec, ThresholdRange, grid_range};
use crate::psychometric::{TARGET, p_correct};
use anyhow::{Result, bail};

/// Grid step of ln threshold.
const THETA_STEP: f64 = 0.05;
/// Slope grid points (odd: the median is one).
const SLOPES: usize = 9;

/// One subject's QUEST+ per condition, interleaved.
pub fn procedure(design: &Design, seed: u64, spec: &QuestPlusSpec) -> Interleaved<QuestPlus> {
    let mut levels = design.file.levels.clone();
    levels.sort_unstable();
    let first = QuestPlus::new(&levels, spec);
    Interleaved::new(design, seed, 1, spec.trials, |_| first.clone())
}

/// One condition's posterior.
#[derive(Clone, Debug)]
pub struct QuestPlus {
    thetas: Vec<f64>,
    slopes: Vec<f64>,
    /// `likelihood[level][m]`: p(correct) at a level for parameter m = theta x SLOPES + slope.
    likelihood: Vec<Vec<f64>>,
    posterior: Vec<f64>,
    stop_width: Option<f64>,
    goal: QuestGoal,
    next: usize,
    stopped: bool,
}

impl QuestPlus {
    /// The prior over the grid for levels sorted ascending.
    pub fn new(levels: &[u32], spec: &QuestPlusSpec) -> Self {
        let (lo, hi) = grid_range(levels);
        let n = ((hi - lo) / THETA_STEP).round() as usize + 1;
        let thetas: Vec<f64> = (0..n).map(|j| lo + j as f64 * THETA_STEP).collect();
        let zs: Vec<f64> = (0..SLOPES)
            .map(|k| -2.0 + 4.0 * k as f64 / (SLOPES - 1) as f64)
            .collect();
        let slopes: Vec<f64> = zs
            .iter()
            .map(|z| spec.slope.median * (spec.slope.sd_ln * z).exp())
            .collect();
        let weights: Vec<f64> = zs.iter().map(|z| (-0.5 * z * z).exp()).collect();
        let mut posterior = Vec::with_capacity(n * SLOPES);
        for &t in &thetas {
            let inside = spec.threshold.as_ref().is_none_or(|r| in_range(r, t));
            posterior.extend(weights.iter().map(|w| if inside { *w } else { 0.0 }));
        }
        normalise(&mut posterior);
        let likelihood = levels
            .iter()
            .map(|&l| {
                let x = (l as f64).ln();
                thetas
                    .iter()
                    .flat_map(|&t| slopes.iter().map(move |&b| p_correct(b, spec.lapse, t, x)))
                    .collect()
            })
            .collect();
        let mut q = Self {
            thetas,
            slopes,
            likelihood,
            posterior,
            stop_width: spec.stop_width,
            goal: spec.goal,
            next: 0,
            stopped: false,
        };
        q.next = q.best_level();
        q
    }

    /// The level index whose answer leaves the least expected entropy (the lowest on a tie).
    fn best_level(&self) -> usize {
        let mut best = (f64::INFINITY, 0);
        for (i, like) in self.likelihood.iter().enumerate() {
            let h = match self.goal {
                QuestGoal::Joint => expected_entropy(&self.posterior, like),
                QuestGoal::Threshold => expected_marginal_entropy(&self.posterior, like, SLOPES),
            };
            if h < best.0 {
                best = (h, i);
            }
        }
        best.1
    }

    /// The marginal posterior of ln threshold.
    fn theta_marginal(&self) -> Vec<f64> {
        self.posterior
            .chunks(SLOPES)
            .map(|c| c.iter().sum())
            .collect()
    }

    /// Posterior mean of ln threshold and its 95% interval (grid quantiles).
    pub fn ln_threshold(&self) -> (f64, f64, f64) {
        let m = self.theta_marginal();
        let mean = m.iter().zip(&self.thetas).map(|(p, t)| p * t).sum();
        let quantile = |q: f64| {
            let mut c = 0.0;
            for (p, &t) in m.iter().zip(&self.thetas) {
                c += p;
                if c >= q {
                    return t;
                }
            }
            self.thetas[self.thetas.len() - 1]
        };
        (mean, quantile(0.025), quantile(0.975))
    }

    /// The parameter index where the posterior's cumulative sum first reaches `u` (a draw).
    #[cfg(test)]
    fn cumulative(&self, u: f64) -> usize {
        let mut c = 0.0;
        self.posterior
            .iter()
            .position(|p| {
                c += p;
                c >= u
            })
            .unwrap_or(self.posterior.len() - 1)
    }

    /// Posterior mean slope.
    pub fn slope(&self) -> f64 {
        self.posterior
            .chunks(SLOPES)
            .flat_map(|c| c.iter().zip(&self.slopes).map(|(p, b)| p * b))
            .sum()
    }
}

impl Track for QuestPlus {
    fn level(&self) -> usize {
        self.next
    }

    fn update(&mut self, level: usize, correct: bool) {
        for (p, &l) in self.posterior.iter_mut().zip(&self.likelihood[level]) {
            *p *= if correct { l } else { 1.0 - l };
        }
        normalise(&mut self.posterior);
        self.next = self.best_level();
        if let Some(w) = self.stop_width {
            let (_, lo, hi) = self.ln_threshold();
            self.stopped = hi - lo < w;
        }
    }

    fn stopped(&self) -> bool {
        self.stopped
    }

    fn estimate(&self, _levels: &[u32]) -> (f64, Option<(f64, f64)>, Option<f64>, f64) {
        let (mean, lo, hi) = self.ln_threshold();
        (
            mean.exp(),
            Some((lo.exp(), hi.exp())),
            Some(self.slope()),
            TARGET,
        )
    }
}

/// A stop rule met after the first trial whatever its answer stops every track there, while
/// the design reads as `trials` per track (issue 42: `stop_width: 1e308` ran one trial a track
/// and `simulate` announced 96): refused when the design is loaded.
pub fn check_stop_width(spec: &QuestPlusSpec, levels: &[u32]) -> Result<()> {
    let Some(w) = spec.stop_width else {
        return Ok(());
    };
    let width = |q: &QuestPlus| {
        let (_, lo, hi) = q.ln_threshold();
        hi - lo
    };
    let prior = QuestPlus::new(levels, spec);
    let first = prior.level();
    let after = [true, false].map(|correct| {
        let mut q = prior.clone();
        q.update(first, correct);
        width(&q)
    });
    let widest = after[0].max(after[1]);
    if widest < w {
        bail!(
            "field `procedure.quest_plus.stop_width` is {}, but the 95% interval of ln \
             threshold is at most {widest:.3} wide after the first trial (the prior's is \
             {:.3}), so every track would stop after one trial; expected a width below \
             {widest:.3} (0.5 is a factor 1.65 between the interval's ends)",
            renderer::limits::shortest(w),
            width(&prior)
        );
    }
    Ok(())
}

/// A grid point inside a threshold range (half a grid step of tolerance, so an end given as a
/// level keeps its grid point despite rounding).
fn in_range(r: &ThresholdRange, theta: f64) -> bool {
    let tolerance = 0.5 * THETA_STEP;
    r.lowest.ln() - tolerance <= theta && theta <= r.highest.ln() + tolerance
}

fn normalise(p: &mut [f64]) {
    let s: f64 = p.iter().sum();
    p.iter_mut().for_each(|x| *x /= s);
}

/// Expected posterior entropy after one answer at a level with p(correct) `like` per
/// parameter: sum over answers r of P(r) H(posterior | r) = sum_r [P_r ln P_r - sum_m a_rm ln
/// a_rm], with a_rm the unnormalised posterior.
fn expected_entropy(prior: &[f64], like: &[f64]) -> f64 {
    let (mut p1, mut p0, mut s1, mut s0) = (0.0, 0.0, 0.0, 0.0);
    for (&q, &l) in prior.iter().zip(like) {
        let a1 = q * l;
        let a0 = q - a1;
        p1 += a1;
        p0 += a0;
        s1 += xlnx(a1);
        s0 += xlnx(a0);
    }
    xlnx(p1) + xlnx(p0) - s1 - s0
}

/// [`expected_entropy`] of the marginal over runs of `group` consecutive parameters (with
/// [`SLOPES`], the threshold's): a_r summed over each run before its entropy is taken.
fn expected_marginal_entropy(prior: &[f64], like: &[f64], group: usize) -> f64 {
    let (mut p1, mut p0, mut s1, mut s0) = (0.0, 0.0, 0.0, 0.0);
    for (q, l) in prior.chunks(group).zip(like.chunks(group)) {
        let a1: f64 = q.iter().zip(l).map(|(q, l)| q * l).sum();
        let a0 = q.iter().sum::<f64>() - a1;
        p1 += a1;
        p0 += a0;
        s1 += xlnx(a1);
        s0 += xlnx(a0);
    }
    xlnx(p1) + xlnx(p0) - s1 - s0
}

fn xlnx(x: f64) -> f64 {
    if x > 0.0 { x * x.ln() } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;
    use renderer::hash::{hash, unit_f64};

    fn spec() -> QuestPlusSpec {
        QuestPlusSpec::default()
    }

    fn entropy(p: &[f64]) -> f64 {
        -p.iter().map(|&x| xlnx(x)).sum::<f64>()
    }

    #[test]
    fn the_posterior_is_the_prior_times_the_likelihood() {
        let levels = [1, 8, 27, 64];
        let mut q = QuestPlus::new(&levels, &spec());
        let prior = q.posterior.clone();
        q.update(2, false);
        let mut want: Vec<f64> = prior
            .iter()
            .zip(&q.likelihood[2])
            .map(|(p, l)| p * (1.0 - l))
            .collect();
        normalise(&mut want);
        for (a, b) in q.posterior.iter().zip(&want) {
            assert!((a - b).abs() < 1e-15);
        }
        // The prior: flat in ln threshold, the slope's log-normal weights.
        let m = QuestPlus::new(&levels, &spec()).theta_marginal();
        assert!(m.iter().all(|&x| (x - m[0]).abs() < 1e-15));
        assert_eq!(prior.len(), m.len() * SLOPES);
    }

    #[test]
    fn expected_entropy_is_zero_when_certain_and_the_prior_entropy_when_uninformative() {
        let prior = [0.1, 0.2, 0.3, 0.4];
        let h = expected_entropy(&prior, &[0.7; 4]);
        assert!((h - entropy(&prior)).abs() < 1e-12, "{h}");
        assert!(expected_entropy(&[0.0, 1.0, 0.0, 0.0], &[0.2, 0.6, 0.9, 0.5]).abs() < 1e-15);
        // Two equally likely parameters told apart perfectly: nothing is left.
        assert!(expected_entropy(&[0.5, 0.5], &[1.0, 0.0]).abs() < 1e-15);
        // A level that separates them only partly leaves some.
        assert!(expected_entropy(&[0.5, 0.5], &[0.9, 0.6]) > 0.0);
    }

    /// The threshold's marginal: a nuisance the answer does not depend on drops out (the
    /// marginal's own expected entropy), and telling only nuisance values apart teaches nothing.
    #[test]
    fn marginal_expected_entropy_ignores_the_nuisance() {
        // Two thresholds (0.4, 0.6) x two slopes (0.25, 0.75), independent a priori; p(correct)
        // depends on the threshold only.
        let joint = [0.1, 0.3, 0.15, 0.45];
        let like = [0.9, 0.9, 0.3, 0.3];
        let marginal = expected_marginal_entropy(&joint, &like, 2);
        let direct = expected_entropy(&[0.4, 0.6], &[0.9, 0.3]);
        assert_eq!(
            expected_marginal_entropy(&joint, &like, 1),
            expected_entropy(&joint, &like)
        );
        assert!((marginal - direct).abs() < 1e-15, "{marginal} {direct}");
        // p(correct) depends on the slope only: the threshold's entropy stays the prior's.
        let h = expected_marginal_entropy(&joint, &[1.0, 0.0, 1.0, 0.0], 2);
        assert!((h - entropy(&[0.4, 0.6])).abs() < 1e-12, "{h}");
        // The joint goal values that level: it settles the slope.
        let joint_h = expected_entropy(&joint, &[1.0, 0.0, 1.0, 0.0]);
        assert!(joint_h < entropy(&joint) - 0.5, "{joint_h}");
    }

    /// A simulated observer with the model's own function: the posterior mean lands within
    /// three posterior standard deviations of the truth (threshold and slope), and the trials
    /// gather near the threshold.
    #[test]
    fn recovers_a_simulated_observers_threshold_and_slope() {
        let levels: Vec<u32> = (0..16)
            .map(|i| (512f64.powf(i as f64 / 15.0)).round() as u32)
            .collect::<std::collections::BTreeSet<_>>()
            .into_iter()
            .collect();
        let (t, slope, lapse) = (40f64, 2.0, 0.02);
        for seed in 0..2 {
            let mut q = QuestPlus::new(&levels, &spec());
            let mut near = 0;
            for i in 0..400 {
                let level = q.level();
                let x = (levels[level] as f64).ln();
                near += ((x - t.ln()).abs() < 1.5) as usize;
                let p = p_correct(slope, lapse, t.ln(), x);
                q.update(level, unit_f64(hash(seed, &[i])) < p);
            }
            let (mean, lo, hi) = q.ln_threshold();
            let sd = (hi - lo) / 3.92;
            assert!(
                (mean - t.ln()).abs() < 3.0 * sd,
                "seed {seed}: {mean} +- {sd}"
            );
            let b = q.slope();
            let var: f64 = q
                .posterior
                .chunks(SLOPES)
                .flat_map(|c| c.iter().zip(&q.slopes).map(|(p, s)| p * (s - b).powi(2)))
                .sum();
            assert!(
                (b - slope).abs() < 3.0 * var.sqrt(),
                "seed {seed}: {b} +- {}",
                var.sqrt()
            );
            assert!(near > 300, "seed {seed}: {near} of 400 near the threshold");
        }
    }

    /// Calibration, from theory: with the truth drawn from the prior itself (a grid threshold
    /// uniformly, a grid slope by its prior weight) and answers from the model, the 95%
    /// posterior interval covers the truth with probability >= 0.95 (grid quantiles err on the
    /// wide side) and the posterior mean's error averages 0. 200 tracks of 16 trials: coverage
    /// at least 0.95 - 3 binomial standard errors (0.904), mean error within 3 standard errors.
    #[test]
    fn posterior_intervals_are_calibrated_under_the_prior() {
        let levels = [1, 8, 27, 64, 125, 216, 343, 512];
        let prior = QuestPlus::new(&levels, &spec());
        let n = 200;
        let (mut covered, mut errors) = (0, Vec::new());
        for k in 0..n as u64 {
            let u = unit_f64(hash(99, &[k, 0]));
            let m = prior.cumulative(u);
            let theta = prior.thetas[m / SLOPES];
            let mut q = prior.clone();
            for i in 0..16 {
                let level = q.level();
                let p = q.likelihood[level][m];
                q.update(level, unit_f64(hash(99, &[k, 1 + i])) < p);
            }
            let (mean, lo, hi) = q.ln_threshold();
            covered += (lo <= theta && theta <= hi) as usize;
            errors.push(mean - theta);
        }
        let coverage = covered as f64 / n as f64;
        assert!(
            coverage >= 0.95 - 3.0 * (0.95f64 * 0.05 / n as f64).sqrt(),
            "{coverage}"
        );
        let mean = errors.iter().sum::<f64>() / n as f64;
        let sd = (errors.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt();
        assert!(mean.abs() < 3.0 * sd / (n as f64).sqrt(), "{mean} +- {sd}");
    }

    /// A threshold range is the prior's support: flat inside (ends included), 0 outside, and
    /// no answer moves mass outside it.
    #[test]
    fn a_threshold_range_is_the_priors_support() {
        let levels = [1, 8, 27, 64, 125, 216, 343, 512];
        let spec = QuestPlusSpec {
            threshold: Some(ThresholdRange {
                lowest: 8.0,
                highest: 64.0,
            }),
            ..spec()
        };
        let mut q = QuestPlus::new(&levels, &spec);
        let inside = |t: f64| (8f64.ln() - 0.025..=64f64.ln() + 0.025).contains(&t);
        let m = q.theta_marginal();
        let mass = m.iter().filter(|&&p| p > 0.0).count();
        assert_eq!(mass, q.thetas.iter().filter(|&&t| inside(t)).count());
        for (p, &t) in m.iter().zip(&q.thetas) {
            let want = if inside(t) { 1.0 / mass as f64 } else { 0.0 };
            assert!((p - want).abs() < 1e-15, "{t}: {p}");
        }
        for (i, correct) in [(0, false), (7, true), (3, false)] {
            q.update(i, correct);
        }
        let (mean, lo, hi) = q.ln_threshold();
        assert!(inside(lo) && inside(hi) && inside(mean), "{lo} {mean} {hi}");
    }

    #[test]
    fn the_first_level_is_inside_the_range() {
        // With a flat prior over the range the most informative first level is not an end.
        let q = QuestPlus::new(&[1, 8, 27, 64, 125, 216, 343, 512], &spec());
        assert!((1..7).contains(&q.level()), "{}", q.level());
    }
}
