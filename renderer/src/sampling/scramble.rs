//! Per-pixel scrambling (`randomization: scramble`): instead of rotating the frame's point set
//! by a per-pixel offset (the thesis's Cranley-Patterson shift, [`super::shift`]), every pixel
//! gets its own randomized copy of the set that keeps the set's strata.
//!
//! The shift wraps the pixel's stratum grid: a stratum that straddles the wrap is cut in two
//! pieces at opposite edges of the pixel, so the pixel border acts as a second discontinuity of
//! the integrand. A nested uniform scramble (Owen 1995) permutes strata instead of translating
//! them: a point stays in a stratum of the same size, and every elementary interval of the set
//! keeps its number of points.
//!
//! Owen's scramble of a base-b fraction x = Σ_{k≥1} a_k b^-k (Owen 1995, "Randomly permuted
//! (t, m, s)-nets and (t, s)-sequences", eq. (2)-(3)):
//!
//! ```text
//!     y = Σ_{k≥1} π_{a_1 ... a_{k-1}}(a_k) b^-k
//! ```
//!
//! with an independent uniform random permutation π of {0, ..., b-1} for every prefix
//! a_1 ... a_{k-1}. Points that share their first k digits (one b-adic interval of length
//! b^-k) still share them after scrambling, and each scrambled point is uniform on [0, 1).
//!
//! Here, one scramble per pixel and coordinate, keyed by a hash of the pixel (counter-based
//! randomness, `crate::hash`):
//!
//! - base 2 ([`owen_base2`]): the hash-based scramble of Laine and Karras (2011, "Stratified
//!   sampling for stochastic transparency") in Burley's form (2020, "Practical Hash-based Owen
//!   Scrambling", JCGT 9(4)): reverse the bits so that a_1 is the lowest bit, apply a
//!   permutation of 32-bit words in which bit k changes only as a function of bits 0..k-1 and
//!   the seed (an addition and x ^= x·c with even c both have that property: carries and
//!   products only move information towards higher bits), reverse back;
//! - other bases ([`owen_radical_inverse`]): the formula above written out, one hashed
//!   permutation per digit, the hash keyed by the prefix (a tree of node keys: the child of
//!   node h for digit a is mix(h, a)), for the D = ⌈log_b N⌉ digits that tell the set's N
//!   points apart, then the rest uniform: below depth D every node of the tree is reached by
//!   one point only, so the permutations of its remaining digits (all 0) are independent of
//!   every other point's, and they make the tail a uniform point of its interval of length
//!   b^-D. (Permuting those zeros one by one, as a first version did to 2^-24, gives the same
//!   distribution at 5-8 times the cost.)
//!
//! What `scramble` means for each point set is listed in `docs/sampling.md` ("Per-pixel
//! randomization"); the sets implement it in `PointSet::scrambled`.

use super::pointset::radical_inverse::permute;
use crate::hash;

const GOLDEN: u64 = 0x9e37_79b9_7f4a_7c15;

/// Laine-Karras permutation of a bit-reversed 32-bit fraction (Burley 2020, Listing 1; the
/// constants are the paper's). Bit k of the result depends only on bits 0..=k of `x` and the
/// seed, and bit k itself is flipped or not: a nested scramble in the reversed domain.
#[inline]
pub fn laine_karras_permutation(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x
}

/// Nested uniform (Owen) scramble of the 32-digit binary fraction x / 2^32 (Burley 2020,
/// `nested_uniform_scramble`): reverse, permute, reverse.
#[inline]
pub fn owen_base2(x: u32, seed: u32) -> u32 {
    laine_karras_permutation(x.reverse_bits(), seed).reverse_bits()
}

/// x / 2^32 as a double.
#[inline]
pub fn fraction(x: u32) -> f64 {
    x as f64 * (1.0 / 4_294_967_296.0)
}

