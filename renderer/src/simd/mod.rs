//! The lane type the packet code is written over, and the choice of it at run time.
//!
//! All packet code (camera rays and samples in `render`, `shading::packet`, the sky in
//! `environment`, the world's packet form in `accel`, the lane math) is generic over [`Lanes`]:
//! eight `f32` a value, one per ray of a packet. Two types implement it: `wide`'s `f32x8`
//! ([`Sse2`], two SSE2 registers, any x86-64) and [`Avx2`] (one AVX register, chosen at run
//! time where the CPU has AVX2). `wide` picks its AVX form when it is compiled, so one binary
//! can only have both by compiling the packet code twice. [`Kernel`] is the seam: a piece of
//! packet work generic over its lanes, which [`run_in`] runs as [`Avx2`] inside a
//! `#[target_feature(enable = "avx2")]` function, into which every lane function (all
//! `#[inline(always)]`) and every intrinsic inlines.
//!
//! Same bits: every [`Avx2`] operation is the very instruction `wide`'s SSE2 form does on
//! each half, at twice the width (IEEE addition, product, quotient, square root, the same
//! comparison predicates, the same NaN rules for `max`/`min`, the same integer conversions).
//! What `wide` does by a longer algorithm (`ln`, `sin_cos`, `atan2`, `acos`) `crate::math`
//! writes over [`Lanes`] in `wide`'s order of operations. The tests compare every operation,
//! and those functions, bit for bit on edge values; `accel::packet`'s tests trace both types
//! against the scalar world.

#[cfg(target_arch = "x86_64")]
mod avx2;
mod wide_lanes;

#[cfg(target_arch = "x86_64")]
pub use avx2::Avx2;
pub use wide_lanes::Sse2;

use std::fmt::Debug;
use std::ops::{Add, AddAssign, BitAnd, BitAndAssign, BitOr, BitOrAssign, BitXor, Div, Mul};
use std::ops::{MulAssign, Neg, Not, Sub, SubAssign};

/// Eight `f32` lanes, with `wide`'s `f32x8` operations and its results to the bit. A mask is
/// a value whose lanes are all ones or all zeros (what the comparisons give).
pub trait Lanes:
    Copy
    + Debug
    + Default
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + BitAnd<Output = Self>
    + BitOr<Output = Self>
    + BitXor<Output = Self>
    + Not<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + BitAndAssign
    + BitOrAssign
{
    const ZERO: Self;
    const ONE: Self;

    /// `kernel.run::<Self>()` where this type's instructions are enabled: how work that cannot
    /// inline (the mirror recursion) gets back into the AVX2 entry.
    fn enter<K: Kernel>(kernel: K) -> K::Output;

    fn splat(x: f32) -> Self;
    /// Every lane the `f32` of these bits.
    #[inline(always)]
    fn splat_bits(bits: u32) -> Self {
        Self::splat(f32::from_bits(bits))
    }
    fn new(lanes: [f32; 8]) -> Self;
    fn to_array(self) -> [f32; 8];
    fn as_array(&self) -> &[f32; 8];
    fn as_mut_array(&mut self) -> &mut [f32; 8];
    /// `wide`'s `f32x8` of the same lanes, and back.
    fn to_wide(self) -> wide::f32x8;
    fn from_wide(w: wide::f32x8) -> Self;

    fn simd_eq(self, rhs: Self) -> Self;
    fn simd_ne(self, rhs: Self) -> Self;
    fn simd_lt(self, rhs: Self) -> Self;
    fn simd_le(self, rhs: Self) -> Self;
    fn simd_gt(self, rhs: Self) -> Self;
    fn simd_ge(self, rhs: Self) -> Self;
    fn is_nan(self) -> Self;
    fn is_finite(self) -> Self;

    /// `self`'s bits where `self` (a mask) is set, else `if_zero`'s.
    fn bitselect(self, if_one: Self, if_zero: Self) -> Self;
    /// Bit `i` set where lane `i`'s sign bit is.
    fn to_bitmask(self) -> u32;
    fn any(self) -> bool;
    fn all(self) -> bool;
    /// All bits set in the lanes of `bits` (bit `i` for lane `i`), clear in the others.
    fn lane_mask(bits: u32) -> Self;

    fn abs(self) -> Self;
    fn sqrt(self) -> Self;
    /// `wide`'s `max`: `rhs` unless it is below `self`, `self` where `rhs` is NaN.
    fn max(self, rhs: Self) -> Self;
    fn min(self, rhs: Self) -> Self;
    /// `maxps`: `self` where it is above `rhs`, else `rhs` (a NaN operand gives `rhs`).
    fn fast_max(self, rhs: Self) -> Self;
    fn fast_min(self, rhs: Self) -> Self;
    /// Truncated to an `i32` and back (`fast_trunc_int().round_float()`).
    fn trunc_through_int(self) -> Self;

    /// `cvtps2dq`: the nearest `i32` (ties to even), `i32::MIN` where out of range or NaN;
    /// the result's lanes hold the integers' bits.
    fn round_int_bits(self) -> Self;
    /// `cvtdq2ps`: the lanes' bits read as `i32`, converted to `f32`.
    fn int_to_float(self) -> Self;

    // The lanes' bits as `i32`: what the lane math (`crate::math`) does to exponents and
    // quadrants.
    /// Sum, wrapping.
    fn int_add(self, rhs: Self) -> Self;
    /// A mask where equal.
    fn int_eq(self, rhs: Self) -> Self;
    /// A mask where `self` > `rhs`, signed.
    fn int_gt(self, rhs: Self) -> Self;
    /// Shifted left by `N` (`N` < 32).
    fn shl<const N: i32>(self) -> Self;
    /// Shifted right by `N`, zeros in (`N` < 32).
    fn shr<const N: i32>(self) -> Self;
}

