//! The environment map's texels in memory: four bytes per texel where that loses nothing,
//! else three `f32`.
//!
//! Why: mirror rays look anywhere in the map, so a sky lookup in the spheres scene is a cache
//! miss or two (`docs/benchmarks/profile.md`). A 2048 x 1024 map in
//! `f32` is 25 MB, larger than the last-level cache of the machines the suite is timed on;
//! packed it is 8 MB, and a bilinear lookup's four texels span 16 bytes instead of 48.
//!
//! **Packed** (the Radiance `.hdr` maps, whose decoder gives `m 2^k` with an 8-bit `m` per
//! channel and one `k` per texel): one `u32` per texel, the channels' mantissas `m` in its
//! three low bytes and `s = k + 149` in its high byte; a channel's value is
//! `m as f32 * scale(s)` with `scale(s) = 2^(s - 149)` (every such power is an `f32`: normal
//! from `s = 23`, subnormal below; values up to `255 x 2^106`, far above
//! [`super::MAX_RADIANCE`]). A map is packed only if every texel decodes to exactly its `f32`
//! bits (checked texel by texel at load), so the lookups, and the pictures, are the same to the
//! bit as from the `f32` texels. Any other map (OpenEXR's half floats, repaired values, `-0.0`)
//! stays in `f32`.

use crate::accel::lanes::{LANES, Lane, Lanes};
use glam::Vec3;
use rayon::prelude::*;

/// A vector per lane.
type V3<L = Lane> = [L; 3];

#[derive(Clone, Debug)]
pub(super) enum Texels {
    /// Three floats (r, g, b) per texel, row-major.
    Floats(Vec<f32>),
    /// One word per texel, row-major (module docs).
    Packed(Vec<u32>),
}

/// `2^(s - 149)`, exactly.
#[inline(always)]
fn scale(s: u32) -> f32 {
    if s >= 23 {
        f32::from_bits((s - 22) << 23)
    } else {
        f32::from_bits(1 << s)
    }
}

/// The texel a packed word holds.
#[inline(always)]
fn decode(word: u32) -> [f32; 3] {
    let s = scale(word >> 24);
    [0, 8, 16].map(|shift| ((word >> shift) & 0xff) as f32 * s)
}

/// A non-negative finite `f32` as `(n, e)` with value `n 2^e`, `n` below 2^24 (`-0.0` and
/// the others: `None`).
#[inline(always)]
fn integer_and_exponent(c: f32) -> Option<(u32, i32)> {
    let bits = c.to_bits();
    let biased = (bits >> 23) as i32;
    // Sign clear and below infinity's exponent.
    if biased >= 255 {
        return None;
    }
    let fraction = bits & 0x7f_ffff;
    match biased {
        0 => Some((fraction, -149)),
        _ => Some((fraction | 1 << 23, biased - 150)),
    }
}

/// The word that decodes to exactly `t`'s bits, if there is one: integer arithmetic on the
/// floats' bits (a division and `fract` per channel made loading a map 0.2 s slower).
fn encode(t: &[f32]) -> Option<u32> {
    let largest = t[0].max(t[1]).max(t[2]);
    let (n, e) = integer_and_exponent(largest)?;
    // The least k for which the largest channel's m = c 2^-k stays below 256: its top bit at 7.
    let k = match n {
        0 => -149,
        n => (e + (31 - n.leading_zeros() as i32) - 7).max(-149),
    };
    let s = u32::try_from(k + 149).ok().filter(|&s| s <= 255)?;
    let mut word = s << 24;
    for (c, shift) in t.iter().zip([0, 8, 16]) {
        let (n, e) = integer_and_exponent(*c)?;
        // m = n 2^(e - k): whole, below 256.
        let m = match e - k {
            up @ 0..=7 => n.checked_shl(up as u32).filter(|&m| m >> up == n)?,
            0.. => (n == 0).then_some(0)?,
            down if down > -32 => {
                let drop = (-down) as u32;
                (n & ((1 << drop) - 1) == 0).then_some(n >> drop)?
            }
            _ => (n == 0).then_some(0)?,
        };
        if m > 255 {
            return None;
        }
        word |= m << shift;
    }
    // The decoded bits, checked (`-0.0` never gets here; this is the contract).
    let same = decode(word)
        .iter()
        .zip(t)
        .all(|(a, b)| a.to_bits() == b.to_bits());
    same.then_some(word)
}

impl Texels {
    /// Row-major texels, three floats each, packed where every texel packs exactly.
    pub(super) fn new(floats: Vec<f32>) -> Self {
        // In parts shared between the threads, each packed by a plain loop.
        const PART: usize = 1 << 14;
        let mut words = vec![0u32; floats.len() / 3];
        let packed = words
            .par_chunks_mut(PART)
            .zip(floats.par_chunks(3 * PART))
            .all(|(words, floats)| {
                for (word, t) in words.iter_mut().zip(floats.chunks_exact(3)) {
                    match encode(t) {
                        Some(w) => *word = w,
                        None => return false,
                    }
                }
                true
            });
        match packed {
            true => Texels::Packed(words),
            false => Texels::Floats(floats),
        }
    }

