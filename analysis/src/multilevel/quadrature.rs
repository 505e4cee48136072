//! Adaptive Gauss-Hermite quadrature of one subject's random effect.
//!
//! The marginal likelihood of a subject is the integral over the subject's offset u of
//! exp(h(u)), h = log-likelihood of the subject's counts given u + log N(u; 0, sigma^2). The
//! rule is centred on h's mode m and scaled by s = (-h''(m))^-1/2 (Liu and Pierce 1994, the
//! method of lme4's `nAGQ`): u = m + sqrt(2) s t, so the integrand is close to the Gauss weight
//! e^-t^2 and a few nodes are exact for a nearly normal posterior. With one node it is the
//! Laplace approximation.

/// Nodes and weights of the n-point Gauss-Hermite rule (weight e^-t^2), nodes ascending.
pub fn gauss_hermite(n: usize) -> (Vec<f64>, Vec<f64>) {
    // Newton's method on the orthonormal Hermite polynomial from the classical initial guesses
    // (Numerical Recipes' `gauher`); the weights from the derivative at each root.
    let pim4 = std::f64::consts::PI.powf(-0.25);
    let mut t = vec![0.0; n];
    let mut w = vec![0.0; n];
    let m = n.div_ceil(2);
    let nf = n as f64;
    let mut z = 0.0;
    for i in 0..m {
        z = match i {
            0 => (2.0 * nf + 1.0).sqrt() - 1.85575 * (2.0 * nf + 1.0).powf(-1.0 / 6.0),
            1 => z - 1.14 * nf.powf(0.426) / z,
            2 => 1.86 * z - 0.86 * t[0],
            3 => 1.91 * z - 0.91 * t[1],
            _ => 2.0 * z - t[i - 2],
        };
        let mut pp = 0.0;
        for _ in 0..100 {
            let (p, dp) = hermite(n, z, pim4);
            pp = dp;
            let step = p / dp;
            z -= step;
            if step.abs() <= 1e-15 * z.abs().max(1.0) {
                break;
            }
        }
        t[i] = z;
        t[n - 1 - i] = -z;
        w[i] = 2.0 / (pp * pp);
        w[n - 1 - i] = w[i];
    }
    t.reverse();
    w.reverse();
    (t, w)
}

/// The orthonormal Hermite polynomial of degree n at z and its derivative.
fn hermite(n: usize, z: f64, pim4: f64) -> (f64, f64) {
    let mut p1 = pim4;
    let mut p2 = 0.0;
    for j in 1..=n {
        let p3 = p2;
        p2 = p1;
        let jf = j as f64;
        p1 = z * (2.0 / jf).sqrt() * p2 - ((jf - 1.0) / jf).sqrt() * p3;
    }
    (p1, (2.0 * n as f64).sqrt() * p2)
}

/// A rule ready to integrate: nodes, ln weights + t^2 (the Gauss weight undone).
#[derive(Clone, Debug)]
pub struct Rule {
    nodes: Vec<f64>,
    ln_w: Vec<f64>,
}

/// One subject's integral: ln of the marginal likelihood, and the posterior mean and standard
/// deviation of the offset (the shrunken estimate).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Integral {
    pub ln_value: f64,
    pub mean: f64,
    pub sd: f64,
}

impl Rule {
    pub fn new(n: usize) -> Self {
        let (nodes, w) = gauss_hermite(n);
        let ln_w = nodes.iter().zip(&w).map(|(t, w)| w.ln() + t * t).collect();
        Rule { nodes, ln_w }
    }

    /// The integral over u of exp(h(u)) with h = `ln_lik`(u) + ln N(u; 0, sigma^2).
    pub fn integrate(&self, sigma: f64, ln_lik: impl Fn(f64) -> f64) -> Integral {
        let ln_norm = -(sigma * (2.0 * std::f64::consts::PI).sqrt()).ln();
        let h = |u: f64| ln_lik(u) - 0.5 * (u / sigma).powi(2) + ln_norm;
        let (m, s) = newton(&h, sigma).unwrap_or_else(|| {
            let m = mode(&h, sigma);
            (m, scale(&h, m, sigma))
        });
        let first = self.at(&h, m, s);
        // Again at the posterior's mean and SD when they disagree with the curvature: a
        // plateau-shaped likelihood (a step in u, flat on both sides) makes the posterior
        // wider than the curvature at its mode says, and the moments of the first pass place
        // the nodes where its mass is.
        let moments_differ = (first.sd / s - 1.0).abs() > 0.02 || (first.mean - m).abs() > 0.02 * s;
        if moments_differ && first.sd > 0.0 && first.sd.is_finite() && first.mean.is_finite() {
            self.at(&h, first.mean, first.sd.clamp(1e-3 * sigma, 2.0 * sigma))
        } else {
            first
        }
    }

