//! The natural logarithm in lanes (see the module notes of [`super`]).

use crate::simd::Lanes;
use wide::f32x8;

/// ln x of eight positive x at once (`wide`'s `f32x8::ln`: x = m 2^e with m in
/// [sqrt(1/2), sqrt(2)), a degree-8 polynomial in m - 1, e ln 2 added in two parts). Zero
/// gives -infinity, a negative x NaN.
#[inline(always)]
pub fn ln_lanes<L: Lanes>(x: L) -> L {
    x.ln()
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
