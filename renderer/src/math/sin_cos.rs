//! Sine and cosine in lanes (see the module notes of [`super`]).

use wide::f32x8;

/// (sin x, cos x) of eight x at once (`wide`'s `f32x8::sin_cos`: x reduced by the nearest
/// multiple of pi/2 in three parts (Cody-Waite), degree-7 and -8 polynomials on
/// [-pi/4, pi/4], swapped and signed by the quadrant). Infinity and NaN give NaN.
#[inline]
pub fn sin_cos_lanes(x: f32x8) -> (f32x8, f32x8) {
    x.sin_cos()
}

/// [`sin_cos_lanes`] of one value: the same bits.
#[inline]
pub fn sin_cos(x: f32) -> (f32, f32) {
    let (s, c) = sin_cos_lanes(f32x8::splat(x));
    (s.as_array()[0], c.as_array()[0])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The largest absolute error over 2^22 evenly spaced f32 of [0, 2 pi] (what the
    /// Box-Muller warp gives it: 2 pi v for v in [0, 1)) and their negatives, against f64's
    /// `sin_cos` of the same f32, in units of 2^-24 (an ulp of values in [1/2, 1)). libm's
    /// f32 `sin_cos` on the same arguments is measured beside it for the record (ours 1.55,
    /// libm 0.55 units; bound 2 units, about 1.2e-7).
    #[test]
    fn within_two_units_of_2_to_minus_24_on_the_warps_range() {
        let n = 1u32 << 22;
        let unit = 2f64.powi(-24);
        let (mut ours, mut libm, mut at) = (0.0f64, 0.0f64, 0.0f32);
        let args: Vec<f32> = (0..=n)
            .map(|i| (std::f64::consts::TAU * i as f64 / n as f64) as f32)
            .flat_map(|x| [x, -x])
            .collect();
        for group in args.chunks(8) {
            let x = f32x8::new(std::array::from_fn(|k| group[k % group.len()]));
            let (s, c) = sin_cos_lanes(x);
            for k in 0..8 {
                let x = group[k % group.len()];
                let (ws, wc) = (x as f64).sin_cos();
                let err = (s.as_array()[k] as f64 - ws)
                    .abs()
                    .max((c.as_array()[k] as f64 - wc).abs());
                if err > ours {
                    (ours, at) = (err, x);
                }
                let (ls, lc) = x.sin_cos();
                libm = libm.max((ls as f64 - ws).abs().max((lc as f64 - wc).abs()));
            }
        }
        eprintln!(
            "sin_cos: {:.3} x 2^-24 at {at:e}; libm {:.3} x 2^-24 ({} arguments)",
            ours / unit,
            libm / unit,
            args.len()
        );
        assert!(ours <= 2.0 * unit, "{} x 2^-24 at {at:e}", ours / unit);
        // The quadrant's signs and swaps at the axes, exact.
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        let (s, c) = sin_cos(std::f32::consts::FRAC_PI_2);
        assert!((s - 1.0).abs() <= f32::EPSILON && c.abs() < 1e-7, "{s} {c}");
        assert!(sin_cos(f32::INFINITY).0.is_nan() && sin_cos(f32::NAN).1.is_nan());
    }
}
