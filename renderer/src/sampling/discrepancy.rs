//! L2-star discrepancy: the root mean square, over every anchored box [0, x), of the difference
//! between the fraction of points inside the box and its volume (thesis Chapter II's
//! "discrepancy", in its L2 form, which has a closed form).

use super::pointset::Points;

/// T* by Warnock's formula (1972), for N points x_i in [0, 1)^d:
/// T*² = 3^-d - (2^(1-d)/N) Σ_i Π_k (1 - x_ik²) + (1/N²) Σ_i Σ_j Π_k (1 - max(x_ik, x_jk)).
/// O(N² d): 4 ms for 512 points.
pub fn l2_star(p: &Points) -> f64 {
    let (n, d) = (p.len() as f64, p.dims() as i32);
    let single: f64 = p
        .iter()
        .map(|x| x.iter().map(|c| 1.0 - c * c).product::<f64>())
        .sum();
    let pairs: f64 = p
        .iter()
        .map(|x| {
            p.iter()
                .map(|y| {
                    x.iter()
                        .zip(y)
                        .map(|(a, b)| 1.0 - a.max(*b))
                        .product::<f64>()
                })
                .sum::<f64>()
        })
        .sum();
    let t2 = 3f64.powi(-d) - 2f64.powi(1 - d) / n * single + pairs / (n * n);
    t2.max(0.0).sqrt()
}

/// E[T*²] for N independent uniform points in d dimensions: (2^-d - 3^-d) / N. Its square root
/// is the RMS discrepancy of random points, the baseline a better set must beat.
pub fn random_l2_star_squared(n: usize, dims: usize) -> f64 {
    let d = dims as i32;
    (2f64.powi(-d) - 3f64.powi(-d)) / n as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hash;

    #[test]
    fn one_point_on_a_line_matches_the_integral() {
        // T*² = ∫ (1{x < y} - y)² dy = x³/3 + (1 - x)³/3 for a single point x.
        for x in [0.0, 0.25, 0.5, 0.9] {
            let t = l2_star(&Points::from_fn(1, 1, |_, _| x));
            let expect = (x.powi(3) / 3.0 + (1.0 - x).powi(3) / 3.0).sqrt();
            assert!((t - expect).abs() < 1e-12, "x={x}: {t} vs {expect}");
        }
    }

    #[test]
    fn midpoints_on_a_line_have_the_known_minimum() {
        // The N midpoints (i + 1/2)/N minimise the 1D L2-star discrepancy: T*² = 1/(12 N²).
        let n = 40;
        let t = l2_star(&Points::from_fn(n, 1, |i, _| (i as f64 + 0.5) / n as f64));
        assert!((t * t - 1.0 / (12.0 * (n * n) as f64)).abs() < 1e-12);
    }

    #[test]
    fn low_discrepancy_sets_beat_random_points() {
        // √N T* of random points has a distribution that hardly changes with N (E[T*²] =
        // 0.088/N in 3D), while T* of a low-discrepancy set falls like (log N)²/N. The
        // baseline is 50 random sets per N: from N = 125 on, Hammersley, Sobol and Halton
        // must be below the best of them (random's ~2nd percentile, about 0.6 of its RMS).
        // Below that the (log N)² factor dominates: the scrambled sets must still beat
        // random's RMS expectation; Hammersley need not (its points i/N crowd the origin,
        // the corner every anchored box contains: at N = 8 it is 1.3 x random's RMS).
        use crate::sampling::pointset::{Halton, Hammersley, PointSet, Random, Sobol, generate};
        for n in [8usize, 27, 64, 125, 216, 343, 512] {
            let best_random = (0..50)
                .map(|s| l2_star(&generate(&Random, n, 3, 100 + s).unwrap()))
                .fold(f64::INFINITY, f64::min);
            let rms = random_l2_star_squared(n, 3).sqrt();
            let sets: [&dyn PointSet; 3] = [&Hammersley, &Sobol, &Halton];
            for set in sets {
                let t = l2_star(&generate(set, n, 3, 7).unwrap());
                if n >= 125 {
                    assert!(
                        t < best_random,
                        "{} N={n}: {t} vs best random {best_random}",
                        set.name()
                    );
                } else if set.name() != "hammersley" {
                    assert!(t < rms, "{} N={n}: {t} vs random RMS {rms}", set.name());
                }
            }
        }
    }

    #[test]
    fn random_points_average_the_closed_form() {
        // 400 sets of 64 random points in 3D: the mean of T*² estimates E[T*²]; its standard
        // error is the sample sd / 20. Allow 4 standard errors.
        let (n, sets) = (64, 400);
        let t2: Vec<f64> = (0..sets)
            .map(|s| {
                let p = Points::from_fn(n, 3, |i, d| {
                    hash::unit_f64(hash::hash(s, &[i as u64, d as u64]))
                });
                l2_star(&p).powi(2)
            })
            .collect();
        let mean = t2.iter().sum::<f64>() / sets as f64;
        let sd = (t2.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (sets - 1) as f64).sqrt();
        let expect = random_l2_star_squared(n, 3);
        assert!(
            (mean - expect).abs() < 4.0 * sd / (sets as f64).sqrt(),
            "mean {mean} vs {expect} (sd {sd})"
        );
    }
}
