//! Independent uniform random points: the plain Monte Carlo baseline.

use super::{PointSet, Points};
use crate::hash;

/// Every coordinate an independent uniform draw keyed by (seed, point, dimension).
pub struct Random;

impl PointSet for Random {
    fn name(&self) -> &'static str {
        "random"
    }

    fn summary(&self) -> &'static str {
        "independent uniform points (plain Monte Carlo)"
    }

    fn generate(&self, n: usize, dims: usize, seed: u64) -> Points {
        Points::from_fn(n, dims, |i, d| coordinate(seed, i, d))
    }

    /// A pixel's own independent random points: the same distribution as a shifted random set.
    fn scrambles(&self) -> bool {
        true
    }

    fn scrambled(&self, _n: usize, dims: usize, i: usize, key: u64) -> [f64; 3] {
        super::coords(dims, |d| coordinate(key, i, d))
    }
}

#[inline]
fn coordinate(seed: u64, i: usize, d: usize) -> f64 {
    hash::unit_f64(hash::hash(seed, &[i as u64, d as u64]))
}
