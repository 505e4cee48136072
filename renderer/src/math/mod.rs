//! The transcendental functions of the hot path in lanes: `ln` and `sin_cos` of the Gaussian
//! pixel filter's Box-Muller warp ([`crate::sampling::warp`]), `atan2` and `acos` of the
//! environment map's direction-to-texel mapping ([`crate::environment`]); `sin_cos` of each
//! spin's rotation too ([`crate::accel::chain::Spin::at_lanes`]: 1.55 x 2^-24 below 2^13 rad,
//! bound 3.3).
//!
//! Why: libm has no lane form, so the lanes called `logf`, `sincosf`, `atan2f` and `acosf`
//! one lane at a time: together about 28% of the thesis's plane scene (frame 93, `perf`,
//! f82e3ac). These are `wide`'s `f32x8` polynomials (Agner Fog's vector class library, after
//! Cephes), already a dependency of the lanes: a few operations on eight values at once. They
//! are written here over [`crate::simd::Lanes`] (building blocks in `vcl.rs`), operation for
//! operation as `wide` writes them, so that AVX2 lanes run them at their width and both lane
//! types give `wide`'s bits (`wide_bits.rs` tests it on edge values and on every family's range).
//!
//! One code for both paths: each function's scalar form runs the lane form on a splat and
//! takes lane 0, so the scalar path (the reference of the bit-identity tests) and the lanes
//! give the same bits by construction. Against libm the results differ at rounding level: each
//! family's tests measure the largest error against f64 over the inputs the renderer gives it
//! and bound it: `ln` 1.17 ulp (bound 2), `acos` 1.20 ulp (2), `atan2` 3.10 ulp (4), `sin_cos`
//! 1.55 x 2^-24 absolute on [-2 pi, 2 pi] (2; libm's f32 `sin_cos` 0.55) (`docs/benchmarks/
//! lanes.md`, "How the scenes are traced"). `pow_whole` is scalar: the Fresnel curve's whole powers
//! as f64 products (correctly rounded but at near-halfway cases; libm's `powf` for the rest).

// The coefficients as `wide` (after Cephes) writes them, digits beyond an f32's included: the
// same f32s, and a reader finds them there.
#![allow(clippy::excessive_precision)]

mod inverse_trig;
mod log;
mod pow;
mod sin_cos;
mod vcl;

pub use inverse_trig::{acos, acos_lanes, atan2, atan2_lanes};
pub use log::{ln, ln_lanes};
pub use pow::pow_whole;
pub use sin_cos::{sin_cos, sin_cos_lanes};

#[cfg(test)]
mod error;
#[cfg(test)]
mod wide_bits;
