//! The scene as rays see it in one frame: every instance of every shape, posed at the ray's time.
//!
//! [`World`] is a two-level structure (top level over instances' swept bounds, per-mesh BVHs in
//! object space); [`instant`] is an instance's pose at one time, [`pose`] how it depends on
//! time; [`swept`] its bounds over a shutter interval; [`chain`] the per-ray form of a spinning
//! pose; [`lanes`] rays and vectors eight at a time, which the packet code shares (it imports
//! nothing else of `accel`); [`packet`] the packet form of a world of a few spheres and planes
//! (eight rays at once, bit for bit the scalar results; `orbits` its orbiting spheres' centres
//! and groups, `around` each grouped one's bound over the shutter); [`cull`] one box around the
//! world, which tells a packet's rays that surely hit nothing. See `docs/geometry.md`.

mod around;
pub mod chain;
mod cull;
pub mod instant;
pub mod lanes;
mod orbits;
pub mod packet;
pub mod pose;
mod slices;
pub mod swept;
pub mod world;

pub use world::World;

use crate::geometry::Shape;
use crate::motion::Motion;
use glam::Vec3A;

/// One placed copy of a shape.
#[derive(Clone, Debug)]
pub struct Instance {
    pub shape: Shape,
    pub motion: Motion,
    /// Index into the scene's materials.
    pub material: u32,
}

/// A world-space hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    pub t: f32,
    /// World-space point.
    pub point: Vec3A,
    /// Unit geometric normal, world space, as the shape faces (not flipped towards the ray).
    pub geometric_normal: Vec3A,
    /// Unit shading normal, world space.
    pub shading_normal: Vec3A,
    /// Which instance was hit.
    pub instance: u32,
    pub material: u32,
}

impl SurfaceHit {
    /// A start point for a ray leaving the surface in direction `dir`: the hit point pushed off
    /// the surface along the geometric normal, towards `dir`'s side, by an amount that grows
    /// with the coordinates' magnitude (a fixed offset fails at coordinates in the thousands;
    /// `docs/geometry.md`, "Self-intersection").
    pub fn spawn_point(&self, dir: Vec3A) -> Vec3A {
        let eps = 1e-5 * (1.0 + self.point.abs().max_element());
        let side = if dir.dot(self.geometric_normal) >= 0.0 {
            1.0
        } else {
            -1.0
        };
        self.point + self.geometric_normal * (eps * side)
    }
}
