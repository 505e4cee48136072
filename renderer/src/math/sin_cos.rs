//! Sine and cosine in lanes (see the module notes of [`super`]).

use crate::simd::Lanes;
use wide::f32x8;

/// (sin x, cos x) of eight x at once (`wide`'s `f32x8::sin_cos`: x reduced by the nearest
/// multiple of pi/2 in three parts (Cody-Waite), degree-7 and -8 polynomials on
/// [-pi/4, pi/4], swapped and signed by the quadrant). Infinity and NaN give NaN.
#[inline(always)]
pub fn sin_cos_lanes<L: Lanes>(x: L) -> (L, L) {
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
        let unit = 2f64.powi(-24);
        let args = symmetric(std::f64::consts::TAU, 1 << 22);
        let (ours, at) = worst(&args);
        let libm = args.iter().fold(0.0f64, |m, &x| {
            let ((ls, lc), (ws, wc)) = (x.sin_cos(), (x as f64).sin_cos());
            m.max((ls as f64 - ws).abs().max((lc as f64 - wc).abs()))
        });
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

    /// The spins' angles (`accel::chain::Spin::at_lanes`: rate times time): the thesis's
    /// spheres turn at most 190 degrees per second over the job's 25 s, under 2^6 rad, and the
    /// accel tests go to 350 rad/s at t = -12.5 s, under 2^13. Cody-Waite's reduction by k pi/2
    /// in three f32 parts is exact in its first part up to |k| = 2^16 and rounds k times the
    /// second (12 bits) once |k| passes 2^12, by up to 2^-24 k 2.4e-4: a bound of 2 units of
    /// 2^-24 for |x| < 2^6, 2 + 2^13 / (pi / 2) 2.4e-4 = 3.3 below 2^13 (measured: 1.54 and
    /// 1.55 units).
    #[test]
    fn within_the_reductions_rounding_on_the_spins_angles() {
        for (range, bound) in [(64.0f64, 2.0), (8192.0, 3.3)] {
            let unit = 2f64.powi(-24);
            let (worst, at) = worst(&symmetric(range, 1 << 21));
            eprintln!(
                "sin_cos below {range}: {:.3} x 2^-24 at {at:e}",
                worst / unit
            );
            assert!(worst <= bound * unit, "{} x 2^-24 at {at:e}", worst / unit);
        }
    }

    /// n + 1 evenly spaced f32 of [0, range] and their negatives.
    fn symmetric(range: f64, n: u32) -> Vec<f32> {
        (0..=n)
            .map(|i| (range * i as f64 / n as f64) as f32)
            .flat_map(|x| [x, -x])
            .collect()
    }

    /// The largest absolute error of sine or cosine over `args` against f64's `sin_cos` of the
    /// same f32, and where.
    fn worst(args: &[f32]) -> (f64, f32) {
        let (mut worst, mut at) = (0.0f64, 0.0f32);
        for group in args.chunks(8) {
            let x = f32x8::new(std::array::from_fn(|k| group[k % group.len()]));
            let (s, c) = sin_cos_lanes(x);
            for k in 0..8 {
                let x = group[k % group.len()];
                let (ws, wc) = (x as f64).sin_cos();
                let err = (s.as_array()[k] as f64 - ws)
                    .abs()
                    .max((c.as_array()[k] as f64 - wc).abs());
                if err > worst {
                    (worst, at) = (err, x);
                }
            }
        }
        (worst, at)
    }
}
