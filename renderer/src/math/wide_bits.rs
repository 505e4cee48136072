//! The lane math gives `wide`'s bits in every lane type this CPU has: each function against
//! `wide`'s `f32x8` method of the same name, on edge values, hashed bit patterns and the range
//! the renderer gives it.

use super::{acos_lanes, atan2_lanes, ln_lanes, sin_cos_lanes};
use crate::hash::{hash, unit_f32};
use crate::simd::{self, Kernel, Lanes};
use wide::f32x8;

/// Edge values, 20,000 hashed bit patterns, and 20,000 values of each range the renderer
/// uses: (0, 1] (the warp's `ln`), [-2^13, 2^13] (the spins' angles), [-1, 1] (`acos`, and
/// direction components for `atan2`).
fn values() -> Vec<f32> {
    let mut v = simd::EDGES.to_vec();
    let u = |seed: u64, i: u64| unit_f32(hash(seed, &[i]));
    for i in 0..20_000u64 {
        v.push(f32::from_bits(hash(0x3c, &[i]) as u32));
        v.push(1.0 - u(0x3d, i));
        v.push(16384.0 * u(0x3e, i) - 8192.0);
        v.push(2.0 * u(0x3f, i) - 1.0);
    }
    v
}

/// The five results (ln, sin, cos, atan2, acos) of `f` for eight values at a time and, as
/// `atan2`'s y, the same values shuffled, as bits per value.
fn bits(values: &[f32], f: impl Fn([f32; 8], [f32; 8]) -> [[f32; 8]; 5]) -> Vec<[u32; 5]> {
    let n = values.len();
    let mut out = Vec::with_capacity(n);
    for g in 0..n.div_ceil(8) {
        let x = std::array::from_fn(|k| values[(g * 8 + k) % n]);
        let y = std::array::from_fn(|k| values[(g * 8 + k * 7 + 3) % n]);
        let results = f(x, y);
        out.extend((0..8).map(|k| results.map(|r| key(r[k]))));
    }
    out
}

/// The bits, any NaN as one: which NaN an operation on two NaNs gives is unspecified, and LLVM
/// may swap an addition's operands (no NaN reaches a picture: such a sample is dropped).
fn key(x: f32) -> u32 {
    match x.is_nan() {
        true => f32::NAN.to_bits(),
        false => x.to_bits(),
    }
}

/// [`bits`] of the lane math in the lanes it is run in.
struct Ours<'a>(&'a [f32]);

impl Kernel for Ours<'_> {
    type Output = Vec<[u32; 5]>;
    #[inline(always)]
    fn run<L: Lanes>(self) -> Self::Output {
        bits(self.0, |x, y| {
            let (x, y) = (L::new(x), L::new(y));
            let (s, c) = sin_cos_lanes(x);
            [ln_lanes(x), s, c, atan2_lanes(y, x), acos_lanes(x)].map(L::to_array)
        })
    }
}

#[test]
fn every_function_gives_wides_bits_in_every_lane_type() {
    let values = values();
    let want = bits(&values, |x, y| {
        let (x, y) = (f32x8::new(x), f32x8::new(y));
        let (s, c) = x.sin_cos();
        [x.ln(), s, c, y.atan2(x), x.acos()].map(f32x8::to_array)
    });
    for &width in simd::widths() {
        let got = simd::run_in(width, Ours(&values));
        for (i, (g, w)) in got.iter().zip(&want).enumerate() {
            assert_eq!(
                g, w,
                "{width:?}: ln, sin, cos, atan2, acos of {}",
                values[i]
            );
        }
    }
}