    /// Texel `i` (row-major).
    #[inline(always)]
    pub(super) fn get(&self, i: usize) -> Vec3 {
        match self {
            Texels::Floats(f) => Vec3::from_slice(&f[3 * i..3 * i + 3]),
            Texels::Packed(w) => Vec3::from_array(decode(w[i])),
        }
    }

    /// Every texel value, three per texel (tests).
    #[cfg(test)]
    pub(super) fn floats(&self) -> Vec<f32> {
        match self {
            Texels::Floats(f) => f.clone(),
            Texels::Packed(w) => w.iter().flat_map(|&w| decode(w)).collect(),
        }
    }

    /// The texels at `at[corner][lane]` for the lanes of `live`, per corner and channel in
    /// lanes; zero in the other lanes.
    #[inline(always)]
    pub(super) fn gather<L: Lanes>(&self, at: &[[usize; LANES]; 4], live: u32) -> [V3<L>; 4] {
        let live_lanes = (0..LANES).filter(|i| live & (1 << i) != 0);
        match self {
            Texels::Floats(f) => {
                let mut t = [[[0.0f32; LANES]; 3]; 4];
                for i in live_lanes {
                    for (corner, at) in t.iter_mut().zip(at) {
                        let texel = &f[3 * at[i]..3 * at[i] + 3];
                        for (ch, value) in corner.iter_mut().zip(texel) {
                            ch[i] = *value;
                        }
                    }
                }
                t.map(|corner| corner.map(L::new))
            }
            Texels::Packed(w) => {
                // A dead lane's word: m = 0 at a normal scale, zero in every channel.
                let mut words = [[f32::from_bits(23 << 24); LANES]; 4];
                for i in live_lanes {
                    for (corner, at) in words.iter_mut().zip(at) {
                        corner[i] = f32::from_bits(w[at[i]]);
                    }
                }
                // Not `map`, whose closure is not always inlined into the AVX2 entry.
                let corner = |c: usize| decode_lanes(L::new(words[c]));
                [corner(0), corner(1), corner(2), corner(3)]
            }
        }
    }
}

