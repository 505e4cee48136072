//! The film: one linear HDR value per pixel (the mean of its samples, each sample one (u, v, t)
//! point), and its two outputs — 8-bit sRGB for display (exposure, then clamp to [0, 1], then
//! the sRGB curve) and 32-bit float linear values (after exposure) for measurement.

use glam::Vec3;

/// One rendered frame in both forms.
#[derive(Clone, Debug)]
pub struct RenderedFrame {
    /// Linear HDR radiance after exposure, row-major.
    pub linear: Vec<[f32; 3]>,
    /// 8-bit sRGB display values, packed RGB, row-major.
    pub display: Vec<u8>,
}

/// Display encoding of a linear value: clamp to [0, 1], then the sRGB transfer curve, rounded
/// to 8 bits (the film's, and the synthetic test source's). [`srgb8_curve`]'s value, found
/// without its `powf` (see [`Levels`]).
#[inline]
pub fn srgb8(linear: f32) -> u8 {
    Levels::get().of(linear)
}

/// The definition of [`srgb8`]: one `powf` per value (a 768 x 768 frame's 1.8 M values cost
/// more than an 8-bit frame's PNG encoding).
pub fn srgb8_curve(linear: f32) -> u8 {
    let c = if linear.is_finite() {
        linear.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let s = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

/// Where [`srgb8_curve`] steps up: `first[k - 1]` is the bit pattern of the least `f32` in
/// (0, 1] it takes to `k` or above. The curve rises with its argument (the tests check it
/// about every step), and positive `f32`s order as their bits, so a value's level is the number
/// of steps at or below its bits: `bucket` (by the bits' top 17) gives the count at a bucket's
/// start, and at most a step or two lie inside a bucket.
struct Levels {
    first: [u32; 255],
    bucket: Vec<u8>,
}

/// Buckets of `2^BUCKET_SHIFT` consecutive bit patterns.
const BUCKET_SHIFT: u32 = 15;
const ONE_BITS: u32 = 0x3f80_0000;

impl Levels {
    fn get() -> &'static Levels {
        static LEVELS: std::sync::OnceLock<Levels> = std::sync::OnceLock::new();
        LEVELS.get_or_init(Levels::new)
    }

    fn new() -> Levels {
        let first = std::array::from_fn(|k| {
            // The least bits in (0, ONE_BITS] at level k + 1 or above, by bisection.
            let (mut lo, mut hi) = (0u32, ONE_BITS);
            while hi - lo > 1 {
                let mid = lo + (hi - lo) / 2;
                if srgb8_curve(f32::from_bits(mid)) as usize > k {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            hi
        });
        let bucket = (0..=ONE_BITS >> BUCKET_SHIFT)
            .map(|b| first.partition_point(|&t| t <= b << BUCKET_SHIFT) as u8)
            .collect();
        Levels { first, bucket }
    }

    #[inline]
    fn of(&self, linear: f32) -> u8 {
        // NaN, infinities and everything at or below zero (-0.0 included) are level 0; 1 and
        // above 255.
        if !(linear > 0.0 && linear.is_finite()) {
            return 0;
        }
        if linear >= 1.0 {
            return 255;
        }
        let bits = linear.to_bits();
        let mut k = self.bucket[(bits >> BUCKET_SHIFT) as usize] as usize;
        while k < 255 && self.first[k] <= bits {
            k += 1;
        }
        k as u8
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    /// Mean radiance per pixel, row-major from the top-left corner.
    pub pixels: Vec<Vec3>,
}

impl Film {
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            pixels: vec![Vec3::ZERO; width as usize * height as usize],
        }
    }

    /// Linear values after `exposure` and the display frame made from them.
    pub fn develop(&self, exposure: f32) -> RenderedFrame {
        let linear: Vec<[f32; 3]> = self
            .pixels
            .iter()
            .map(|p| (*p * exposure).to_array())
            .collect();
        let display = linear.iter().flat_map(|p| p.map(srgb8)).collect();
        RenderedFrame { linear, display }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`srgb8`] is [`srgb8_curve`] at every step (4,096 values either side of each) and at
    /// values of every kind; the curve rises through each window, so between steps it stays
    /// on its level (`every_f32` checks all 2^32 values).
    #[test]
    fn levels_are_the_curve_to_the_byte() {
        let levels = Levels::get();
        let mut values = vec![
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.003_130_8,
            f32::MIN_POSITIVE,
            1e-45,
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            1.0 - f32::EPSILON / 2.0,
            30.0,
        ];
        for &step in &levels.first {
            let from = step.saturating_sub(4096);
            let mut last = 0;
            for bits in from..(step + 4096).min(ONE_BITS + 1) {
                let v = srgb8_curve(f32::from_bits(bits));
                assert!(v >= last, "the curve falls at {bits:#x}");
                last = v;
                values.push(f32::from_bits(bits));
            }
        }
        for i in 0..200_000u64 {
            values.push(f32::from_bits(crate::hash::hash(31, &[i]) as u32));
            values.push(crate::hash::unit_f32(crate::hash::hash(32, &[i])) * 1.2 - 0.1);
        }
        for x in values {
            assert_eq!(srgb8(x), srgb8_curve(x), "{x:e} ({:#x})", x.to_bits());
        }
    }

    #[test]
    #[ignore = "all 2^32 f32 values, about 20 s of CPU at opt-level 3"]
    fn every_f32() {
        for bits in 0..=u32::MAX {
            let x = f32::from_bits(bits);
            assert_eq!(srgb8(x), srgb8_curve(x), "{bits:#x}");
        }
    }

    #[test]
    fn develop_applies_exposure_then_clamp_then_srgb() {
        let mut f = Film::new(3, 1);
        f.pixels = vec![
            Vec3::new(0.5, 2.0, 0.0),
            Vec3::splat(0.107),
            Vec3::splat(100.0),
        ];
        let r = f.develop(2.0);
        assert_eq!(r.linear[0], [1.0, 4.0, 0.0]);
        assert_eq!(&r.display[0..3], &[255, 255, 0]);
        // 0.107 * 2 = 0.214: sRGB mid grey (128).
        assert!((r.display[3] as i32 - 128).abs() <= 1);
        assert_eq!(r.linear[2], [200.0; 3], "linear values are not clamped");
    }
}
