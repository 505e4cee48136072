//! Stratified Monte Carlo, also called jittered grid (Cook 1986; thesis Chapter II): the cube is
//! cut into n^d equal cells and each cell holds one uniformly placed point.

use super::{PointSet, Points};
use crate::hash;
use crate::sampling::scramble::axis_key;

/// One jittered point per cell of an n x ... x n grid; needs N = n^d.
pub struct Stratified;

/// The integer `k` with `k^dims == n`, if there is one.
pub fn exact_root(n: usize, dims: usize) -> Option<usize> {
    let guess = (n as f64).powf(1.0 / dims as f64).round() as usize;
    (guess.saturating_sub(1)..=guess + 1).find(|k| k.checked_pow(dims as u32) == Some(n))
}

/// The perfect `dims`-th powers just below and just above `n` (the lower one is at least 1).
fn nearest_powers(n: usize, dims: usize) -> (usize, usize) {
    let mut k = 1usize;
    while (k + 1).pow(dims as u32) <= n {
        k += 1;
    }
    (k.pow(dims as u32), (k + 1).pow(dims as u32))
}

impl PointSet for Stratified {
    fn name(&self) -> &'static str {
        "stratified"
    }

    fn summary(&self) -> &'static str {
        "jittered grid, one random point per cell (N must be n^3; n^2 for a spatial set)"
    }

    fn check(&self, n: usize, dims: usize) -> Result<(), String> {
        if exact_root(n, dims).is_some() {
            return Ok(());
        }
        let (lo, hi) = nearest_powers(n, dims);
        let what = if dims == 2 { "square" } else { "cube" };
        Err(format!(
            "stratified sampling in {dims}D needs a {what} number of samples, not {n}; \
             nearest {what}s are {lo} and {hi}"
        ))
    }

    fn generate(&self, n: usize, dims: usize, seed: u64) -> Points {
        let k = exact_root(n, dims).expect("checked before generating");
        Points::from_fn(n, dims, |i, d| coordinate(k, seed, i, d, 0))
    }

    /// A pixel's own jittered grid: the cells relabelled along each axis by a random cyclic
    /// offset (cell c -> (c + r_d) mod k, a permutation of the cell digit in base k, so each
    /// point's cell, and the point, is uniform) and every point re-jittered inside its cell by
    /// the pixel's key. One point per cell, always; the set is a fresh jittered grid.
    fn scrambles(&self) -> bool {
        true
    }

    fn scrambled(&self, n: usize, dims: usize, i: usize, key: u64) -> [f64; 3] {
        let k = exact_root(n, dims).expect("checked before scrambling");
        super::coords(dims, |d| {
            let offset = (axis_key(key, d) % k as u64) as usize;
            coordinate(k, key, i, d, offset)
        })
    }
}

/// Coordinate d of point i of a k^dims jittered grid whose cells along d are relabelled by
/// `offset`.
#[inline]
fn coordinate(k: usize, seed: u64, i: usize, d: usize, offset: usize) -> f64 {
    // Cell index of point i along axis d: digit d of i in base k.
    let cell = ((i / k.pow(d as u32)) + offset) % k;
    let jitter = hash::unit_f64(hash::hash(seed, &[i as u64, d as u64]));
    (cell as f64 + jitter) / k as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    #[test]
    fn exactly_one_point_per_cell() {
        for (n, dims) in [(1, 3), (8, 3), (27, 3), (125, 3), (512, 3), (64, 2), (7, 1)] {
            let k = exact_root(n, dims).unwrap();
            let p = Stratified.generate(n, dims, 3);
            let cells: BTreeSet<Vec<usize>> = p
                .iter()
                .map(|x| x.iter().map(|c| (c * k as f64) as usize).collect())
                .collect();
            assert_eq!(cells.len(), n, "n={n} dims={dims}: a cell holds two points");
            assert!(cells.iter().flatten().all(|&c| c < k));
        }
    }

    #[test]
    fn non_cubes_name_the_nearest_cubes() {
        let e = Stratified.check(100, 3).unwrap_err();
        assert!(e.contains("cube") && e.contains("64 and 125"), "{e}");
        let e = Stratified.check(1000 - 1, 3).unwrap_err();
        assert!(e.contains("729 and 1000"), "{e}");
        let e = Stratified.check(10, 2).unwrap_err();
        assert!(e.contains("square") && e.contains("9 and 16"), "{e}");
        assert!(Stratified.check(1000, 3).is_ok());
        assert!(Stratified.check(13, 1).is_ok());
        assert_eq!(exact_root(4096, 3), Some(16));
        assert_eq!(exact_root(4097, 3), None);
    }
}