    /// The rule centred on `m` with scale `s`.
    fn at(&self, h: &impl Fn(f64) -> f64, m: f64, s: f64) -> Integral {
        let r2s = std::f64::consts::SQRT_2 * s;
        let terms: Vec<(f64, f64)> = self
            .nodes
            .iter()
            .zip(&self.ln_w)
            .map(|(t, lw)| {
                let u = m + r2s * t;
                (u, lw + h(u))
            })
            .collect();
        let top = terms.iter().map(|x| x.1).fold(f64::NEG_INFINITY, f64::max);
        let (mut sum, mut su, mut suu) = (0.0, 0.0, 0.0);
        for (u, l) in terms {
            let e = (l - top).exp();
            sum += e;
            su += e * u;
            suu += e * u * u;
        }
        let mean = su / sum;
        Integral {
            ln_value: top + sum.ln() + r2s.ln(),
            mean,
            sd: (suu / sum - mean * mean).max(0.0).sqrt(),
        }
    }
}

/// The mode of h and (-h'')^-1/2 there by Newton's method from u = 0 with central differences
/// (steps at most sigma, halved until h rises); `None` where h is not curved down on the way
/// (then [`mode`] searches a grid).
fn newton(h: &impl Fn(f64) -> f64, sigma: f64) -> Option<(f64, f64)> {
    let e = 1e-3 * sigma;
    let mut u = 0.0;
    let mut h0 = h(u);
    for _ in 0..40 {
        let (hp, hm) = (h(u + e), h(u - e));
        let d1 = (hp - hm) / (2.0 * e);
        let d2 = (hp - 2.0 * h0 + hm) / (e * e);
        if !(d2 < 0.0 && d1.is_finite()) {
            return None;
        }
        let s = (-d2).sqrt().recip();
        let mut step = (-d1 / d2).clamp(-sigma, sigma);
        if step.abs() < 1e-7 * sigma {
            return Some((u, s.clamp(1e-3 * sigma, 2.0 * sigma)));
        }
        let mut next = h(u + step);
        let mut halvings = 0;
        while next.is_nan() || next < h0 {
            halvings += 1;
            if halvings > 30 {
                return None;
            }
            step *= 0.5;
            next = h(u + step);
        }
        u += step;
        h0 = next;
    }
    None
}

/// The mode of h: the best of a grid over +-6 sigma, refined by golden-section search between
/// its neighbours. A grid first, because with a guess rate above 0 the subject's likelihood is
/// not log-concave in u (flat plateaus on both sides of a step).
fn mode(h: &impl Fn(f64) -> f64, sigma: f64) -> f64 {
    const N: i32 = 24;
    let step = 12.0 * sigma / N as f64;
    let (mut best, mut best_v) = (0.0, h(0.0));
    for i in -N / 2..=N / 2 {
        let u = i as f64 * step;
        let v = h(u);
        if v > best_v {
            (best, best_v) = (u, v);
        }
    }
    let (mut a, mut b) = (best - step, best + step);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut hc, mut hd) = (h(c), h(d));
    while b - a > 1e-9 * sigma {
        if hc > hd {
            (b, d, hd) = (d, c, hc);
            c = b - g * (b - a);
            hc = h(c);
        } else {
            (a, c, hc) = (c, d, hd);
            d = a + g * (b - a);
            hd = h(d);
        }
    }
    0.5 * (a + b)
}

