//! Powers in lanes, for the Phong lobe (see the module notes of [`super`]).

use wide::f32x8;

/// x^p of eight x >= 0 and exponents p at once (`wide`'s `f32x8::powf_simd`, Agner Fog's
/// `pow`: ln x from a degree-8 polynomial with its rounding error carried along, times p split
/// into an integer and a fraction of ln 2, then exp from a degree-7 polynomial and the exponent
/// bits). 0^p is 0 for p > 0 and 1 for p = 0; results below the smallest normal f32 flush to 0.
/// Negative bases follow libm (NaN unless p is an integer); the renderer gives none.
#[inline]
pub fn pow_lanes(x: f32x8, p: f32x8) -> f32x8 {
    x.powf_simd(p)
}

/// [`pow_lanes`] of one pair: the same bits.
#[inline]
pub fn pow(x: f32, p: f32) -> f32 {
    pow_lanes(f32x8::splat(x), f32x8::splat(p)).as_array()[0]
}

#[cfg(test)]
mod tests {
    use super::super::error::{Worst, ulps};
    use super::*;
    use crate::hash::{hash, unit_f32};

    /// The Phong lobe's inputs: bases r·v in [0, 1] (every 97th f32 of [2^-20, 1] and 2^20
    /// random ones) under exponents from 1 to 1000 (the thesis's materials use 20-200), against
    /// f64's `powf` of the same f32 pair, where the f64 result is a normal f32 (below that the
    /// lobe flushes to 0 where libm would give a subnormal no pixel can show).
    ///
    /// The bound is from theory, not from the measurement: without a fused multiply-add the
    /// product p ln x is rounded to f32 (the build has no FMA), and ln x carries its own
    /// rounding, so the exponent is off by up to about 2 x 2^-24 |p ln x| and the result by as
    /// much relatively, up to 2 |p ln x| ulp, plus a few ulp for the polynomials: bound
    /// 4 + 2 |p ln x| ulp. Measured: 78.0 ulp at x = 0.707, p = 200 (|p ln x| = 69, a lobe of
    /// 1e-30); 5.6 ulp where the lobe is above 1e-3 (|p ln x| < 6.9), a relative 7e-7.
    #[test]
    fn within_the_rounding_of_p_ln_x_on_the_phong_lobes_inputs() {
        let exponents = [
            1.0f32, 2.0, 7.5, 20.0, 50.0, 100.0, 128.0, 200.0, 333.3, 1000.0,
        ];
        let mut bases: Vec<f32> = (2f32.powi(-20).to_bits()..=1.0f32.to_bits())
            .step_by(97)
            .map(f32::from_bits)
            .collect();
        bases.extend((0..1u64 << 20).map(|i| unit_f32(hash(17, &[i]))));
        let (mut all, mut visible) = (Worst::default(), Worst::default());
        let mut over = None;
        for &p in &exponents {
            for group in bases.chunks(8) {
                let x = f32x8::new(std::array::from_fn(|k| group[k % group.len()]));
                let got = pow_lanes(x, f32x8::splat(p)).to_array();
                for (k, got) in got.into_iter().enumerate() {
                    let x = group[k % group.len()];
                    let want = (x as f64).powf(p as f64);
                    if want < f32::MIN_POSITIVE as f64 {
                        continue;
                    }
                    let e = ulps(got, want);
                    let bound = 4.0 + 2.0 * (p as f64 * (x as f64).ln()).abs();
                    if e > bound && over.is_none() {
                        over = Some((x, p, e, bound));
                    }
                    all.add(x, e);
                    if want > 1e-3 {
                        visible.add(x, e);
                    }
                }
            }
        }
        eprintln!("pow: all {all}; lobe above 1e-3 {visible}");
        assert_eq!(over, None, "(x, p, ulps, bound)");
        assert!(visible.ulps <= 4.0 + 2.0 * 1e3f64.ln(), "{visible}");
    }

    /// The lobe's edges as libm gives them: exact ones, zeros and the flush below f32's range.
    #[test]
    fn edges_as_libm() {
        for p in [0.0f32, 1.0, 20.0, 200.0, 1e6, 1e9, f32::MAX] {
            assert_eq!(pow(1.0, p), 1.0, "1^{p}");
            assert_eq!(pow(0.0, p), if p == 0.0 { 1.0 } else { 0.0 }, "0^{p}");
            assert_eq!(pow(0.5, p), 0.5f32.powf(p), "0.5^{p}");
        }
        assert_eq!(pow(0.3, 0.0), 1.0);
        assert_eq!(pow(0.999, 1e9), 0.0);
        assert_eq!(pow(0.5, 2.0), 0.25);
        assert!(pow(f32::NAN, 2.0).is_nan());
    }
}
