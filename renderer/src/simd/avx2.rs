//! [`Lanes`] in one AVX register, for CPUs with AVX2 (chosen at run time, [`super::widest`]).
//!
//! Each operation is one intrinsic, the instruction `wide`'s SSE2 form runs on each half
//! (`wide` 1.7's `f32x4`, to the bit: see the module notes of [`super`]). The intrinsics need
//! AVX; they run only inside [`run`], a `#[target_feature(enable = "avx2")]` function, into
//! which these `#[inline(always)]` methods inline (outside one they would be calls, still
//! right but slow: `bench/lanes.sh` finds any).

use super::{Kernel, Lanes};
use std::arch::x86_64::*;
use std::fmt;
use std::ops::{Add, AddAssign, BitAnd, BitAndAssign, BitOr, BitOrAssign, BitXor, Div, Mul};
use std::ops::{MulAssign, Neg, Not, Sub, SubAssign};

/// Eight `f32` in one AVX register.
#[derive(Clone, Copy)]
#[repr(transparent)]
pub struct Avx2(__m256);

/// `kernel` in AVX2 lanes, compiled with AVX2 enabled.
#[target_feature(enable = "avx2")]
fn run<K: Kernel>(kernel: K) -> K::Output {
    kernel.run::<Avx2>()
}

// Safety of the `unsafe` blocks below: each calls an AVX or AVX2 intrinsic, on a CPU with AVX2
// (`Lanes::enter` checks; the tests check before they make an `Avx2`); the transmutes are
// between 32-byte plain-old-data types of the same size.

impl Avx2 {
    #[inline(always)]
    fn bits(self) -> __m256i {
        unsafe { _mm256_castps_si256(self.0) }
    }
    #[inline(always)]
    fn of_bits(i: __m256i) -> Self {
        unsafe { Self(_mm256_castsi256_ps(i)) }
    }
}

impl fmt::Debug for Avx2 {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.as_array().fmt(f)
    }
}

impl Default for Avx2 {
    fn default() -> Self {
        Self::ZERO
    }
}

/// The `std::ops` traits, one intrinsic each.
macro_rules! binary {
    ($trait:ident, $fn:ident, $intrinsic:ident) => {
        impl $trait for Avx2 {
            type Output = Self;
            #[inline(always)]
            fn $fn(self, rhs: Self) -> Self {
                unsafe { Self($intrinsic(self.0, rhs.0)) }
            }
        }
    };
}
binary!(Add, add, _mm256_add_ps);
binary!(Sub, sub, _mm256_sub_ps);
binary!(Mul, mul, _mm256_mul_ps);
binary!(Div, div, _mm256_div_ps);
binary!(BitAnd, bitand, _mm256_and_ps);
binary!(BitOr, bitor, _mm256_or_ps);
binary!(BitXor, bitxor, _mm256_xor_ps);

/// The compound assignments, by the operators above.
macro_rules! assign {
    ($trait:ident, $fn:ident, $op:tt) => {
        impl $trait for Avx2 {
            #[inline(always)]
            fn $fn(&mut self, rhs: Self) {
                *self = *self $op rhs;
            }
        }
    };
}
assign!(AddAssign, add_assign, +);
assign!(SubAssign, sub_assign, -);
assign!(MulAssign, mul_assign, *);
assign!(BitAndAssign, bitand_assign, &);
assign!(BitOrAssign, bitor_assign, |);

/// `wide`'s negation: the sign bit flipped.
impl Neg for Avx2 {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self ^ Self::splat(-0.0)
    }
}

impl Not for Avx2 {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        self ^ Self::of_bits(unsafe { _mm256_set1_epi32(-1) })
    }
}

/// A comparison by its `_CMP_` predicate: SSE2's `cmpeqps` is `EQ_OQ`, `cmpneqps` `NEQ_UQ`,
/// `cmpltps` `LT_OS`, `cmpleps` `LE_OS` (and `wide`'s `>`, `>=` the same with the operands
/// swapped: `GT_OS`, `GE_OS`), `cmpunordps` `UNORD_Q`.
macro_rules! compare {
    ($self:expr, $rhs:expr, $predicate:ident) => {
        unsafe { Avx2(_mm256_cmp_ps::<$predicate>($self.0, $rhs.0)) }
    };
}

