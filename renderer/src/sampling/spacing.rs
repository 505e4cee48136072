//! Distances in the periodic unit cube: how far apart a point set's points are once the cube
//! wraps around (as it does under the pixel shift), against the best any N points can do.

use super::pointset::Points;

/// Euclidean distance on the torus [0, 1)^d: each axis difference is taken the short way round.
#[inline]
pub fn toroidal_distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| {
            let d = (x - y).abs();
            let d = d.min(1.0 - d);
            d * d
        })
        .sum::<f64>()
        .sqrt()
}

/// The smallest toroidal distance between two of the points (all pairs); `None` below 2 points.
pub fn min_toroidal_distance(p: &Points) -> Option<f64> {
    (0..p.len())
        .flat_map(|i| (i + 1..p.len()).map(move |j| (i, j)))
        .map(|(i, j)| toroidal_distance(p.get(i), p.get(j)))
        .reduce(f64::min)
}

/// d_max = 2 r_max: the distance between neighbours when `n` equal balls are packed as densely
/// as possible into the unit cube of `dims` dimensions (Yuksel 2015, after Lagae and Dutré):
/// ball volume = packing density / n, with densities 1 (1D), π/(2√3) (hexagonal, 2D) and
/// π/(3√2) (FCC, 3D) and ball volumes 2r, πr², 4/3 πr³. So r_max = 1/(2n) in 1D,
/// sqrt(1/(2√3 n)) in 2D and cbrt(1/(4√2 n)) in 3D.
pub fn max_packing_distance(dims: usize, n: usize) -> f64 {
    let n = n as f64;
    let r_max = match dims {
        1 => 1.0 / (2.0 * n),
        2 => (1.0 / (2.0 * 3f64.sqrt() * n)).sqrt(),
        3 => (1.0 / (4.0 * 2f64.sqrt() * n)).cbrt(),
        _ => panic!("packing distance for {dims} dimensions"),
    };
    2.0 * r_max
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_wrap_around() {
        assert!((toroidal_distance(&[0.05, 0.5], &[0.95, 0.5]) - 0.1).abs() < 1e-12);
        assert!(
            (toroidal_distance(&[0.0, 0.0, 0.0], &[0.5, 0.5, 0.5]) - 0.75f64.sqrt()).abs() < 1e-12
        );
        let p = Points::from_fn(3, 1, |i, _| [0.1, 0.5, 0.97][i]);
        assert!((min_toroidal_distance(&p).unwrap() - 0.13).abs() < 1e-12);
        assert_eq!(
            min_toroidal_distance(&Points::from_fn(1, 3, |_, _| 0.2)),
            None
        );
    }

    #[test]
    fn regular_lattices_reach_the_packing_distance() {
        // n evenly spaced points in 1D are the densest packing: spacing 1/n = d_max.
        assert!((max_packing_distance(1, 10) - 0.1).abs() < 1e-15);
        // The FCC lattice with 4 points per cell: 4 points in the unit cube are at distance
        // sqrt(2)/2 and that is the densest packing of 4 balls.
        assert!((max_packing_distance(3, 4) - 0.5f64.sqrt()).abs() < 1e-12);
        // A square grid (k² points, spacing 1/k) is below the hexagonal packing distance.
        assert!(1.0 / 8.0 < max_packing_distance(2, 64));
    }
}
