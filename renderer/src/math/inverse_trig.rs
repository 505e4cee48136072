//! The inverse trigonometric functions in lanes (see the module notes of [`super`]).

use super::vcl::select;
use super::vcl::{flip_signs, is_inf, is_sign_negative, mul_add, polynomial_3, polynomial_4};
use crate::simd::Lanes;
use wide::f32x8;

/// atan2(y, x) of eight (y, x) at once, in [-pi, pi] (`wide`'s `f32x8::atan2`, op for op: the
/// pair folded into the first octant, t = min / max, (t - 1) / (t + 1) above tan(pi/8), a
/// degree-9 odd polynomial, unfolded). Signed zeros as libm: atan2(+-0, +0) = +-0, atan2(+-0,
/// -0) = +-pi. For finite inputs (the environment's directions are).
#[inline(always)]
pub fn atan2_lanes<L: Lanes>(y: L, x: L) -> L {
    use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI, SQRT_2};
    const P: [f32; 4] = [
        -3.33329491539E-1,
        1.99777106478E-1,
        -1.38776856032E-1,
        8.05374449538E-2,
    ];
    let one = L::ONE;
    let (x1, y1) = (x.abs(), y.abs());
    let swapxy = y1.simd_gt(x1);
    let mut x2 = select(swapxy, y1, x1);
    let mut y2 = select(swapxy, x1, y1);
    // Both infinite: 1 and 1 (the bits of -1 masked by infinity's), so pi/4.
    let both_infinite = is_inf(x) & is_inf(y);
    if both_infinite.any() {
        x2 = select(both_infinite, x2 & -one, x2);
        y2 = select(both_infinite, y2 & -one, y2);
    }
    // x = y = 0 gives NaN here, replaced below.
    let t = y2 / x2;
    let notsmal = t.simd_ge(L::splat(SQRT_2) - one);
    let a = select(notsmal, t - one, t);
    let b = select(notsmal, t + one, one);
    let s = notsmal & L::splat(FRAC_PI_4);
    let z = a / b;
    let zz = z * z;
    let re = mul_add(polynomial_3(zz, P), zz * z, z) + s;
    let re = select(swapxy, L::splat(FRAC_PI_2) - re, re);
    let re = select((x | y).simd_eq(L::ZERO), L::ZERO, re);
    let re = select(is_sign_negative(x), L::splat(PI) - re, re);
    select(is_sign_negative(y), -re, re)
}

/// [`atan2_lanes`] of one pair: the same bits.
#[inline]
pub fn atan2(y: f32, x: f32) -> f32 {
    atan2_lanes(f32x8::splat(y), f32x8::splat(x)).as_array()[0]
}

/// acos x of eight x in [-1, 1] at once, in [0, pi] (`wide`'s `f32x8::acos`, op for op: for
/// |x| >= 1/2 2 asin(sqrt((1 - |x|) / 2)), else pi/2 - asin x, asin by a degree-9 odd
/// polynomial).
#[inline(always)]
pub fn acos_lanes<L: Lanes>(x: L) -> L {
    use std::f32::consts::{FRAC_PI_2, PI};
    const P: [f32; 5] = [
        1.6666752422E-1,
        7.4953002686E-2,
        4.5470025998E-2,
        2.4181311049E-2,
        4.2163199048E-2,
    ];
    let xa = x.abs();
    let big = xa.simd_ge(L::splat(0.5));
    let x1 = L::splat(0.5) * (L::ONE - xa);
    let x2 = xa * xa;
    let x3 = select(big, x1, x2);
    let xb = x1.sqrt();
    let x4 = select(big, xb, xa);
    let z = mul_add(polynomial_4(x3, P), x3 * x4, x4);
    let z1 = z + z;
    let z3 = select(x.simd_lt(L::ZERO), L::splat(PI) - z1, z1);
    let z4 = L::splat(FRAC_PI_2) - flip_signs(z, x);
    select(big, z3, z4)
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
