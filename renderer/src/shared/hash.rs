//! Counter-based randomness (the suite's determinism rule).
//!
//! Every random choice is a pure function of a master seed and the choice's coordinates
//! (job, stimulus, frame, pixel, sample; subject, trial), never a draw from a shared sequential
//! generator. Output therefore does not depend on thread count, work order or how a job is split.

/// SplitMix64's finalizer: a bijective 64-bit mixer with good avalanche.
#[inline]
pub fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

const GOLDEN: u64 = 0x9e37_79b9_7f4a_7c15;

/// Hash a seed and a list of coordinates into 64 random-looking bits.
#[inline]
pub fn hash(seed: u64, coords: &[u64]) -> u64 {
    let mut h = mix64(seed ^ GOLDEN);
    for (i, &c) in coords.iter().enumerate() {
        h = mix64(h ^ mix64(c.wrapping_add(GOLDEN.wrapping_mul(i as u64 + 2))));
    }
    h
}

/// A stable 64-bit id for a name (FNV-1a then mixed), for using strings as coordinates.
pub fn name_id(name: &str) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in name.bytes() {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    mix64(h)
}

/// The top 53 bits as a double in [0, 1).
#[inline]
pub fn unit_f64(h: u64) -> f64 {
    (h >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// The top 24 bits as a float in [0, 1) (exactly representable, never rounds up to 1).
#[inline]
pub fn unit_f32(h: u64) -> f32 {
    (h >> 40) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// A `rand` generator whose n-th output is `hash(key, [n])`: use it where an algorithm wants an
/// `Rng` (shuffles, distributions) but the stream must be keyed by coordinates.
#[derive(Clone, Debug)]
pub struct HashRng {
    key: u64,
    counter: u64,
}

impl HashRng {
    /// A generator keyed by a seed and coordinates.
    pub fn new(seed: u64, coords: &[u64]) -> Self {
        Self {
            key: hash(seed, coords),
            counter: 0,
        }
    }
}

impl rand::RngCore for HashRng {
    fn next_u32(&mut self) -> u32 {
        (self.next_u64() >> 32) as u32
    }
    fn next_u64(&mut self) -> u64 {
        let v = hash(self.key, &[self.counter]);
        self.counter += 1;
        v
    }
    fn fill_bytes(&mut self, dst: &mut [u8]) {
        for chunk in dst.chunks_mut(8) {
            let v = self.next_u64().to_le_bytes();
            chunk.copy_from_slice(&v[..chunk.len()]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coordinates_change_the_hash() {
        assert_ne!(hash(1, &[0, 1]), hash(1, &[1, 0]));
        assert_ne!(hash(1, &[0]), hash(2, &[0]));
        assert_ne!(hash(1, &[0]), hash(1, &[0, 0]));
        assert_eq!(hash(7, &[3, 4]), hash(7, &[3, 4]));
    }

    #[test]
    fn unit_values_stay_below_one() {
        assert!(unit_f32(u64::MAX) < 1.0);
        assert!(unit_f64(u64::MAX) < 1.0);
        assert_eq!(unit_f32(0), 0.0);
    }

    #[test]
    fn unit_values_are_uniform_in_mean_and_variance() {
        // 100k draws: the mean's standard error is sqrt(1/12/1e5) ~ 9.1e-4; allow 5 sigma.
        let n = 100_000;
        let xs: Vec<f64> = (0..n).map(|i| unit_f64(hash(42, &[i]))).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
        assert!((mean - 0.5).abs() < 5.0 * 9.1e-4, "mean {mean}");
        assert!((var - 1.0 / 12.0).abs() < 0.002, "var {var}");
    }
}