/// [`decode`] in lanes, on the words' bits (read as `f32`): the same products, so the same bits.
#[inline(always)]
fn decode_lanes<L: Lanes>(word: L) -> V3<L> {
    let byte = L::splat_bits(0xff);
    let s = word.shr::<24>();
    let scale = if s.int_gt(L::splat_bits(22)).all() {
        s.int_add(L::splat_bits(-22i32 as u32)).shl::<23>()
    } else {
        L::new(s.to_array().map(|s| scale(s.to_bits())))
    };
    let channel = |m: L| (m & byte).int_to_float() * scale;
    [
        channel(word),
        channel(word.shr::<8>()),
        channel(word.shr::<16>()),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hash::{hash, unit_f32};

    /// What `image`'s Radiance decoder gives for the bytes `(r, g, b, e)`.
    fn rgbe(c: [u8; 3], e: u8) -> [f32; 3] {
        if e == 0 {
            return [0.0; 3];
        }
        // `ldexp(1, e - 136)`: the scale of s = e + 13.
        let unit = scale(u32::from(e) + 13);
        c.map(|c| unit * f32::from(c))
    }

    #[test]
    fn every_rgbe_texel_packs_and_decodes_to_its_bits() {
        let mut texels = vec![[0.0f32; 3]];
        // Every exponent up to 2^106 scales (values to 255 x 2^106, far above MAX_RADIANCE).
        for e in 1..=242u8 {
            for i in 0..64u64 {
                let h = hash(20, &[u64::from(e), i]);
                let mut c = [h as u8, (h >> 8) as u8, (h >> 16) as u8];
                if i % 2 == 0 {
                    c[(h >> 24) as usize % 3] |= 0x80; // as encoders write them: normalised
                }
                texels.push(rgbe(c, e));
            }
        }
        for t in texels {
            let word = encode(&t).unwrap_or_else(|| panic!("{t:?} does not pack"));
            assert_eq!(decode(word).map(f32::to_bits), t.map(f32::to_bits), "{t:?}");
        }
    }

    /// [`encode`] by its definition, in f64 (exact: values a power of two apart).
    fn encode_by_division(t: &[f32]) -> Option<u32> {
        let largest = t[0].max(t[1]).max(t[2]);
        if !(largest.is_finite() && largest >= 0.0) {
            return None;
        }
        (0..=255u32).find_map(|s| {
            let unit = f64::from(scale(s));
            let m = [t[0], t[1], t[2]].map(|c| f64::from(c) / unit);
            let whole = m
                .iter()
                .all(|m| m.fract() == 0.0 && (0.0..256.0).contains(m));
            let word = whole.then(|| {
                s << 24
                    | m.iter()
                        .zip([0, 8, 16])
                        .map(|(m, sh)| (*m as u32) << sh)
                        .sum::<u32>()
            })?;
            let same = decode(word)
                .iter()
                .zip(t)
                .all(|(a, b)| a.to_bits() == b.to_bits());
            same.then_some(word)
        })
    }

    #[test]
    fn encoding_by_the_bits_is_encoding_by_division() {
        for i in 0..20_000u64 {
            let h = hash(25, &[i]);
            let bits = |k: u32| (h >> k) as u32;
            let t: [f32; 3] = match i % 3 {
                0 => [0, 21, 42].map(|k| f32::from_bits(bits(k))),
                1 => rgbe([h as u8, (h >> 8) as u8, (h >> 16) as u8], (h >> 24) as u8),
                _ => [0, 10, 20].map(|k| ((h >> k) & 0x3ff) as f32 * scale(bits(40) & 0xff)),
            };
            assert_eq!(encode(&t), encode_by_division(&t), "{t:?}");
        }
    }

    #[test]
    fn values_an_8_bit_mantissa_cannot_hold_stay_floats() {
        for t in [
            [1e6, 0.0, 0.0], // 15625 x 2^6
            [1.0, 1.0 / 3.0, 0.0],
            [256.0, 1.0, 0.0], // 1 would need k = 0, 256 needs k >= 1
            [-0.0, 1.0, 1.0],  // decodes to +0.0
            [f32::NAN, 1.0, 1.0],
            [f32::INFINITY, 1.0, 1.0],
            [1.0, 0.5 + 2f32.powi(-10), 0.0],
        ] {
            assert_eq!(encode(&t), None, "{t:?}");
        }
        let mut floats = vec![1.0, 2.0, 4.0, 0.5, 0.25, 0.0];
        assert!(matches!(Texels::new(floats.clone()), Texels::Packed(_)));
        floats[4] = 0.3;
        let t = Texels::new(floats.clone());
        assert!(matches!(t, Texels::Floats(_)));
        assert_eq!(t.floats(), floats);
    }

    #[test]
    fn gather_in_lanes_is_get_to_the_bit_in_both_forms() {
        // Tiny values (subnormal scales) in some texels: the lanes' slow scale path too.
        let floats: Vec<f32> = (0..64u64)
            .flat_map(|i| {
                let e = match i % 7 {
                    0 => 3,
                    _ => 100 + (hash(21, &[i]) % 60) as u8,
                };
                rgbe([(hash(22, &[i]) as u8) | 0x80, 7, 200], e)
            })
            .collect();
        let packed = Texels::new(floats.clone());
        assert!(matches!(packed, Texels::Packed(_)));
        let mut plain = floats.clone();
        plain[0] = 0.3;
        let plain = Texels::new(plain);
        for texels in [&packed, &plain] {
            for n in 0..200u64 {
                let at: [[usize; LANES]; 4] = std::array::from_fn(|c| {
                    std::array::from_fn(|i| (hash(23, &[n, c as u64, i as u64]) % 64) as usize)
                });
                let live = (unit_f32(hash(24, &[n])) * 256.0) as u32 & 0xff;
                for &width in crate::simd::widths() {
                    let got = crate::simd::run_in(width, Gather(texels, &at, live));
                    check(texels, &got, &at, live);
                }
            }
        }
    }

    /// [`Texels::gather`] in the lanes it is run in.
    struct Gather<'a>(&'a Texels, &'a [[usize; LANES]; 4], u32);

    impl crate::simd::Kernel for Gather<'_> {
        type Output = [[[f32; LANES]; 3]; 4];
        #[inline(always)]
        fn run<L: Lanes>(self) -> Self::Output {
            self.0
                .gather::<L>(self.1, self.2)
                .map(|c| c.map(L::to_array))
        }
    }

    /// `got` (corner, channel, lane) is [`Texels::get`] at `at`'s texels in the lanes of
    /// `live`, zero in the others, to the bit.
    fn check(texels: &Texels, got: &[[[f32; LANES]; 3]; 4], at: &[[usize; LANES]; 4], live: u32) {
        for (corner, at) in got.iter().zip(at) {
            for (i, &at) in at.iter().enumerate() {
                let want = match live & (1 << i) {
                    0 => Vec3::ZERO,
                    _ => texels.get(at),
                };
                let have = Vec3::from_array(corner.map(|l| l[i]));
                assert_eq!(
                    have.to_array().map(f32::to_bits),
                    want.to_array().map(f32::to_bits)
                );
            }
        }
    }
}