/// (-h''(m))^-1/2 by a central difference, kept within [sigma / 1000, 2 sigma]; sigma itself
/// when h is not curved down at m (numerically flat).
fn scale(h: &impl Fn(f64) -> f64, m: f64, sigma: f64) -> f64 {
    let e = 1e-3 * sigma;
    let d2 = (h(m + e) - 2.0 * h(m) + h(m - e)) / (e * e);
    if d2.is_finite() && d2 < 0.0 {
        (-d2).sqrt().recip().clamp(1e-3 * sigma, 2.0 * sigma)
    } else {
        sigma
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_hermite_integrates_polynomials_exactly() {
        // An n-point rule is exact to degree 2n - 1: int t^2k e^-t^2 = Gamma(k + 1/2).
        let sqrt_pi = std::f64::consts::PI.sqrt();
        for n in [1, 2, 5, 15, 20] {
            let (t, w) = gauss_hermite(n);
            for k in 0..n {
                let exact = sqrt_pi * (1..=k).map(|j| (2 * j - 1) as f64 / 2.0).product::<f64>();
                let got: f64 = t
                    .iter()
                    .zip(&w)
                    .map(|(t, w)| w * t.powi(2 * k as i32))
                    .sum();
                assert!(
                    (got - exact).abs() < 1e-12 * exact,
                    "n {n} k {k}: {got} {exact}"
                );
            }
            assert!(t.windows(2).all(|p| p[0] < p[1]), "{t:?}");
        }
        // Published: the 2-point rule's nodes are +-1/sqrt(2), weights sqrt(pi)/2.
        let (t, w) = gauss_hermite(2);
        assert!((t[1] - 0.5f64.sqrt()).abs() < 1e-15 && (w[0] - sqrt_pi / 2.0).abs() < 1e-15);
    }

    #[test]
    fn a_normal_likelihood_is_integrated_exactly() {
        // ln L(u) = -(u - 1)^2 / (2 * 0.25): the posterior is normal, the integral closed form:
        // N(1; 0, sigma^2 + 0.25) * sqrt(2 pi 0.25), posterior mean sigma^2 / (sigma^2 + 0.25).
        let rule = Rule::new(3);
        let sigma: f64 = 0.6;
        let v = sigma * sigma + 0.25;
        let got = rule.integrate(sigma, |u| -(u - 1.0).powi(2) / 0.5);
        let want = -0.5 / v - 0.5 * (2.0 * std::f64::consts::PI * v).ln()
            + 0.5 * (2.0 * std::f64::consts::PI * 0.25).ln();
        assert!((got.ln_value - want).abs() < 1e-9, "{got:?} {want}");
        assert!((got.mean - sigma * sigma / v).abs() < 1e-9);
        assert!((got.sd - (sigma * sigma * 0.25 / v).sqrt()).abs() < 1e-6);
    }

    #[test]
    fn a_binomial_step_likelihood_matches_brute_force_integration() {
        // A subject at chance above a step and perfect below: far from normal in u (the
        // likelihood has a plateau at 0.5^16 for u -> -inf, so a wide prior leaves a heavy
        // left tail). 15 nodes against the trapezoid rule on 200 001 points over +-10 sigma:
        // 1e-7 at sigma 0.1 and 0.5 (measured < 1e-12 and 3.7e-8), while at sigma 1.5 (a
        // factor of 4.5 between subjects one SD apart) the rule converges slowly (measured ln
        // errors 2.3e-3, 4.4e-4, 1.5e-4, 3.7e-5, 3.5e-6 with 7, 11, 15, 21, 31 nodes): bounded
        // here at 2e-4, a thousandth of what a likelihood-ratio test resolves.
        let ln_lik = |u: f64| {
            [(0.0f64, 4.0f64), (1.0, 4.0), (2.0, 2.0), (3.0, 2.0)]
                .iter()
                .map(|&(x, k)| {
                    let p = 0.5 + 0.5 / (1.0 + (-(3.0 * (1.5 + u - x))).exp());
                    // 0 ln 0 = 0 where p rounds to 1.
                    let miss = if k < 4.0 {
                        (4.0 - k) * (1.0 - p).ln()
                    } else {
                        0.0
                    };
                    k * p.ln() + miss
                })
                .sum::<f64>()
        };
        for sigma in [0.1, 0.5, 1.5] {
            let got = Rule::new(15).integrate(sigma, ln_lik);
            let (n, lim) = (200_000, 10.0 * sigma);
            let du = 2.0 * lim / n as f64;
            let dens = |u: f64| {
                (ln_lik(u) - 0.5 * (u / sigma).powi(2)).exp()
                    / (sigma * (2.0 * std::f64::consts::PI).sqrt())
            };
            let (mut sum, mut su) = (0.0, 0.0);
            for i in 0..=n {
                let u = -lim + i as f64 * du;
                let wt = if i == 0 || i == n { 0.5 } else { 1.0 };
                sum += wt * dens(u) * du;
                su += wt * dens(u) * u * du;
            }
            let tol = if sigma < 1.0 { 1e-7 } else { 2e-4 };
            assert!(
                (got.ln_value - sum.ln()).abs() < tol,
                "{sigma}: {got:?} {}",
                sum.ln()
            );
            assert!(
                (got.mean - su / sum).abs() < 1e-3 * sigma,
                "{sigma}: {got:?}"
            );
        }
    }
}
