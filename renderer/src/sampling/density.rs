//! How the samples of a pixel split between space and time. The thesis sampled (u, v, t) with
//! one 3D set of N points, an equal density on every axis; its future work asks whether space
//! or time matters more. `Temporal(K)` / `Spatial(K)` answer that with a product set: every
//! point of a 2D (u, v) set of N/K (or K) points is paired with every point of a 1D t set of K
//! (or N/K) points, so the pixel sees exactly that many distinct positions and times.

use super::config::Density;
use super::pointset::{self, PointSet};
use crate::hash;
use anyhow::{Context, Result, bail};

/// The (u, v, t) points of one pixel pattern: `spp` points of `set` split by `density`, keyed
/// by `key`. Sample i of a product set is spatial point i / N_t with temporal point i % N_t.
pub fn points(set: &dyn PointSet, spp: usize, density: Density, key: u64) -> Result<Vec<[f64; 3]>> {
    let (spatial, temporal) = match density {
        Density::Joint => {
            let p = pointset::generate(set, spp, 3, key)?;
            return Ok(p.iter().map(|x| [x[0], x[1], x[2]]).collect());
        }
        Density::Temporal(k) => (split(spp, k, "temporal")?, k as usize),
        Density::Spatial(k) => (k as usize, split(spp, k, "spatial")?),
    };
    let uv = pointset::generate(set, spatial, 2, hash::hash(key, &[2]))
        .with_context(|| format!("the spatial set of {spatial} points"))?;
    let t = pointset::generate(set, temporal, 1, hash::hash(key, &[1]))
        .with_context(|| format!("the temporal set of {temporal} points"))?;
    Ok((0..spp)
        .map(|i| {
            let (a, b) = (uv.get(i / temporal), t.get(i % temporal));
            [a[0], a[1], b[0]]
        })
        .collect())
}

/// spp / k when k divides spp; the error names the setting.
fn split(spp: usize, k: u32, axis: &str) -> Result<usize> {
    let k = k as usize;
    if k == 0 || !spp.is_multiple_of(k) {
        bail!(
            "field `density` asks for {k} {axis} samples, which must be at least 1 and divide \
             the {spp} samples per pixel"
        );
    }
    Ok(spp / k)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::pointset::{Hammersley, Stratified};
    use std::collections::BTreeSet;

    fn distinct(p: &[[f64; 3]], axes: std::ops::Range<usize>) -> usize {
        p.iter()
            .map(|x| {
                x[axes.clone()]
                    .iter()
                    .map(|c| c.to_bits())
                    .collect::<Vec<_>>()
            })
            .collect::<BTreeSet<_>>()
            .len()
    }

    #[test]
    fn product_sets_have_the_asked_numbers_of_positions_and_times() {
        let p = points(&Stratified, 512, Density::Temporal(8), 1).unwrap();
        assert_eq!(p.len(), 512);
        assert_eq!((distinct(&p, 0..2), distinct(&p, 2..3)), (64, 8));
        assert_eq!(distinct(&p, 0..3), 512, "every position meets every time");
        let p = points(&Hammersley, 96, Density::Spatial(32), 1).unwrap();
        assert_eq!((distinct(&p, 0..2), distinct(&p, 2..3)), (32, 3));
        let p = points(&Hammersley, 125, Density::Joint, 1).unwrap();
        assert_eq!((distinct(&p, 0..2), distinct(&p, 2..3)), (125, 125));
    }

    #[test]
    fn impossible_splits_are_explained() {
        let e = format!(
            "{:#}",
            points(&Stratified, 100, Density::Temporal(3), 1).unwrap_err()
        );
        assert!(e.contains("`density`") && e.contains("3 temporal"), "{e}");
        let e = format!(
            "{:#}",
            points(&Stratified, 96, Density::Temporal(8), 1).unwrap_err()
        );
        assert!(e.contains("12 points") && e.contains("9 and 16"), "{e}");
        assert!(points(&Stratified, 8, Density::Spatial(0), 1).is_err());
    }
}
