//! The spatial warp (filter importance sampling, Ernst 2006; thesis Figures 7 and 16): a
//! shifted (u, v) in [0, 1)² becomes an offset from the pixel centre distributed as the
//! reconstruction filter, so every sample counts equally.

use super::config::SpatialFilter;
use crate::math;
use crate::simd::Lanes;
#[cfg(test)]
use wide::f32x8;

/// The smallest 1 - u the Gaussian warp accepts: u = 1 (never produced by a wrapped shift, but
/// possible from callers) then lands at sqrt(-2 ln 2^-24) ≈ 5.77 σ instead of infinity.
const MIN_ONE_MINUS_U: f32 = 1.0 / (1u32 << 24) as f32;

/// A spatial filter with its parameters, ready for the hot path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpatialWarp {
    /// Uniform over the pixel: (u - 1/2, v - 1/2).
    Box,
    /// Isotropic Gaussian with this standard deviation in pixels.
    Gaussian { sigma: f32 },
}

impl SpatialWarp {
    pub fn new(filter: SpatialFilter, sigma: f64) -> Self {
        match filter {
            SpatialFilter::Box => SpatialWarp::Box,
            SpatialFilter::Gaussian => SpatialWarp::Gaussian {
                sigma: sigma as f32,
            },
        }
    }

    /// The offset (dx, dy) from the pixel centre, in pixels, for (u, v) in [0, 1]².
    #[inline]
    pub fn offset(self, u: f32, v: f32) -> (f32, f32) {
        match self {
            SpatialWarp::Box => (u - 0.5, v - 0.5),
            SpatialWarp::Gaussian { sigma } => box_muller(u, v, sigma),
        }
    }

    /// [`SpatialWarp::offset`] of eight (u, v) at once, lane by lane the same bits.
    #[inline(always)]
    pub fn offset_lanes<L: Lanes>(self, u: L, v: L) -> (L, L) {
        match self {
            SpatialWarp::Box => (u - L::splat(0.5), v - L::splat(0.5)),
            SpatialWarp::Gaussian { sigma } => box_muller_lanes(u, v, sigma),
        }
    }
}

/// Box-Muller (Box and Muller 1958): r = sqrt(-2 ln(1 - u)), θ = 2πv; (r cos θ, r sin θ) · σ
/// are two independent N(0, σ²) values. The thesis's code takes ln u, which is infinite at
/// u = 0, the first Hammersley point; 1 - u has the same uniform distribution and is positive
/// on [0, 1), so u = 0 gives the centre. u = 1 is clamped (see [`MIN_ONE_MINUS_U`]).
///
/// `ln` and `sin_cos` are [`crate::math`]'s, the lanes' polynomials on one value (`ln` within
/// 2 ulp, `sin_cos` within 2^-23 of the exact values, tested there), not libm's: the same bits
/// as [`box_muller_lanes`], and libm's results to rounding (the thesis gives the formula, not
/// the functions).
#[inline]
pub fn box_muller(u: f32, v: f32, sigma: f32) -> (f32, f32) {
    let r = sigma * (-2.0 * math::ln((1.0 - u).max(MIN_ONE_MINUS_U))).sqrt();
    let (s, c) = math::sin_cos(std::f32::consts::TAU * v);
    (r * c, r * s)
}

/// [`box_muller`] in lanes: each lane does its f32 operations in its order (`max` and `sqrt`
/// are exact in lanes as in f32), `ln` and `sin_cos` by [`crate::math`]'s lanes.
#[inline(always)]
pub fn box_muller_lanes<L: Lanes>(u: L, v: L, sigma: f32) -> (L, L) {
    let kept = (L::ONE - u).max(L::splat(MIN_ONE_MINUS_U));
    let r = L::splat(sigma) * (L::splat(-2.0) * math::ln_lanes(kept)).sqrt();
    let (s, c) = math::sin_cos_lanes(L::splat(std::f32::consts::TAU) * v);
    (r * c, r * s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hash;
    use crate::sampling::ks::{ks_critical, ks_statistic};
    use statrs::distribution::{ContinuousCDF, Normal};

    #[test]
    fn finite_at_both_ends() {
        for (u, v) in [
            (0.0, 0.0),
            (0.0, 0.7),
            (1.0, 0.0),
            (1.0, 1.0),
            (0.999_999_94, 0.5),
        ] {
            let (x, y) = box_muller(u, v, 0.5);
            assert!(x.is_finite() && y.is_finite(), "({u}, {v}) -> ({x}, {y})");
            assert!(
                x.hypot(y) <= 0.5 * 5.8,
                "({u}, {v}) -> radius {}",
                x.hypot(y)
            );
        }
        assert_eq!(box_muller(0.0, 0.3, 0.5), (0.0, 0.0));
        assert_eq!(SpatialWarp::Box.offset(0.0, 0.75), (-0.5, 0.25));
    }

    #[test]
    fn lanes_are_the_scalar_warp_to_the_bit() {
        // Random points, both ends and the clamp at u = 1, for both warps.
        let mut points = vec![(0.0, 0.0), (1.0, 1.0), (0.999_999_94, 0.5), (0.5, 0.25)];
        for i in 0..4_000u64 {
            let c = |k: u64| hash::unit_f32(hash::hash(13, &[i, k]));
            points.push((c(0), c(1)));
        }
        for warp in [SpatialWarp::Box, SpatialWarp::Gaussian { sigma: 0.37 }] {
            for group in points.chunks(8) {
                let lane = |f: fn(&(f32, f32)) -> f32| {
                    f32x8::new(std::array::from_fn(|k| f(&group[k % group.len()])))
                };
                let (dx, dy) = warp.offset_lanes(lane(|p| p.0), lane(|p| p.1));
                for k in 0..8 {
                    let (u, v) = group[k % group.len()];
                    let (x, y) = warp.offset(u, v);
                    let got = (dx.as_array()[k].to_bits(), dy.as_array()[k].to_bits());
                    assert_eq!(got, (x.to_bits(), y.to_bits()), "{warp:?} at ({u}, {v})");
                }
            }
        }
    }

    #[test]
    fn warped_uniform_points_are_gaussian() {
        // Kolmogorov-Smirnov of each coordinate against N(0, σ²) at α = 0.001 (critical value
        // 1.949/sqrt(n) for large n); and both coordinates uncorrelated.
        let n = 20_000;
        let sigma = 0.5;
        let normal = Normal::new(0.0, sigma).unwrap();
        let (mut xs, mut ys) = (Vec::new(), Vec::new());
        for i in 0..n {
            let u = hash::unit_f32(hash::hash(8, &[i, 0]));
            let v = hash::unit_f32(hash::hash(8, &[i, 1]));
            let (x, y) = SpatialWarp::new(SpatialFilter::Gaussian, sigma).offset(u, v);
            xs.push(x as f64);
            ys.push(y as f64);
        }
        // Independent N(0, σ²) pairs: the mean product has sd σ²/sqrt(n); allow 5 sd.
        let r: f64 = xs.iter().zip(&ys).map(|(x, y)| x * y).sum::<f64>() / n as f64;
        assert!(r.abs() < 5.0 * sigma * sigma / (n as f64).sqrt(), "{r}");
        let crit = ks_critical(n as usize, 0.001);
        for (name, s) in [("dx", &mut xs), ("dy", &mut ys)] {
            let d = ks_statistic(s, |x| normal.cdf(x));
            assert!(d < crit, "{name}: D = {d} >= {crit}");
        }
    }
}
