//! Scrambled Halton points: x_i = (φ_2(i), φ_3(i), φ_5(i)) with every radical inverse
//! Owen-scrambled by its own seed, so that, unlike Hammersley, each frame can get a new set.

use super::radical_inverse::owen_scrambled_radical_inverse;
use super::{PointSet, Points};
use crate::hash;
use crate::sampling::scramble::{axis_key, fraction, owen_base2, owen_radical_inverse};

/// Bases 2, 3, 5 for (u, v, t); a 1D set uses base 2.
pub struct Halton;

impl PointSet for Halton {
    fn name(&self) -> &'static str {
        "halton"
    }

    fn summary(&self) -> &'static str {
        "Halton in bases 2, 3, 5 with Owen scrambling"
    }

    fn generate(&self, n: usize, dims: usize, seed: u64) -> Points {
        const BASES: [u64; 3] = [2, 3, 5];
        let keys: Vec<u64> = (0..dims).map(|d| hash::hash(seed, &[d as u64])).collect();
        Points::from_fn(n, dims, |i, d| {
            owen_scrambled_radical_inverse(BASES[d], i as u64, keys[d])
        })
    }

    /// Owen-scrambled per pixel (one scramble keyed by pixel and frame replaces the frame's):
    /// φ_2 through [`owen_base2`], φ_3 and φ_5 digit by digit.
    fn scrambles(&self) -> bool {
        true
    }

    fn scrambled(&self, n: usize, dims: usize, i: usize, key: u64) -> [f64; 3] {
        super::coords(dims, |d| match d {
            0 => fraction(owen_base2(
                (i as u32).reverse_bits(),
                axis_key(key, d) as u32,
            )),
            1 => owen_radical_inverse(3, i as u32, n as u32, axis_key(key, d)),
            _ => owen_radical_inverse(5, i as u32, n as u32, axis_key(key, d)),
        })
    }
}
