//! Sampling the pixel's (u, v, t) cube: point sets, per-pixel shifts and filter warps
//! (thesis Chapter II "Point Sets for Sampling", Chapter III Figures 14 and 16).
//!
//! The renderer sees only [`FrameSampler`]: built once per frame, then asked for sample `i` of
//! pixel `(x, y)`. Points are generated once per frame or once per sequence, never per pixel;
//! each pixel rotates them by its own seeded shift (Cranley-Patterson), then the spatial and
//! temporal warps (filter importance sampling) turn them into a sub-pixel offset and a shutter time.

use crate::hash;
use anyhow::Result;
use serde::{Deserialize, Serialize};

/// How a stimulus samples its pixels. Lives in a scene's `settings.sampling` block and is
/// overridden per stimulus by a job.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SamplingConfig {
    /// Point set name: `random`, `stratified`, `hammersley`, `poisson`, `sobol`, `halton`.
    #[serde(default = "default_point_set")]
    pub point_set: String,
    /// Samples per pixel.
    #[serde(default = "default_spp")]
    pub spp: u32,
    /// Time filter name: `box`, `truncated_box`, `triangle`.
    #[serde(default = "default_time_filter")]
    pub time_filter: String,
}

fn default_point_set() -> String {
    "random".into()
}
fn default_spp() -> u32 {
    16
}
fn default_time_filter() -> String {
    "box".into()
}

impl Default for SamplingConfig {
    fn default() -> Self {
        Self {
            point_set: default_point_set(),
            spp: default_spp(),
            time_filter: default_time_filter(),
        }
    }
}

/// One sample of a pixel after shift and warps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelSample {
    /// Offset from the pixel's centre, in pixels (x to the right, y down); may exceed 0.5 under a
    /// wide spatial filter.
    pub dx: f32,
    pub dy: f32,
    /// Fraction of the frame's shutter interval, in [0, 1].
    pub t: f32,
}

/// Everything needed to produce every pixel's samples for one frame.
#[derive(Clone, Debug)]
pub struct FrameSampler {
    points: Vec<[f32; 3]>,
    shift_key: u64,
}

impl FrameSampler {
    /// The sampler for `frame` of a stimulus with master `seed`.
    pub fn new(config: &SamplingConfig, seed: u64, frame: u32) -> Result<Self> {
        anyhow::ensure!(config.spp > 0, "field `spp` must be at least 1");
        let n = config.spp as usize;
        let points = (0..n as u64)
            .map(|i| {
                let c = |d: u64| hash::unit_f32(hash::hash(seed, &[0x5e7, frame as u64, i, d]));
                [c(0), c(1), c(2)]
            })
            .collect();
        Ok(Self {
            points,
            shift_key: hash::hash(seed, &[0x5817]),
        })
    }

    /// Samples per pixel.
    pub fn spp(&self) -> usize {
        self.points.len()
    }

    /// Sample `i` of pixel `(x, y)`.
    #[inline]
    pub fn sample(&self, x: u32, y: u32, i: usize) -> PixelSample {
        let p = self.points[i];
        let s = |d: u64| hash::unit_f32(hash::hash(self.shift_key, &[x as u64, y as u64, d]));
        let wrap = |a: f32, b: f32| {
            let r = a + b;
            if r >= 1.0 { r - 1.0 } else { r }
        };
        PixelSample {
            dx: wrap(p[0], s(0)) - 0.5,
            dy: wrap(p[1], s(1)) - 0.5,
            t: wrap(p[2], s(2)),
        }
    }
}
