//! Owen-scrambled Sobol points (Burley 2020, via `sobol_burley`): the first N points of a
//! scrambled and shuffled Sobol sequence; a (0, m, 2)-net in every pair of its first dimensions
//! when N is a power of two.

use super::{PointSet, Points};

/// Dimensions 0, 1, 2 of the sequence, seeded by the low 32 bits of the set's seed.
pub struct Sobol;

impl PointSet for Sobol {
    fn name(&self) -> &'static str {
        "sobol"
    }

    fn summary(&self) -> &'static str {
        "Owen-scrambled Sobol (Burley 2020); best at powers of two"
    }

    fn generate(&self, n: usize, dims: usize, seed: u64) -> Points {
        let seed = fold(seed);
        Points::from_fn(n, dims, |i, d| {
            sobol_burley::sample(i as u32, d as u32, seed) as f64
        })
    }

    /// Per pixel: the crate's own Owen scramble (and index shuffle) seeded by the pixel's key,
    /// so every pixel has its own scrambled Sobol set; at N = 2^m dimensions 0 and 1 stay a
    /// (0, m, 2)-net.
    fn scrambles(&self) -> bool {
        true
    }

    /// The four dimensions come from one call of the crate's SIMD `sample_4d`, whose values
    /// are `sample`'s (checked by a test): a third of the cost of three `sample` calls.
    fn scrambled(&self, _n: usize, dims: usize, i: usize, key: u64) -> [f64; 3] {
        let p = sobol_burley::sample_4d(i as u32, 0, fold(key));
        super::coords(dims, |d| p[d] as f64)
    }
}

/// The crate's 32-bit seed from ours.
#[inline]
fn fold(seed: u64) -> u32 {
    (seed ^ (seed >> 32)) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_dimensions_at_once_equal_one_at_a_time() {
        for key in [0u64, 1, 0xdead_beef_cafe, u64::MAX] {
            for i in (0..4096).chain([65_535]) {
                let p = Sobol.scrambled(4096, 3, i, key);
                for (d, c) in p.iter().enumerate() {
                    let one = sobol_burley::sample(i as u32, d as u32, fold(key));
                    assert_eq!(c.to_bits(), (one as f64).to_bits(), "i {i} d {d} key {key}");
                }
            }
        }
    }
}
