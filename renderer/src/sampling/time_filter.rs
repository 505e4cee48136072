//! Temporal filters (thesis Chapter II "Temporal Filtering Kernels", Figures 8, 9 and 16): the
//! shutter-time weighting of motion blur, realised by warping a uniform t in [0, 1] through the
//! filter's inverse CDF, so t stays within the frame's shutter interval and samples count
//! equally.

pub use crate::condition::TimeFilter;
use crate::simd::Lanes;
#[cfg(test)]
use wide::f32x8;
use wide::f64x4;

/// The density and warp of each filter (its names are in [`crate::condition`]).
impl TimeFilter {
    /// The filter's probability density at t in [0, 1] (0 outside).
    pub fn pdf(self, t: f64) -> f64 {
        if !(0.0..=1.0).contains(&t) {
            return 0.0;
        }
        match self {
            TimeFilter::Box => 1.0,
            TimeFilter::TruncatedBox => {
                if (0.25..=0.75).contains(&t) {
                    2.0
                } else {
                    0.0
                }
            }
            TimeFilter::Triangle => 4.0 * t.min(1.0 - t),
        }
    }

    /// The fraction of the filter's weight before t: the blur profile a moving edge should show.
    pub fn cdf(self, t: f64) -> f64 {
        let t = t.clamp(0.0, 1.0);
        match self {
            TimeFilter::Box => t,
            TimeFilter::TruncatedBox => ((t - 0.25) / 0.5).clamp(0.0, 1.0),
            TimeFilter::Triangle if t <= 0.5 => 2.0 * t * t,
            TimeFilter::Triangle => 1.0 - 2.0 * (1.0 - t) * (1.0 - t),
        }
    }

    /// The inverse CDF in f64: u in [0, 1] to t in [0, 1] (thesis Figure 16's formulas).
    pub fn inverse_cdf(self, u: f64) -> f64 {
        match self {
            TimeFilter::Box => u,
            TimeFilter::TruncatedBox => 0.5 * u + 0.25,
            TimeFilter::Triangle if u <= 0.5 => 0.5 * (2.0 * u).sqrt(),
            TimeFilter::Triangle => 1.0 - 0.5 * (2.0 - 2.0 * u).sqrt(),
        }
    }

    /// The hot-path warp: [`TimeFilter::inverse_cdf`] rounded to f32 (0, 1/4, 1/2, 3/4 and 1
    /// are exact in both, so the warp is exact at u = 0, 1/2 and 1).
    #[inline]
    pub fn warp(self, u: f32) -> f32 {
        self.inverse_cdf(u as f64) as f32
    }

    /// [`TimeFilter::warp`] of eight u at once, lane by lane the same bits.
    #[inline(always)]
    pub fn warp_lanes<L: Lanes>(self, u: L) -> L {
        match self {
            TimeFilter::Box => u,
            TimeFilter::Triangle => L::new(triangle_lanes(u.to_array())),
            TimeFilter::TruncatedBox => L::new(u.to_array().map(|u| self.warp(u))),
        }
    }
}

