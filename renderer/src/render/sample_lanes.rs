//! Sample `i` of [`LANES`] pixels at once, in lanes, wherever the pixels shift the frame's
//! points (not scrambled): any spatial warp and time filter, the thesis's Gaussian and
//! triangle filters included. Pixel-major packets give every lane the same frame point, so a
//! sample is a splat, an add per axis, the warps in lanes
//! ([`SpatialWarp::offset_lanes`], [`TimeFilter::warp_lanes`]) and a few more lane
//! operations, where [`PixelSampler::sample`] per lane costs a lookup, a branch per axis and
//! the warps one lane at a time, and leaves the lanes to be gathered from scalars.
//!
//! Bit identity with [`PixelSampler::sample`] and [`super::CameraRays::ray`]: the shift is
//! [`crate::sampling::shift::wrap`] (`r = a + s`, `r - 1` where `r >= 1`), the warps are
//! lane by lane the scalar ones (tested in their modules), the time is `t0 + t (t1 - t0)` and
//! the film point `(x + 1/2) + dx`, each in that order.

use crate::accel::lanes::{LANES, Lanes, each};
use crate::sampling::warp::SpatialWarp;
use crate::sampling::{FrameSampler, PixelSampler, TimeFilter};

/// A frame's shifted samples in lanes (see the module notes).
pub(super) struct ShiftedSamples<'a> {
    points: &'a [[f32; 3]],
    spatial: SpatialWarp,
    time: TimeFilter,
    shutter: (f32, f32),
}

/// Sample `i` of a group of pixels: film points `(fx, fy)` and scene times per lane.
pub(super) struct FilmLanes<L: Lanes> {
    pub(super) fx: L,
    pub(super) fy: L,
    pub(super) time: L,
}

impl<'a> ShiftedSamples<'a> {
    /// The frame's samples in lanes, or `None` when its pixels scramble the points.
    pub(super) fn new(sampler: &'a FrameSampler, shutter: (f32, f32)) -> Option<Self> {
        Some(Self {
            points: sampler.shifted_points()?,
            spatial: sampler.spatial(),
            time: sampler.time_filter(),
            shutter,
        })
    }

    /// The pixels' shifts, per axis.
    pub(super) fn shifts<L: Lanes>(pixels: &[PixelSampler; LANES]) -> [L; 3] {
        let s = pixels.each_ref().map(PixelSampler::shift);
        [0, 1, 2].map(|d| L::new(std::array::from_fn(|k| s[k][d])))
    }

    /// Sample `i` of the pixels whose shifts are `shift`, at film columns `x` (pixel
    /// `x + 1/2` per lane) of the row whose centre is `y`.
    #[inline(always)]
    pub(super) fn sample<L: Lanes>(&self, shift: &[L; 3], x: L, y: f32, i: usize) -> FilmLanes<L> {
        let p = self.points[i];
        let [u, v, t] = each(|d| wrap(L::splat(p[d]), shift[d]));
        let (dx, dy) = self.spatial.offset_lanes(u, v);
        let t = self.time.warp_lanes(t);
        let (t0, t1) = self.shutter;
        FilmLanes {
            fx: x + dx,
            fy: L::splat(y) + dy,
            time: L::splat(t0) + t * L::splat(t1 - t0),
        }
    }
}

/// [`crate::sampling::shift::wrap`] in lanes.
#[inline(always)]
fn wrap<L: Lanes>(a: L, s: L) -> L {
    let r = a + s;
    r.simd_ge(L::ONE).bitselect(r - L::ONE, r)
}
