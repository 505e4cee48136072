//! Sample `i` of [`LANES`] pixels at once, in lanes, where a frame's samples are plain
//! arithmetic: points shifted per pixel (not scrambled), box spatial and box time filters (the
//! matched scenes' sampling). Pixel-major packets give every lane the same frame point, so a
//! sample is a splat, an add per axis and a few more lane operations, where
//! [`PixelSampler::sample`] per lane costs a lookup, a branch per axis and the time warp's
//! f64 round trip, and leaves the lanes to be gathered from scalars.
//!
//! Bit identity with [`PixelSampler::sample`] and [`super::CameraRays::ray`]: the shift is
//! [`crate::sampling::shift::wrap`] (`r = a + s`, `r - 1` where `r >= 1`), the box offset is
//! `(u - 1/2, v - 1/2)`, the box time warp is the identity (`u as f64 as f32` is `u`), the
//! time is `t0 + t (t1 - t0)` and the film point `(x + 1/2) + dx`, each in that order.

use crate::accel::packet::{LANES, Lane};
use crate::sampling::{FrameSampler, PixelSampler};

/// A frame's samples in lanes (see the module notes).
pub(super) struct PlainSamples<'a> {
    points: &'a [[f32; 3]],
    shutter: (f32, f32),
}

/// Sample `i` of a group of pixels: film points `(fx, fy)` and scene times per lane.
pub(super) struct FilmLanes {
    pub(super) fx: Lane,
    pub(super) fy: Lane,
    pub(super) time: Lane,
}

impl<'a> PlainSamples<'a> {
    /// The frame's samples in lanes, or `None` unless they are plain arithmetic.
    pub(super) fn new(sampler: &'a FrameSampler, shutter: (f32, f32)) -> Option<Self> {
        let points = sampler.plain_points()?;
        Some(Self { points, shutter })
    }

    /// The pixels' shifts, per axis.
    pub(super) fn shifts(pixels: &[PixelSampler; LANES]) -> [Lane; 3] {
        let s = pixels.each_ref().map(PixelSampler::shift);
        std::array::from_fn(|d| Lane::new(std::array::from_fn(|k| s[k][d])))
    }

    /// Sample `i` of the pixels whose shifts are `shift`, at film columns `x` (pixel
    /// `x + 1/2` per lane) of the row whose centre is `y`.
    #[inline]
    pub(super) fn sample(&self, shift: &[Lane; 3], x: Lane, y: f32, i: usize) -> FilmLanes {
        let p = self.points[i];
        let [u, v, t] = std::array::from_fn(|d| wrap(Lane::splat(p[d]), shift[d]));
        let half = Lane::splat(0.5);
        let (t0, t1) = self.shutter;
        FilmLanes {
            fx: x + (u - half),
            fy: Lane::splat(y) + (v - half),
            time: Lane::splat(t0) + t * Lane::splat(t1 - t0),
        }
    }
}

/// [`crate::sampling::shift::wrap`] in lanes.
#[inline(always)]
fn wrap(a: Lane, s: Lane) -> Lane {
    let r = a + s;
    r.simd_ge(Lane::ONE).bitselect(r - Lane::ONE, r)
}
