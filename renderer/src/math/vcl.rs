//! The building blocks of the lane math, over any [`Lanes`] type, each as `wide` 1.7's `f32x8`
//! writes it for SSE2 (after Agner Fog's vector class library): the same operations in the same
//! order, so the functions built of them give `wide`'s bits in either lane type
//! (`super::wide_bits`'s tests). Multiply-add is a product then a sum, never fused (the renderer
//! refuses to compile with FMA, `lib.rs`). No `array::map` of lanes: its closure is not always
//! inlined into the AVX2 entry (`simd::run_in`).

use crate::simd::Lanes;

/// a b + c, rounded twice (`wide`'s `mul_add` without FMA).
#[inline(always)]
pub fn mul_add<L: Lanes>(a: L, b: L, c: L) -> L {
    a * b + c
}

/// c - a b, rounded twice (`wide`'s `mul_neg_add` without FMA).
#[inline(always)]
pub fn mul_neg_add<L: Lanes>(a: L, b: L, c: L) -> L {
    c - a * b
}

/// `if_true` where `mask` is set, else `if_false` (`wide`'s SSE2 `select`, a bit blend).
#[inline(always)]
pub fn select<L: Lanes>(mask: L, if_true: L, if_false: L) -> L {
    mask.bitselect(if_true, if_false)
}

/// `x` with its sign flipped where `sign`'s is set.
#[inline(always)]
pub fn flip_signs<L: Lanes>(x: L, sign: L) -> L {
    x ^ (sign & L::splat(-0.0))
}

/// The nearest integer, ties to even, as an `f32` (SSE2: through `cvtps2dq`, `x` itself where
/// that overflows, which is where `x` is already whole, infinite or NaN).
#[inline(always)]
pub fn round_ties_even<L: Lanes>(x: L) -> L {
    let i = x.round_int_bits();
    let overflowed = i.int_eq(L::splat_bits(0x8000_0000));
    select(overflowed, x, i.int_to_float())
}

/// The nearest integer, ties to even, as `i32` lanes (NaN gives 0, 2^31 and above `i32::MAX`).
#[inline(always)]
pub fn round_int<L: Lanes>(x: L) -> L {
    let non_nan = x & x.simd_eq(x);
    let flip_to_max = x.simd_ge(L::splat(2_147_483_648.0));
    flip_to_max ^ non_nan.round_int_bits()
}

/// The exponent of a positive `x`, unbiased, as an `f32`.
#[inline(always)]
pub fn exponent<L: Lanes>(x: L) -> L {
    let pow2_23 = L::splat(8_388_608.0);
    let biased = x.shr::<23>() | pow2_23;
    biased - (pow2_23 + L::splat(127.0))
}

/// The mantissa of `x` scaled into [1/2, 1).
#[inline(always)]
pub fn fraction_2<L: Lanes>(x: L) -> L {
    (x & L::splat_bits(0x007F_FFFF)) | L::splat_bits(0x3F00_0000)
}

/// Where `x` is infinite.
#[inline(always)]
pub fn is_inf<L: Lanes>(x: L) -> L {
    x.shl::<1>().int_eq(L::splat_bits(0xFF00_0000))
}

/// Where the sign bit of `x` is set (negative zero and NaNs included).
#[inline(always)]
pub fn is_sign_negative<L: Lanes>(x: L) -> L {
    let sign = L::splat_bits(0x8000_0000);
    (x & sign).int_eq(sign)
}

/// Where `x` is zero or subnormal (its exponent bits all zero).
#[inline(always)]
pub fn is_zero_or_subnormal<L: Lanes>(x: L) -> L {
    (x & L::splat_bits(0x7F80_0000)).int_eq(L::ZERO)
}

/// c0 + c1 x + c2 x^2 (`wide`'s `polynomial_2!`).
#[inline(always)]
pub fn polynomial_2<L: Lanes>(x: L, c: [f32; 3]) -> L {
    let k = |i: usize| L::splat(c[i]);
    let [c0, c1, c2] = [k(0), k(1), k(2)];
    mul_add(x * x, c2, mul_add(x, c1, c0))
}

/// c0 + ... + c3 x^3 (`polynomial_3!`).
#[inline(always)]
pub fn polynomial_3<L: Lanes>(x: L, c: [f32; 4]) -> L {
    let k = |i: usize| L::splat(c[i]);
    let [c0, c1, c2, c3] = [k(0), k(1), k(2), k(3)];
    let x2 = x * x;
    mul_add(mul_add(c3, x, c2), x2, mul_add(c1, x, c0))
}

/// c0 + ... + c4 x^4 (`polynomial_4!`).
#[inline(always)]
pub fn polynomial_4<L: Lanes>(x: L, c: [f32; 5]) -> L {
    let k = |i: usize| L::splat(c[i]);
    let [c0, c1, c2, c3, c4] = [k(0), k(1), k(2), k(3), k(4)];
    let x2 = x * x;
    let x4 = x2 * x2;
    mul_add(mul_add(c3, x, c2), x2, mul_add(c1, x, c0)) + c4 * x4
}

/// c0 + ... + c8 x^8 (`polynomial_8!`).
#[inline(always)]
pub fn polynomial_8<L: Lanes>(x: L, c: [f32; 9]) -> L {
    let k = |i: usize| L::splat(c[i]);
    let [c0, c1, c2, c3, c4, c5, c6, c7, c8] =
        [k(0), k(1), k(2), k(3), k(4), k(5), k(6), k(7), k(8)];
    let x2 = x * x;
    let x4 = x2 * x2;
    let x8 = x4 * x4;
    mul_add(
        x4,
        mul_add(x2, mul_add(c7, x, c6), mul_add(x, c5, c4)),
        mul_add(x8, c8, mul_add(x2, mul_add(x, c3, c2), mul_add(x, c1, c0))),
    )
}
