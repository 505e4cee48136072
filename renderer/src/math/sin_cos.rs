//! Sine and cosine in lanes (see the module notes of [`super`]).

use super::vcl::select;
use super::vcl::{flip_signs, mul_neg_add, polynomial_2, round_int, round_ties_even};
use crate::simd::Lanes;
use wide::f32x8;

/// (sin x, cos x) of eight x at once (`wide`'s `f32x8::sin_cos`, op for op: x reduced by the
/// nearest multiple of pi/2 in three parts (Cody-Waite), degree-7 and -8 polynomials on
/// [-pi/4, pi/4], swapped and signed by the quadrant). Infinity and NaN give NaN.
#[inline(always)]
pub fn sin_cos_lanes<L: Lanes>(x: L) -> (L, L) {
    const DP: [f32; 3] = [
        0.78515625 * 2.0,
        2.4187564849853515625E-4 * 2.0,
        3.77489497744594108E-8 * 2.0,
    ];
    const SIN: [f32; 3] = [-1.6666654611E-1, 8.3321608736E-3, -1.9515295891E-4];
    const COS: [f32; 3] = [
        4.166664568298827E-2,
        -1.388731625493765E-3,
        2.443315711809948E-5,
    ];
    let xa = x.abs();
    // The quadrant q, and xa - q pi/2.
    let y = round_ties_even(xa * L::splat(2.0 / std::f32::consts::PI));
    let q = round_int(y);
    let [dp1, dp2, dp3] = [L::splat(DP[0]), L::splat(DP[1]), L::splat(DP[2])];
    let r = mul_neg_add(y, dp3, mul_neg_add(y, dp2, mul_neg_add(y, dp1, xa)));
    let r2 = r * r;
    let s = polynomial_2(r2, SIN) * (r * r2) + r;
    let c = polynomial_2(r2, COS) * (r2 * r2) + mul_neg_add(L::splat(0.5), r2, L::ONE);
    let swap = !(q & L::splat_bits(1)).int_eq(L::ZERO);
    // Beyond 2^25 quadrants the reduction means nothing: 0 and 1, as `wide`.
    let overflow = q.int_gt(L::splat_bits(0x200_0000)) & xa.is_finite();
    let s = select(overflow, L::ZERO, s);
    let c = select(overflow, L::ONE, c);
    let sin = flip_signs(select(swap, c, s), q.shl::<30>() ^ x);
    let cos = select(swap, s, c) ^ (q.int_add(L::splat_bits(1)) & L::splat_bits(2)).shl::<30>();
    let finite = x.is_finite();
    let nan = L::splat(f32::NAN);
    (select(finite, sin, nan), select(finite, cos, nan))
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
