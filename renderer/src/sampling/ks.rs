//! One-sample Kolmogorov-Smirnov test: how the warps (and the renderer's blur profiles) are
//! checked against their target distributions.

/// D = sup_x |F_n(x) - F(x)| of the samples (sorted in place) against the CDF `cdf`.
pub fn ks_statistic(samples: &mut [f64], cdf: impl Fn(f64) -> f64) -> f64 {
    samples.sort_by(f64::total_cmp);
    let n = samples.len() as f64;
    samples
        .iter()
        .enumerate()
        .map(|(i, &x)| {
            let f = cdf(x);
            (f - i as f64 / n).max((i + 1) as f64 / n - f)
        })
        .fold(0.0, f64::max)
}

/// The critical value of D at significance `alpha` for `n` samples, from the asymptotic
/// Kolmogorov distribution: P(sqrt(n) D > c) ≈ 2 exp(-2c²), so c = sqrt(-ln(α/2) / 2)
/// (1.358 at α = 0.05, 1.949 at α = 0.001). Accurate for n above about 100.
pub fn ks_critical(n: usize, alpha: f64) -> f64 {
    (-(alpha / 2.0).ln() / 2.0).sqrt() / (n as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_values() {
        assert!((ks_critical(1, 0.05) - 1.3581).abs() < 1e-3);
        // Midpoints of n strata are off by exactly 1/(2n) from the uniform CDF.
        let mut s: Vec<f64> = (0..10).rev().map(|i| (i as f64 + 0.5) / 10.0).collect();
        assert!((ks_statistic(&mut s, |x| x) - 0.05).abs() < 1e-12);
        // All mass at 0 against a uniform: D = 1.
        assert_eq!(ks_statistic(&mut [0.0, 0.0], |x| x), 1.0);
    }
}
