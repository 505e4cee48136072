//! The natural logarithm in lanes (see the module notes of [`super`]).

use super::vcl::{exponent, fraction_2, is_sign_negative, is_zero_or_subnormal, mul_add};
use super::vcl::{mul_neg_add, polynomial_8, select};
use crate::simd::Lanes;
use wide::f32x8;

/// ln x of eight positive x at once (`wide`'s `f32x8::ln`, op for op: x = m 2^e with m in
/// [sqrt(1/2), sqrt(2)), a degree-8 polynomial in m - 1, e ln 2 added in two parts). Zero
/// gives -infinity, a negative x NaN.
#[inline(always)]
pub fn ln_lanes<L: Lanes>(x1: L) -> L {
    const P: [f32; 9] = [
        3.3333331174E-1,
        -2.4999993993E-1,
        2.0000714765E-1,
        -1.6668057665E-1,
        1.4249322787E-1,
        -1.2420140846E-1,
        1.1676998740E-1,
        -1.1514610310E-1,
        7.0376836292E-2,
    ];
    let (half, one) = (L::splat(0.5), L::ONE);
    let x = fraction_2(x1);
    let e = exponent(x1);
    let mask = x.simd_gt(L::splat(std::f32::consts::SQRT_2) * half);
    let x = select(!mask, x + x, x);
    let fe = select(mask, e + one, e);
    let x = x - one;
    let res = polynomial_8(x, P);
    let x2 = x * x;
    let res = x2 * x * res;
    let res = mul_add(fe, L::splat(-2.12194440e-4), res);
    let res = res + mul_neg_add(x2, half, x);
    let res = mul_add(fe, L::splat(0.693359375), res);
    let overflow = !x1.is_finite();
    let underflow = x1.simd_lt(L::splat(1.17549435E-38));
    if !(overflow | underflow).any() {
        return res;
    }
    // Zero and subnormals -infinity (as `wide`), infinity itself, the rest of x <= 0 NaN.
    let res = select(underflow, L::splat_bits(0x7FC0_0101), res);
    let res = select(is_zero_or_subnormal(x1), -L::splat_bits(0x7F80_0000), res);
    let res = select(overflow, x1, res);
    select(
        !x1.is_finite() & is_sign_negative(x1),
        L::splat_bits(0x7FC0_0101),
        res,
    )
}

/// [`ln_lanes`] of one value: the same bits.
#[inline]
pub fn ln(x: f32) -> f32 {
    ln_lanes(f32x8::splat(x)).as_array()[0]
}

#[cfg(test)]
mod tests {
    use super::super::error::{Worst, ulps};
    use super::*;
    use crate::hash::{hash, unit_f32};

    /// Measures the largest error in ulps of the result over every 61st f32 of [2^-24, 1) (the
    /// Box-Muller warp's range: 1 - u, clamped at 2^-24) and 10^6 random normal floats of the
    /// whole positive range, against f64's `ln` (measured 1.17 and 1.09 ulp).
    #[test]
    fn within_two_ulp_of_f64_over_the_whole_range() {
        let mut warp_range = Worst::default();
        let lo = (2.0f32).powi(-24).to_bits();
        let values: Vec<f32> = (lo..1.0f32.to_bits())
            .step_by(61)
            .map(f32::from_bits)
            .collect();
        measure(&values, &mut warp_range);
        let mut whole = Worst::default();
        let values: Vec<f32> = (0..1_000_000u64)
            .map(|i| {
                let bits = hash(15, &[i]) as u32 & 0x7fff_ffff;
                f32::from_bits(bits.clamp(f32::MIN_POSITIVE.to_bits(), f32::MAX.to_bits()))
            })
            .collect();
        measure(&values, &mut whole);
        eprintln!("ln: warp range {warp_range}; whole range {whole}");
        assert!(warp_range.ulps <= 2.0, "{warp_range}");
        assert!(whole.ulps <= 2.0, "{whole}");
        // Exact where it must be, and the edges.
        assert_eq!(ln(1.0), 0.0);
        assert_eq!(ln(0.0), f32::NEG_INFINITY);
        assert!(ln(-1.0).is_nan());
        let u = unit_f32(hash(16, &[0]));
        assert_eq!(
            ln(u).to_bits(),
            ln_lanes(f32x8::splat(u)).as_array()[3].to_bits()
        );
    }

    fn measure(values: &[f32], worst: &mut Worst) {
        for group in values.chunks(8) {
            let x = f32x8::new(std::array::from_fn(|k| group[k % group.len()]));
            for (k, got) in ln_lanes(x).to_array().into_iter().enumerate() {
                let x = group[k % group.len()];
                worst.add(x, ulps(got, (x as f64).ln()));
            }
        }
    }
}
