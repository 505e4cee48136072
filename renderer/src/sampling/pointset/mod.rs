//! Point sets: N points in the unit cube [0, 1)^d, d = 1, 2 or 3 (thesis Chapter II "Point
//! Sets for Sampling"). Each set is one file implementing [`PointSet`]; adding a set means
//! adding a file and one entry to [`ALL`].
//!
//! Sets are made once per frame or once per sequence from a seed (never per pixel); the pixel
//! shift then decorrelates pixels. Three dimensions are (u, v, t); two are (u, v); one is t.

mod halton;
mod hammersley;
mod poisson;
pub(crate) mod radical_inverse;
mod random;
mod sobol;
mod stratified;

pub use halton::Halton;
pub use hammersley::Hammersley;
pub use poisson::{Poisson, PoissonSet};
pub use radical_inverse::radical_inverse;
pub use random::Random;
pub use sobol::Sobol;
pub use stratified::Stratified;

use crate::condition::PointSetKind;
use anyhow::{Result, bail};

/// The most points a set may have: [`crate::limits::MAX_SPP`].
pub const MAX_POINTS: usize = crate::limits::MAX_SPP as usize;

/// The largest double below 1: where coordinates that round up to 1 are put back.
const BELOW_ONE: f64 = 1.0 - f64::EPSILON / 2.0;

/// A family of point sets.
pub trait PointSet: Sync {
    /// The name used in scene and job files.
    fn name(&self) -> &'static str;
    /// One line for help texts.
    fn summary(&self) -> &'static str;
    /// Whether `n` points in `dims` dimensions can be made; the error explains why not.
    fn check(&self, _n: usize, _dims: usize) -> std::result::Result<(), String> {
        Ok(())
    }
    /// `n` points in `dims` dimensions from `seed` (the same arguments give the same points).
    /// Called only after [`PointSet::check`] passed, with 1 <= n <= MAX_POINTS, 1 <= dims <= 3.
    fn generate(&self, n: usize, dims: usize, seed: u64) -> Points;
    /// Whether the set has a per-pixel scramble ([`PointSet::scrambled`]); a set without one
    /// keeps the shift under `randomization: scramble` (docs/sampling.md).
    fn scrambles(&self) -> bool {
        false
    }
    /// Point `i` of one pixel's own scrambled copy of the `n`-point set in `dims` dimensions,
    /// keyed by `key` (coordinates past `dims` are 0). Every key gives a set with the strata of
    /// the unscrambled one, each point uniform on the cube (`crate::sampling::scramble`).
    /// Called only when [`PointSet::scrambles`] and after [`PointSet::check`] passed.
    fn scrambled(&self, _n: usize, _dims: usize, _i: usize, _key: u64) -> [f64; 3] {
        unreachable!("{} has no per-pixel scramble", self.name())
    }
}

/// `coord(d)` for d < dims, 0 past them.
#[inline]
pub(crate) fn coords(dims: usize, mut coord: impl FnMut(usize) -> f64) -> [f64; 3] {
    let mut out = [0.0; 3];
    for (d, c) in out.iter_mut().enumerate().take(dims) {
        *c = coord(d);
    }
    out
}

/// Every point set, in the order help texts list them.
pub const ALL: &[&dyn PointSet] = &[&Random, &Stratified, &Hammersley, &Poisson, &Sobol, &Halton];

/// The point set `kind` names.
pub fn of(kind: PointSetKind) -> &'static dyn PointSet {
    match kind {
        PointSetKind::Random => &Random,
        PointSetKind::Stratified => &Stratified,
        PointSetKind::Hammersley => &Hammersley,
        PointSetKind::Poisson => &Poisson,
        PointSetKind::Sobol => &Sobol,
        PointSetKind::Halton => &Halton,
    }
}

/// The point set called `name`; the error lists the known names.
pub fn by_name(name: &str) -> Result<&'static dyn PointSet> {
    Ok(of(name.parse()?))
}

