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

    fn scrambled(&self, _n: usize, dims: usize, i: usize, key: u64) -> [f64; 3] {
        let seed = fold(key);
        super::coords(dims, |d| {
            sobol_burley::sample(i as u32, d as u32, seed) as f64
        })
    }
}

/// The crate's 32-bit seed from ours.
#[inline]
fn fold(seed: u64) -> u32 {
    (seed ^ (seed >> 32)) as u32
}
