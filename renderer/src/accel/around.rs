//! One sphere around each grouped orbiting sphere's path over the frame's shutter, so that a
//! packet passing near a spinning group places and tests only the members its lanes may meet.
//!
//! Why: a group's bound (`accel::orbits`) lets through every lane passing near any of its
//! members, and each such packet then placed every member (its spin's rotation and its centre
//! per lane, `Centres::place`, 7.4% of the spheres scene's frame 100 at 60501c8 by `perf`) and
//! ran its sphere test. Over one frame's shutter a carousel ball moves a few hundredths of a
//! unit, so the sphere around its swept box is not much larger than the ball.
//!
//! The sphere: around the instance's swept box as the top level pads it (`World`'s
//! `pad_top_level` of [`swept_bounds`](super::swept::swept_bounds), which holds the instance at
//! every time of the shutter), centred on the box's centre; its radius, for a ball of radius
//! `R`, the half diagonal of the box shrunk by `R` (where the ball's centre stays) plus `R`
//! (for a still ball `R` itself, not the box's `sqrt 3 R`), grown
//! by `2^-10` and by `2^-20` of the box's largest coordinate (the centres' absolute rounding). The test is the sphere test's early outs ([`super::packet`]'s `sphere`, with its
//! rounding [`SLACK`]): a lane is culled where its line passes the widened sphere by more than
//! the test's rounding, or where its origin is outside it and the ray leads away. A culled
//! lane's ray passes the member by at least `2^-10` of the radius, far more than the sphere
//! test's own rounding, so that test would have missed too: the same answers, bit for bit
//! (`accel::packet`'s and `render`'s bit-identity tests). Rays whose time lies outside the
//! shutter never come here (they are not `simple`).

use super::lanes::{Lanes, RayPacket, SLACK, dot, each};
use crate::geometry::Bounds;
use glam::Vec3A;

/// A sphere holding an instance over the shutter: its centre and its radius squared, the
/// radius widened by `2^-10`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Around {
    centre: [f32; 3],
    wide2: f32,
}

impl Around {
    /// The sphere around a ball of radius `radius` (0 for any other shape) held by `swept`
    /// (padded already) at every time; `None` for an empty or unbounded box.
    pub(crate) fn new(swept: Bounds, radius: f32) -> Option<Self> {
        if swept.is_empty() || !swept.is_finite() {
            return None;
        }
        let centre = (swept.min + swept.max) * 0.5;
        // A ball the box holds has its centre within the box shrunk by its radius, so within
        // that box's half diagonal of the centre, and all of it within `radius` more (the
        // whole half diagonal for other shapes). The pad covers the rounding, and `2^-20` of
        // the coordinates' size the centre's (and that of the centres the lanes place, a few
        // `u` of their size).
        let extent = (swept.max - centre).max(centre - swept.min);
        let radius = radius.abs();
        let half = (extent - Vec3A::splat(radius)).max(Vec3A::ZERO).length() + radius;
        let far = swept.min.abs().max(swept.max.abs()).max_element();
        let wide = half * (1.0 + 1.0 / 1024.0) + far / 1_048_576.0;
        Some(Self {
            centre: centre.to_array(),
            wide2: wide * wide,
        })
    }

    /// The lanes of `active` whose ray may meet the sphere (see the module notes); `a` is the
    /// rays' `d · d`.
    #[inline(always)]
    pub(crate) fn near<L: Lanes>(&self, ray: &RayPacket<L>, a: L, active: u32) -> u32 {
        if active == 0 {
            return 0;
        }
        let oc: [L; 3] = each(|k| ray.origin[k] - L::splat(self.centre[k]));
        let oo = dot(&oc, &oc);
        let half_b = dot(&oc, &ray.dir);
        let wide2 = L::splat(self.wide2);
        let away = (oo - wide2).simd_gt(L::ZERO) & half_b.simd_gt(L::ZERO);
        let oo_a = a * oo;
        let past = (oo_a - half_b * half_b).simd_gt(a * wide2 + L::splat(SLACK) * oo_a);
        active & !(away | past).to_bitmask()
    }
}