/// `n` points of `set` in `dims` dimensions, after checking every constraint.
pub fn generate(set: &dyn PointSet, n: usize, dims: usize, seed: u64) -> Result<Points> {
    if !(1..=3).contains(&dims) {
        bail!("point sets have 1 to 3 dimensions, not {dims}");
    }
    if n == 0 {
        bail!("a point set needs at least 1 point");
    }
    if n > MAX_POINTS {
        bail!(
            "{n} points requested; at most {MAX_POINTS} samples per pixel are supported (the \
             limit of Owen-scrambled Sobol)"
        );
    }
    set.check(n, dims).map_err(|e| anyhow::anyhow!("{e}"))?;
    let p = set.generate(n, dims, seed);
    debug_assert_eq!((p.len(), p.dims()), (n, dims));
    Ok(p)
}

/// N points in [0, 1)^d, stored flat.
#[derive(Clone, Debug, PartialEq)]
pub struct Points {
    dims: usize,
    coords: Vec<f64>,
}

impl Points {
    /// Build from `coord(i, d)`; every coordinate is checked finite and kept below 1 (a
    /// computation like (k + jitter) / n can round up to exactly 1).
    pub fn from_fn(n: usize, dims: usize, mut coord: impl FnMut(usize, usize) -> f64) -> Self {
        let mut coords = Vec::with_capacity(n * dims);
        for i in 0..n {
            for d in 0..dims {
                let c = coord(i, d);
                assert!(
                    (0.0..=1.0).contains(&c),
                    "point set coordinate {c} out of [0, 1]"
                );
                coords.push(c.min(BELOW_ONE));
            }
        }
        Self { dims, coords }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.coords.len() / self.dims.max(1)
    }

    pub fn is_empty(&self) -> bool {
        self.coords.is_empty()
    }

    pub fn dims(&self) -> usize {
        self.dims
    }

    /// Point `i`'s coordinates.
    pub fn get(&self, i: usize) -> &[f64] {
        &self.coords[i * self.dims..(i + 1) * self.dims]
    }

    pub fn iter(&self) -> impl Iterator<Item = &[f64]> {
        self.coords.chunks_exact(self.dims)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_set_fills_the_unit_cube_reproducibly_in_every_dimension() {
        for set in ALL {
            for dims in 1..=3 {
                let n = 64; // a cube, a square and a line count for stratified
                let a = generate(*set, n, dims, 5).unwrap();
                assert_eq!((a.len(), a.dims()), (n, dims), "{}", set.name());
                assert!(a.iter().flatten().all(|c| (0.0..1.0).contains(c)));
                assert_eq!(a, generate(*set, n, dims, 5).unwrap(), "{}", set.name());
            }
        }
    }

    #[test]
    fn every_kind_names_its_set_in_the_same_order() {
        for (kind, set) in PointSetKind::ALL.into_iter().zip(ALL) {
            assert_eq!(of(kind).name(), kind.name());
            assert_eq!(set.name(), kind.name());
        }
        assert_eq!(PointSetKind::ALL.len(), ALL.len());
    }

    #[test]
    fn seeded_sets_change_with_the_seed() {
        for set in ALL.iter().filter(|s| s.name() != "hammersley") {
            let a = generate(*set, 27, 3, 1).unwrap();
            let b = generate(*set, 27, 3, 2).unwrap();
            assert_ne!(a, b, "{}", set.name());
        }
    }

    #[test]
    fn bad_requests_are_explained() {
        let e = by_name("stratifiedmc").err().unwrap().to_string();
        assert!(e.contains("stratified, hammersley"), "{e}");
        assert!(generate(&Random, 0, 3, 0).is_err());
        assert!(generate(&Random, MAX_POINTS + 1, 3, 0).is_err());
        assert!(generate(&Random, 8, 4, 0).is_err());
        assert_eq!(
            generate(&Random, MAX_POINTS, 1, 0).unwrap().len(),
            MAX_POINTS
        );
    }

    #[test]
    fn coordinates_that_round_up_to_one_are_kept_below_it() {
        let p = Points::from_fn(1, 1, |_, _| 1.0);
        assert!(p.get(0)[0] < 1.0);
    }
}
