//! Sampling the pixel's (u, v, t) cube: point sets, per-pixel shifts and filter warps
//! (thesis Chapter II "Point Sets for Sampling", "Spatial Filtering", "Temporal Filtering
//! Kernels"; Chapter III Figures 14 and 16).
//!
//! The renderer sees only [`FrameSampler`]: built once per frame from a [`SamplingConfig`], then
//! asked for sample `i` of pixel `(x, y)`. Points are generated once per frame or once per
//! sequence, never per pixel ([`pointset`], split between space and time by [`density`]); each
//! pixel rotates them by its own seeded shift ([`shift`], Cranley-Patterson), then the spatial
//! warp ([`warp`]) and the time filter ([`time_filter`]) turn them into a sub-pixel offset and
//! a shutter time. [`discrepancy`] and [`spacing`] measure sets; `ks` (unit tests only) tests distributions.

pub mod config;
pub mod density;
pub mod discrepancy;
#[cfg(test)]
pub(crate) mod ks;
pub mod pointset;
pub mod sampler;
pub mod scramble;
pub mod shift;
pub mod spacing;
pub mod time_filter;
pub mod warp;

pub use config::{Density, Randomization, SamplingConfig, SamplingOptions, Scope, SpatialFilter};
pub use sampler::{FrameSampler, PixelSample, PixelSampler};
pub use time_filter::TimeFilter;
