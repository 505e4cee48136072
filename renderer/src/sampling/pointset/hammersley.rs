//! The Hammersley point set (thesis Chapter II): x_i = (i/N, φ_2(i), φ_3(i)) for i = 0..N-1,
//! deterministic, with low discrepancy. In 3D the coordinates are (u, v, t), so dropping time
//! leaves the 2D Hammersley set (i/N, φ_2(i)) of thesis Figure 4.

use super::{PointSet, Points, radical_inverse};
use crate::sampling::scramble::{
    axis_key, fixed_ratio, fraction, owen_base2, owen_radical_inverse,
};

/// Deterministic: the seed is ignored (the pixel shift provides the randomness).
pub struct Hammersley;

impl PointSet for Hammersley {
    fn name(&self) -> &'static str {
        "hammersley"
    }

    fn summary(&self) -> &'static str {
        "(i/N, radical inverse base 2, base 3): deterministic low discrepancy"
    }

    fn generate(&self, n: usize, dims: usize, _seed: u64) -> Points {
        const BASES: [u64; 2] = [2, 3];
        Points::from_fn(n, dims, |i, d| match d {
            0 => i as f64 / n as f64,
            _ => radical_inverse(BASES[d - 1], i as u64),
        })
    }

    /// Owen-scrambled per pixel: i/N and φ_2(i) in base 2 (the 32-bit fraction through
    /// [`owen_base2`]; φ_2(i) is i's bits reversed), φ_3(i) in base 3. At N = 2^m, (u, v)
    /// stays a (0, m, 2)-net; at any N, every box of 2-adic (u, v) and 3-adic t intervals
    /// keeps its count.
    fn scrambles(&self) -> bool {
        true
    }

    fn scrambled(&self, n: usize, dims: usize, i: usize, key: u64) -> [f64; 3] {
        super::coords(dims, |d| match d {
            0 => fraction(owen_base2(fixed_ratio(i, n), axis_key(key, d) as u32)),
            1 => fraction(owen_base2(
                (i as u32).reverse_bits(),
                axis_key(key, d) as u32,
            )),
            _ => owen_radical_inverse(3, i as u32, n as u32, axis_key(key, d)),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// φ_b(i) written independently: the digit sum Σ d_k b^-k built from the digit string.
    fn phi(base: u32, i: usize) -> f64 {
        let digits: Vec<u32> = {
            let mut v = Vec::new();
            let mut m = i as u32;
            while m > 0 {
                v.push(m % base);
                m /= base;
            }
            v
        };
        digits
            .iter()
            .enumerate()
            .map(|(k, &d)| d as f64 / (base as f64).powi(k as i32 + 1))
            .sum()
    }

    #[test]
    fn every_point_follows_the_definition() {
        for n in [1usize, 8, 27, 64, 125, 216, 343, 512] {
            let p = Hammersley.generate(n, 3, 0);
            for i in 0..n {
                let x = p.get(i);
                assert_eq!(x[0], i as f64 / n as f64, "n={n} i={i} u");
                assert!((x[1] - phi(2, i)).abs() < 1e-14, "n={n} i={i} v");
                assert!((x[2] - phi(3, i)).abs() < 1e-14, "n={n} i={i} t");
            }
        }
        assert_eq!(Hammersley.generate(4, 1, 0).get(3), &[0.75]);
    }
}