/// The base-2 fixed-point form floor(x 2^32) of i / n (exact when n is a power of two).
#[inline]
pub fn fixed_ratio(i: usize, n: usize) -> u32 {
    (((i as u64) << 32) / n as u64) as u32
}

/// The key of coordinate `d` of a pixel's scramble.
#[inline]
pub fn axis_key(key: u64, d: usize) -> u64 {
    hash::mix64(key ^ GOLDEN.wrapping_mul(d as u64 + 1))
}

/// The Owen-scrambled radical inverse of point `i` of a set of `n` points (`i < n`) in `base`
/// under `key`: Owen's formula for φ_b(i) = Σ a_k b^-k, with a_k the k-th digit of i from
/// the least significant, over the D = ⌈log_b n⌉ digits the set's points differ in, then a
/// uniform tail of length b^-D (the module notes say why that is the same scramble).
pub fn owen_radical_inverse(base: u32, mut i: u32, n: u32, key: u64) -> f64 {
    debug_assert!(i < n.max(1), "point {i} of a set of {n}");
    let b = base as u64;
    let inv = 1.0 / base as f64;
    let (mut scale, mut value, mut node) = (inv, 0.0, key);
    // `interval`: b^k after k digits; the points share no interval of length b^-D.
    let mut interval = 1u64;
    while interval < n as u64 {
        let a = (i % base) as u64;
        i /= base;
        value += permute(a, b, node) as f64 * scale;
        // The child node of this prefix for digit a.
        node = hash::mix64(node ^ GOLDEN.wrapping_mul(a + 2));
        scale *= inv;
        interval *= b;
    }
    // scale is now b^-(D+1); the tail is uniform over the last interval, of length b^-D.
    let tail = hash::unit_f64(hash::mix64(node ^ 0x7a11)) * scale * base as f64;
    (value + tail).min(1.0 - f64::EPSILON / 2.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::ks::{ks_critical, ks_statistic};

    #[test]
    fn the_base_2_scramble_is_nested() {
        // Two fractions sharing their first k binary digits share the first k digits of their
        // scrambles, and the (k+1)-th digit is permuted: different stays different.
        for seed in [0u32, 1, 0xdead_beef, u32::MAX] {
            for (x, y) in [
                (0x1234_5678u32, 0x1234_ffffu32),
                (0x8000_0000, 0x8000_0001),
                (0, 1),
            ] {
                let k = (x ^ y).leading_zeros();
                let (sx, sy) = (owen_base2(x, seed), owen_base2(y, seed));
                assert_eq!((sx ^ sy).leading_zeros(), k, "{x:#x} {y:#x} seed {seed:#x}");
            }
        }
    }

    #[test]
    fn scrambled_fractions_are_uniform_and_fill_every_interval() {
        // 4096 seeds scrambling the same fraction (0): each result should be uniform. KS at
        // α = 0.001 (critical D = 1.95/sqrt(4096) = 0.030).
        for base in [2u32, 3, 5] {
            let mut v: Vec<f64> = (0..4096u64)
                .map(|s| match base {
                    2 => fraction(owen_base2(0, hash::hash(s, &[]) as u32)),
                    _ => owen_radical_inverse(base, 0, 1 + s as u32 % 100, hash::hash(s, &[])),
                })
                .collect();
            let d = ks_statistic(&mut v, |x| x);
            assert!(d < ks_critical(4096, 0.001), "base {base}: D = {d}");
        }
        // The first b^m radical inverses hold one point in each interval [j/b^m, (j+1)/b^m):
        // still true after the scramble.
        for (base, m) in [(3u32, 5u32), (5, 3)] {
            let n = base.pow(m);
            for key in [1u64, 99] {
                let mut seen = vec![false; n as usize];
                for i in 0..n {
                    let j = (owen_radical_inverse(base, i, n, key) * n as f64) as usize;
                    assert!(
                        !std::mem::replace(&mut seen[j], true),
                        "base {base}: {j} twice"
                    );
                }
            }
        }
    }
}
