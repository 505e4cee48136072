//! The per-pixel Cranley-Patterson shift (thesis Figure 14): every pixel adds its own seeded
//! offset to all three coordinates of the shared point set and wraps into [0, 1), so one set
//! serves every pixel without the aliasing of reusing it unchanged (thesis Figure 15).

use crate::hash;

/// 21 bits per coordinate from one 64-bit hash: steps of 2^-21 ≈ 5e-7 pixel or shutter
/// fraction, far below anything visible, for one hash per pixel instead of three.
const BITS: u32 = 21;
const MASK: u64 = (1 << BITS) - 1;
const SCALE: f32 = 1.0 / (1u32 << BITS) as f32;

/// The shift of pixel (x, y) under `key` (one key per stimulus, or per frame): three values
/// in [0, 1) that depend only on the key and the pixel, never on the order of work.
#[inline]
pub fn pixel_shift(key: u64, x: u32, y: u32) -> [f32; 3] {
    let h = hash::hash(key, &[((x as u64) << 32) | y as u64]);
    [
        (h >> (64 - BITS)) as f32 * SCALE,
        ((h >> (64 - 2 * BITS)) & MASK) as f32 * SCALE,
        ((h >> (64 - 3 * BITS)) & MASK) as f32 * SCALE,
    ]
}

/// a + s wrapped into [0, 1) for a, s in [0, 1) (thesis Figure 14: add, subtract 1 if >= 1).
/// In f32 the sum may round up to 1 exactly; it then wraps to 0, and r - 1 for r in [1, 2) is
/// exact, so the result never leaves [0, 1).
#[inline]
pub fn wrap(a: f32, s: f32) -> f32 {
    let r = a + s;
    if r >= 1.0 { r - 1.0 } else { r }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn wrapped_points_stay_in_the_unit_interval(a in 0f32..1.0, key: u64, x: u32, y: u32) {
            for s in pixel_shift(key, x, y) {
                prop_assert!((0.0..1.0).contains(&s));
                let w = wrap(a, s);
                prop_assert!((0.0..1.0).contains(&w), "{} + {} -> {}", a, s, w);
            }
        }
    }

    #[test]
    fn extreme_values_wrap_into_range() {
        let below_one = 1.0 - f32::EPSILON / 2.0;
        assert_eq!(wrap(below_one, below_one), 1.0 - f32::EPSILON);
        assert!(wrap(0.5, 0.499_999_97) < 1.0);
        assert_eq!(wrap(0.0, 0.0), 0.0);
    }

    #[test]
    fn pixels_get_different_uniform_shifts() {
        // 256 x 256 pixels: all distinct, and each coordinate's mean within 5 standard errors
        // (sqrt(1/12 / 65536) = 1.1e-3) of 1/2.
        let mut seen = std::collections::HashSet::new();
        let mut sum = [0.0f64; 3];
        for y in 0..256 {
            for x in 0..256 {
                let s = pixel_shift(9, x, y);
                assert!(
                    seen.insert(s.map(f32::to_bits)),
                    "({x}, {y}) repeats a shift"
                );
                for d in 0..3 {
                    sum[d] += s[d] as f64;
                }
            }
        }
        for m in sum.map(|v| v / 65536.0) {
            assert!((m - 0.5).abs() < 5.0 * 1.13e-3, "{m}");
        }
        assert_ne!(pixel_shift(1, 3, 4), pixel_shift(2, 3, 4));
        assert_ne!(pixel_shift(1, 3, 4), pixel_shift(1, 4, 3));
    }
}
