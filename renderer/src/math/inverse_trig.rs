//! The inverse trigonometric functions in lanes (see the module notes of [`super`]).

use crate::simd::Lanes;
use wide::f32x8;

/// atan2(y, x) of eight (y, x) at once, in [-pi, pi] (`wide`'s `f32x8::atan2`: the pair
/// folded into the first octant, t = min / max, (t - 1) / (t + 1) above tan(pi/8), a degree-9
/// odd polynomial, unfolded). Signed zeros as libm: atan2(+-0, +0) = +-0, atan2(+-0, -0) =
/// +-pi. For finite inputs (the environment's directions are).
#[inline(always)]
pub fn atan2_lanes<L: Lanes>(y: L, x: L) -> L {
    y.atan2(x)
}

/// [`atan2_lanes`] of one pair: the same bits.
#[inline]
pub fn atan2(y: f32, x: f32) -> f32 {
    atan2_lanes(f32x8::splat(y), f32x8::splat(x)).as_array()[0]
}

/// acos x of eight x in [-1, 1] at once, in [0, pi] (`wide`'s `f32x8::acos`: for |x| >= 1/2
/// 2 asin(sqrt((1 - |x|) / 2)), else pi/2 - asin x, asin by a degree-9 odd polynomial).
#[inline(always)]
pub fn acos_lanes<L: Lanes>(x: L) -> L {
    x.acos()
}

/// [`acos_lanes`] of one value: the same bits.
#[inline]
pub fn acos(x: f32) -> f32 {
    acos_lanes(f32x8::splat(x)).as_array()[0]
}

#[cfg(test)]
mod tests {
    use super::super::error::{Worst, ulps};
    use super::*;
    use crate::hash::{hash, unit_f32};
    use std::f32::consts::PI;

    /// Every 1021st f32 of [-1, 1] and every f32 within 2^-10 of -1 and 1 (where acos is
    /// steepest) against f64's `acos`, in ulps of the result (measured 1.20 ulp).
    #[test]
    fn acos_within_two_ulp_of_f64_over_its_whole_domain() {
        let one = 1.0f32.to_bits();
        let positive: Vec<f32> = (0..=one)
            .step_by(1021)
            .chain(one - (1 << 14)..=one)
            .map(f32::from_bits)
            .collect();
        let values: Vec<f32> = positive.iter().flat_map(|&x| [x, -x]).collect();
        let mut worst = Worst::default();
        for group in values.chunks(8) {
            let x = f32x8::new(std::array::from_fn(|k| group[k % group.len()]));
            for (k, got) in acos_lanes(x).to_array().into_iter().enumerate() {
                let x = group[k % group.len()];
                worst.add(x, ulps(got, (x as f64).acos()));
            }
        }
        eprintln!("acos: {worst}");
        assert!(worst.ulps <= 2.0, "{worst}");
        assert_eq!(acos(1.0), 0.0);
        assert_eq!(acos(-1.0), PI);
        assert_eq!(acos(0.0), std::f32::consts::FRAC_PI_2);
    }

    /// 4 * 10^6 pairs: directions all around the circle at magnitudes 1e-30 to 1e30, half of
    /// them with one coordinate 10^-3 to 10^-12 of the other (angles near the axes), against
    /// f64's `atan2`, in ulps of the result (measured 3.10 ulp, bound 4); the signed zeros
    /// and axes exactly.
    #[test]
    fn atan2_within_four_ulp_of_f64_all_around() {
        let mut worst = Worst::default();
        let pairs: Vec<(f32, f32)> = (0..4_000_000u64)
            .map(|i| {
                let c = |k: u64| unit_f32(hash(17, &[i, k]));
                let angle = (c(0) as f64 - 0.5) * std::f64::consts::TAU;
                let scale = 10f64.powf(c(1) as f64 * 60.0 - 30.0);
                let (mut y, mut x) = (angle.sin() * scale, angle.cos() * scale);
                if i % 2 == 1 {
                    let squash = 10f64.powf(-3.0 - 9.0 * c(2) as f64);
                    if i % 4 == 1 { y *= squash } else { x *= squash }
                }
                (y as f32, x as f32)
            })
            .collect();
        for group in pairs.chunks(8) {
            let y = f32x8::new(std::array::from_fn(|k| group[k % group.len()].0));
            let x = f32x8::new(std::array::from_fn(|k| group[k % group.len()].1));
            for (k, got) in atan2_lanes(y, x).to_array().into_iter().enumerate() {
                let (y, x) = group[k % group.len()];
                worst.add(y / x, ulps(got, (y as f64).atan2(x as f64)));
            }
        }
        eprintln!("atan2: {worst} (at y / x)");
        assert!(worst.ulps <= 4.0, "{worst}");
        for (y, x, want) in [
            (0.0f32, 0.0f32, 0.0f32),
            (-0.0, 0.0, -0.0),
            (0.0, -0.0, PI),
            (-0.0, -0.0, -PI),
            (1.0, 0.0, std::f32::consts::FRAC_PI_2),
            (-1.0, 0.0, -std::f32::consts::FRAC_PI_2),
            (0.0, -1.0, PI),
            (-0.0, -1.0, -PI),
            (0.0, 1.0, 0.0),
        ] {
            let got = atan2(y, x);
            assert_eq!(got.to_bits(), want.to_bits(), "atan2({y}, {x}) = {got}");
        }
    }
}