/// Work written once over any [`Lanes`] type: the seam between the scalar code and the packet
/// code compiled for each lane type. `run` must be `#[inline(always)]`, and so must every lane
/// function it calls, so that all of it inlines into [`run_in`]'s AVX2 entry.
pub trait Kernel {
    type Output;
    fn run<L: Lanes>(self) -> Self::Output;
}

/// `kernel.run::<L>()` with `L` the lane type of `width` (one this CPU has: [`widest`] or
/// narrower), where its instructions are enabled.
#[inline(always)]
pub fn run_in<K: Kernel>(width: Width, kernel: K) -> K::Output {
    match width {
        #[cfg(target_arch = "x86_64")]
        Width::Avx2 => Avx2::enter(kernel),
        _ => Sse2::enter(kernel),
    }
}

/// The lane types the run-time choice picks from (`Avx2` only on x86-64).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Width {
    Sse2,
    Avx2,
}

/// The lanes the renderer traces in: the widest this machine has ([`widths`]), or SSE2 after
/// [`limit_to_sse2`].
pub fn widest() -> Width {
    match SSE2_ONLY.load(std::sync::atomic::Ordering::Relaxed) {
        true => Width::Sse2,
        false => *widths().last().expect("SSE2 at least"),
    }
}

static SSE2_ONLY: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// From now on, trace in SSE2 lanes even where the CPU has wider ones (the same bytes: to time
/// the two, `bench/lanes.sh`, whose binaries take `BLURLAB_LANES=sse2`).
pub fn limit_to_sse2() {
    SSE2_ONLY.store(true, std::sync::atomic::Ordering::Relaxed);
}

/// Every lane width this CPU has, narrowest first (the tests render with each).
pub fn widths() -> &'static [Width] {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") {
        return &[Width::Sse2, Width::Avx2];
    }
    &[Width::Sse2]
}

/// Edge values for the bit-for-bit tests of the lane types and the lane math: signed zeros and
/// infinities, NaNs of both signs, subnormals, the largest and smallest normals, whole numbers
/// near 2^23, 2^25 pi/2 and 2^31, halves (ties of the rounding).
#[cfg(test)]
pub(crate) const EDGES: [f32; 25] = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.5,
    -0.5,
    1.5,
    -1.5,
    2.5,
    std::f32::consts::FRAC_PI_4,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::NAN,
    -f32::NAN,
    f32::MIN_POSITIVE,
    -f32::MIN_POSITIVE / 4.0,
    f32::from_bits(1),
    f32::MAX,
    f32::MIN,
    8_388_607.5,
    -8_388_608.0,
    52_707_180.0,
    2_147_483_520.0,
    -2_147_483_648.0,
    3.0e9,
];