impl Lanes for Avx2 {
    const ZERO: Self = unsafe { std::mem::transmute::<[f32; 8], Self>([0.0; 8]) };
    const ONE: Self = unsafe { std::mem::transmute::<[f32; 8], Self>([1.0; 8]) };

    #[inline(always)]
    fn enter<K: Kernel>(kernel: K) -> K::Output {
        // std keeps the answer: one load.
        assert!(
            is_x86_feature_detected!("avx2"),
            "AVX2 lanes on a CPU without AVX2"
        );
        // Safety: this CPU has AVX2.
        unsafe { run(kernel) }
    }

    #[inline(always)]
    fn splat(x: f32) -> Self {
        unsafe { Self(_mm256_set1_ps(x)) }
    }
    #[inline(always)]
    fn new(lanes: [f32; 8]) -> Self {
        unsafe { std::mem::transmute::<[f32; 8], Self>(lanes) }
    }
    #[inline(always)]
    fn to_array(self) -> [f32; 8] {
        unsafe { std::mem::transmute::<Self, [f32; 8]>(self) }
    }
    #[inline(always)]
    fn as_array(&self) -> &[f32; 8] {
        unsafe { &*(self as *const Self).cast::<[f32; 8]>() }
    }
    #[inline(always)]
    fn as_mut_array(&mut self) -> &mut [f32; 8] {
        unsafe { &mut *(self as *mut Self).cast::<[f32; 8]>() }
    }
    #[inline(always)]
    fn to_wide(self) -> wide::f32x8 {
        unsafe { std::mem::transmute::<Self, wide::f32x8>(self) }
    }
    #[inline(always)]
    fn from_wide(w: wide::f32x8) -> Self {
        unsafe { std::mem::transmute::<wide::f32x8, Self>(w) }
    }
    #[inline(always)]
    fn simd_eq(self, rhs: Self) -> Self {
        compare!(self, rhs, _CMP_EQ_OQ)
    }
    #[inline(always)]
    fn simd_ne(self, rhs: Self) -> Self {
        compare!(self, rhs, _CMP_NEQ_UQ)
    }
    #[inline(always)]
    fn simd_lt(self, rhs: Self) -> Self {
        compare!(self, rhs, _CMP_LT_OS)
    }
    #[inline(always)]
    fn simd_le(self, rhs: Self) -> Self {
        compare!(self, rhs, _CMP_LE_OS)
    }
    #[inline(always)]
    fn simd_gt(self, rhs: Self) -> Self {
        compare!(self, rhs, _CMP_GT_OS)
    }
    #[inline(always)]
    fn simd_ge(self, rhs: Self) -> Self {
        compare!(self, rhs, _CMP_GE_OS)
    }
    #[inline(always)]
    fn is_nan(self) -> Self {
        compare!(self, self, _CMP_UNORD_Q)
    }
    /// `wide`'s test: the exponent's bits, shifted to the top, not all ones.
    #[inline(always)]
    fn is_finite(self) -> Self {
        unsafe {
            let exponent = _mm256_set1_epi32(0xFF00_0000_u32 as i32);
            let shifted = _mm256_and_si256(_mm256_slli_epi32::<1>(self.bits()), exponent);
            !Self::of_bits(_mm256_cmpeq_epi32(shifted, exponent))
        }
    }
    /// `wide`'s `(if_one & self) | (if_zero & !self)`.
    #[inline(always)]
    fn bitselect(self, if_one: Self, if_zero: Self) -> Self {
        unsafe {
            Self(_mm256_or_ps(
                _mm256_and_ps(if_one.0, self.0),
                _mm256_andnot_ps(self.0, if_zero.0),
            ))
        }
    }
    #[inline(always)]
    fn to_bitmask(self) -> u32 {
        unsafe { _mm256_movemask_ps(self.0) as u32 }
    }
    #[inline(always)]
    fn any(self) -> bool {
        self.to_bitmask() != 0
    }
    #[inline(always)]
    fn all(self) -> bool {
        self.to_bitmask() == 0xff
    }
    #[inline(always)]
    fn lane_mask(bits: u32) -> Self {
        unsafe {
            let bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
            let set = _mm256_and_si256(_mm256_set1_epi32(bits as i32), bit);
            Self::of_bits(_mm256_cmpeq_epi32(set, bit))
        }
    }
    #[inline(always)]
    fn abs(self) -> Self {
        self & Self::of_bits(unsafe { _mm256_set1_epi32(i32::MAX) })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        unsafe { Self(_mm256_sqrt_ps(self.0)) }
    }
    /// `wide`'s: `maxps`, but `self` where `rhs` is NaN.
    #[inline(always)]
    fn max(self, rhs: Self) -> Self {
        unsafe {
            let m = _mm256_max_ps(self.0, rhs.0);
            Self(_mm256_blendv_ps(m, self.0, rhs.is_nan().0))
        }
    }
    #[inline(always)]
    fn min(self, rhs: Self) -> Self {
        unsafe {
            let m = _mm256_min_ps(self.0, rhs.0);
            Self(_mm256_blendv_ps(m, self.0, rhs.is_nan().0))
        }
    }
    #[inline(always)]
    fn fast_max(self, rhs: Self) -> Self {
        unsafe { Self(_mm256_max_ps(self.0, rhs.0)) }
    }
    #[inline(always)]
    fn fast_min(self, rhs: Self) -> Self {
        unsafe { Self(_mm256_min_ps(self.0, rhs.0)) }
    }
    /// `cvttps2dq` then `cvtdq2ps`, as `wide`'s SSE2 form.
    #[inline(always)]
    fn trunc_through_int(self) -> Self {
        unsafe { Self(_mm256_cvtepi32_ps(_mm256_cvttps_epi32(self.0))) }
    }
    #[inline(always)]
    fn round_int_bits(self) -> Self {
        Self::of_bits(unsafe { _mm256_cvtps_epi32(self.0) })
    }
    #[inline(always)]
    fn int_to_float(self) -> Self {
        unsafe { Self(_mm256_cvtepi32_ps(self.bits())) }
    }
    #[inline(always)]
    fn int_add(self, rhs: Self) -> Self {
        Self::of_bits(unsafe { _mm256_add_epi32(self.bits(), rhs.bits()) })
    }
    #[inline(always)]
    fn int_eq(self, rhs: Self) -> Self {
        Self::of_bits(unsafe { _mm256_cmpeq_epi32(self.bits(), rhs.bits()) })
    }
    #[inline(always)]
    fn int_gt(self, rhs: Self) -> Self {
        Self::of_bits(unsafe { _mm256_cmpgt_epi32(self.bits(), rhs.bits()) })
    }
    #[inline(always)]
    fn shl<const N: i32>(self) -> Self {
        Self::of_bits(unsafe { _mm256_slli_epi32::<N>(self.bits()) })
    }
    #[inline(always)]
    fn shr<const N: i32>(self) -> Self {
        Self::of_bits(unsafe { _mm256_srli_epi32::<N>(self.bits()) })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hash::{hash, unit_f32};
    use wide::f32x8;

    /// [`super::EDGES`] and hashed bit patterns.
    fn values() -> Vec<f32> {
        let mut v = super::super::EDGES.to_vec();
        v.extend((0..1000u64).map(|i| f32::from_bits(hash(0xa5, &[i]) as u32)));
        v.extend((0..1000u64).map(|i| 4.0 * unit_f32(hash(0x5a, &[i])) - 2.0));
        v
    }

    /// Every group of eight consecutive values, and the same shifted by three against itself:
    /// pairs `(a, b)` covering every edge value against every other often.
    fn pairs() -> Vec<([f32; 8], [f32; 8])> {
        let v = values();
        let n = v.len();
        (0..n * 4)
            .map(|g| {
                let a = std::array::from_fn(|k| v[(g * 8 + k) % n]);
                let b = std::array::from_fn(|k| v[(g * 8 + k * 7 + g / n) % n]);
                (a, b)
            })
            .collect()
    }

    /// The same bits, except that any NaN matches any NaN for arithmetic (`+ - * /`, square
    /// root): LLVM may swap an addition's operands, and which NaN a sum of two NaNs gives is
    /// unspecified. (No NaN reaches a picture: a sample that is not finite is dropped.)
    fn same(got: Avx2, want: f32x8, what: &str, a: &[f32; 8], b: &[f32; 8]) {
        let arithmetic = ["+", "-", "*", "/", "sqrt", "+= *="].contains(&what);
        let key = |x: f32| match arithmetic && x.is_nan() {
            true => f32::NAN.to_bits(),
            false => x.to_bits(),
        };
        let (g, w) = (got.to_array().map(key), want.to_array().map(key));
        assert_eq!(g, w, "{what} of {a:?} and {b:?}");
    }

    #[test]
    fn every_operation_gives_wides_bits() {
        if !std::is_x86_feature_detected!("avx2") {
            eprintln!("skipped: this CPU has no AVX2");
            return;
        }
        for (a, b) in pairs() {
            let (x, y) = (Avx2::new(a), Avx2::new(b));
            let (p, q) = (f32x8::new(a), f32x8::new(b));
            let ops: [(&str, Avx2, f32x8); 32] = [
                ("+", x + y, p + q),
                ("-", x - y, p - q),
                ("*", x * y, p * q),
                ("/", x / y, p / q),
                ("neg", -x, -p),
                ("&", x & y, p & q),
                ("|", x | y, p | q),
                ("^", x ^ y, p ^ q),
                ("!", !x, !p),
                ("==", x.simd_eq(y), Lanes::simd_eq(p, q)),
                ("!=", x.simd_ne(y), Lanes::simd_ne(p, q)),
                ("<", x.simd_lt(y), Lanes::simd_lt(p, q)),
                ("<=", x.simd_le(y), Lanes::simd_le(p, q)),
                (">", x.simd_gt(y), Lanes::simd_gt(p, q)),
                (">=", x.simd_ge(y), Lanes::simd_ge(p, q)),
                ("is_nan", x.is_nan(), p.is_nan()),
                ("is_finite", x.is_finite(), p.is_finite()),
                ("bitselect", x.bitselect(x, y), p.bitselect(p, q)),
                ("abs", x.abs(), p.abs()),
                ("sqrt", x.sqrt(), p.sqrt()),
                ("max", x.max(y), p.max(q)),
                ("min", x.min(y), p.min(q)),
                ("fast_max", x.fast_max(y), p.fast_max(q)),
                ("fast_min", x.fast_min(y), p.fast_min(q)),
                ("trunc", x.trunc_through_int(), p.trunc_through_int()),
                ("cvtps2dq", x.round_int_bits(), p.round_int_bits()),
                ("cvtdq2ps", x.int_to_float(), p.int_to_float()),
                ("paddd", x.int_add(y), p.int_add(q)),
                ("pcmpeqd", x.int_eq(y), p.int_eq(q)),
                ("pcmpgtd", x.int_gt(y), p.int_gt(q)),
                ("pslld", x.shl::<30>(), p.shl::<30>()),
                ("psrld", x.shr::<23>(), p.shr::<23>()),
            ];
            for (what, got, want) in ops {
                same(got, want, what, &a, &b);
            }
            let mask = x.simd_lt(y);
            assert_eq!(mask.to_bitmask(), Lanes::to_bitmask(p.simd_lt(q)));
            assert_eq!(mask.any(), Lanes::any(p.simd_lt(q)));
            assert_eq!(mask.all(), Lanes::all(p.simd_lt(q)));
            let sel = mask.bitselect(x, y);
            same(sel, p.simd_lt(q).bitselect(p, q), "select", &a, &b);
            let (mut m, mut n) = (x, p);
            m += y;
            n += q;
            m *= y;
            n *= q;
            same(m, n, "+= *=", &a, &b);
        }
        for bits in 0..=255u32 {
            same(
                Avx2::lane_mask(bits),
                <f32x8 as Lanes>::lane_mask(bits),
                "mask",
                &[0.0; 8],
                &[0.0; 8],
            );
        }
        same(
            Avx2::splat(-0.0),
            f32x8::splat(-0.0),
            "splat",
            &[0.0; 8],
            &[0.0; 8],
        );
        same(
            Avx2::ZERO + Avx2::ONE,
            f32x8::ONE,
            "consts",
            &[0.0; 8],
            &[0.0; 8],
        );
    }
}