/// The triangle's warp in f64 lanes, four at a time: both halves of [`TimeFilter::inverse_cdf`]
/// from one square root, `0.5 sqrt(2 u)` below 1/2, `1 - 0.5 sqrt(2 - 2 u)` above, each
/// operation as the scalar warp does it (`2 u` and `2 - 2 u` are exact in f64), then rounded
/// to f32. Per lane, a branch on a random u and a scalar square root each cost about as
/// much as the rest of a camera sample's set-up (perf, the plane's frame 93).
#[inline(always)]
fn triangle_lanes(u: [f32; 8]) -> [f32; 8] {
    let (half, one, two) = (f64x4::splat(0.5), f64x4::ONE, f64x4::splat(2.0));
    let mut t = [0.0f32; 8];
    for (quarter, out) in u.chunks_exact(4).zip(t.chunks_exact_mut(4)) {
        let u = f64x4::new(std::array::from_fn(|k| quarter[k] as f64));
        let low = u.simd_le(half);
        let root = (low.bitselect(two * u, two - two * u)).sqrt();
        let t = low.bitselect(half * root, one - half * root);
        for (out, t) in out.iter_mut().zip(t.to_array()) {
            *out = t as f32;
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hash;
    use crate::sampling::ks::{ks_critical, ks_statistic};

    #[test]
    fn exact_at_the_ends_and_the_middle() {
        let expect = [
            (TimeFilter::Box, [0.0, 0.5, 1.0]),
            (TimeFilter::TruncatedBox, [0.25, 0.5, 0.75]),
            (TimeFilter::Triangle, [0.0, 0.5, 1.0]),
        ];
        for (f, want) in expect {
            for (u, w) in [0.0f32, 0.5, 1.0].into_iter().zip(want) {
                assert_eq!(f.warp(u), w as f32, "{} at {u}", f.name());
                assert_eq!(f.inverse_cdf(u as f64), w, "{} at {u}", f.name());
            }
        }
    }

    #[test]
    fn lanes_are_the_scalar_warp_to_the_bit() {
        let mut u: Vec<f32> = vec![0.0, 0.25, 0.5, 0.75, 1.0, 0.5 - f32::EPSILON / 4.0];
        u.extend((0..4_000u64).map(|i| hash::unit_f32(hash::hash(14, &[i]))));
        for f in TimeFilter::ALL {
            for group in u.chunks(8) {
                let lanes = f32x8::new(std::array::from_fn(|k| group[k % group.len()]));
                for (k, got) in f.warp_lanes(lanes).to_array().into_iter().enumerate() {
                    let want = f.warp(group[k % group.len()]);
                    assert_eq!(got.to_bits(), want.to_bits(), "{}", f.name());
                }
            }
        }
    }

    #[test]
    fn the_warp_inverts_the_cdf_and_the_cdf_integrates_the_pdf() {
        for f in TimeFilter::ALL {
            for k in 0..=1000 {
                let u = k as f64 / 1000.0;
                let t = f.inverse_cdf(u);
                assert!((0.0..=1.0).contains(&t));
                assert!((f.cdf(t) - u).abs() < 1e-12, "{}: cdf(warp({u}))", f.name());
                assert!((f.warp(u as f32) as f64 - t).abs() < 1e-6, "{}", f.name());
            }
            // Midpoint rule on 10^4 cells: error of a piecewise-linear pdf's integral is at
            // most its jump x cell width = 2e-4.
            let m = 10_000;
            let mut acc = 0.0;
            for k in 0..m {
                acc += f.pdf((k as f64 + 0.5) / m as f64) / m as f64;
                if k % 1000 == 999 {
                    let t = (k + 1) as f64 / m as f64;
                    assert!((acc - f.cdf(t)).abs() < 2.5e-4, "{} at {t}", f.name());
                }
            }
        }
    }

    #[test]
    fn warped_uniform_samples_follow_each_filter() {
        // KS at α = 0.001 against the filter's CDF, 20k uniform draws each.
        let n = 20_000;
        for f in TimeFilter::ALL {
            let mut t: Vec<f64> = (0..n)
                .map(|i| f.warp(hash::unit_f32(hash::hash(3, &[i]))) as f64)
                .collect();
            let d = ks_statistic(&mut t, |x| f.cdf(x));
            assert!(d < ks_critical(n as usize, 0.001), "{}: D = {d}", f.name());
            // Against the box's CDF instead, D must reach the true distance sup|F - t| less
            // the critical value (triangle: 1/8 at t = 1/4; truncated box: 1/4): the test
            // has the power to tell the filters apart.
            let gap = (0..=1000)
                .map(|k| (f.cdf(k as f64 / 1000.0) - k as f64 / 1000.0).abs())
                .fold(0.0, f64::max);
            let d_box = ks_statistic(&mut t, |x| x);
            assert!(
                d_box >= gap - ks_critical(n as usize, 0.001),
                "{}: {d_box} vs {gap}",
                f.name()
            );
        }
    }
}
