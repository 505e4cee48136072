//! [`Lanes`] for `wide`'s `f32x8`: what the packet code always ran on (two SSE2 registers in
//! the default build, one AVX register in a build for x86-64-v3).

use super::{Kernel, Lanes};
use wide::bytemuck::cast;
use wide::{f32x8, i32x8, u32x8};

/// The same bits as `i32` lanes.
#[inline(always)]
fn int(x: f32x8) -> i32x8 {
    cast(x)
}

/// `kernel` in `wide`'s lanes: a function of its own, as [`super::Avx2`]'s entry is (so a
/// recursion through [`Lanes::enter`] is a call, not inlined into itself).
#[inline(never)]
fn run<K: Kernel>(kernel: K) -> K::Output {
    kernel.run::<f32x8>()
}

/// Trait methods taking `self` by value that call `f32x8`'s inherent method of the same name.
macro_rules! delegate {
    ($(fn $name:ident(self $(, $arg:ident: $ty:ty)*) -> $out:ty;)*) => {
        $(
            #[inline(always)]
            fn $name(self $(, $arg: $ty)*) -> $out {
                f32x8::$name(self $(, $arg)*)
            }
        )*
    };
}

/// `wide`'s eight lanes, as compiled.
pub type Sse2 = f32x8;

impl Lanes for f32x8 {
    const ZERO: Self = f32x8::ZERO;
    const ONE: Self = f32x8::ONE;

    #[inline(always)]
    fn enter<K: Kernel>(kernel: K) -> K::Output {
        run(kernel)
    }

    #[inline(always)]
    fn splat(x: f32) -> Self {
        f32x8::splat(x)
    }
    #[inline(always)]
    fn new(lanes: [f32; 8]) -> Self {
        f32x8::new(lanes)
    }
    #[inline(always)]
    fn as_array(&self) -> &[f32; 8] {
        f32x8::as_array(self)
    }
    #[inline(always)]
    fn as_mut_array(&mut self) -> &mut [f32; 8] {
        f32x8::as_mut_array(self)
    }
    // Each `wide`'s own method of the same name.
    delegate! {
        fn to_array(self) -> [f32; 8];
        fn simd_eq(self, rhs: Self) -> Self;
        fn simd_ne(self, rhs: Self) -> Self;
        fn simd_lt(self, rhs: Self) -> Self;
        fn simd_le(self, rhs: Self) -> Self;
        fn simd_gt(self, rhs: Self) -> Self;
        fn simd_ge(self, rhs: Self) -> Self;
        fn is_nan(self) -> Self;
        fn is_finite(self) -> Self;
        fn bitselect(self, if_one: Self, if_zero: Self) -> Self;
        fn to_bitmask(self) -> u32;
        fn any(self) -> bool;
        fn all(self) -> bool;
        fn abs(self) -> Self;
        fn sqrt(self) -> Self;
        fn max(self, rhs: Self) -> Self;
        fn min(self, rhs: Self) -> Self;
        fn fast_max(self, rhs: Self) -> Self;
        fn fast_min(self, rhs: Self) -> Self;
    }
    #[inline(always)]
    fn to_wide(self) -> f32x8 {
        self
    }
    #[inline(always)]
    fn from_wide(w: f32x8) -> Self {
        w
    }
    #[inline(always)]
    fn lane_mask(bits: u32) -> Self {
        let bit = i32x8::new([1, 2, 4, 8, 16, 32, 64, 128]);
        cast((i32x8::splat(bits as i32) & bit).simd_eq(bit))
    }
    #[inline(always)]
    fn trunc_through_int(self) -> Self {
        self.fast_trunc_int().round_float()
    }
    /// `wide`'s `round_int` without its NaN and overflow fix-ups: `cvtps2dq` alone.
    #[inline(always)]
    fn round_int_bits(self) -> Self {
        cast(self.fast_round_int())
    }
    #[inline(always)]
    fn int_to_float(self) -> Self {
        int(self).round_float()
    }
    #[inline(always)]
    fn int_add(self, rhs: Self) -> Self {
        cast(int(self) + int(rhs))
    }
    #[inline(always)]
    fn int_eq(self, rhs: Self) -> Self {
        cast(int(self).simd_eq(int(rhs)))
    }
    #[inline(always)]
    fn int_gt(self, rhs: Self) -> Self {
        cast(int(self).simd_gt(int(rhs)))
    }
    #[inline(always)]
    fn shl<const N: i32>(self) -> Self {
        cast(int(self) << N)
    }
    #[inline(always)]
    fn shr<const N: i32>(self) -> Self {
        cast(cast::<_, u32x8>(self) >> N)
    }
}
