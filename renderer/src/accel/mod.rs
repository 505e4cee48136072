//! The scene as rays see it in one frame: every instance of every shape, posed at the ray's time.
//!
//! Placeholder: brute force over instances, computing each instance's pose per ray. To be
//! replaced by a top level (obvhs) over the instances' bounds swept over the frame's shutter,
//! with static instances' transforms precomputed.

use crate::geometry::{Ray, Shape};
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
    /// `../shared/notes/obvhs.md`).
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

/// Every instance, ready to be traced for the shutter interval `[t0, t1]` of one frame.
#[derive(Clone, Debug)]
pub struct World {
    instances: Vec<Instance>,
}

impl World {
    /// Build for rays whose times lie in `[shutter.0, shutter.1]`.
    pub fn build(instances: Vec<Instance>, _shutter: (f32, f32)) -> Self {
        Self { instances }
    }

    pub fn instances(&self) -> &[Instance] {
        &self.instances
    }

    /// Closest hit with `ray.t_min < t < ray.t_max`.
    pub fn intersect(&self, ray: &Ray) -> Option<SurfaceHit> {
        let mut r = *ray;
        let mut best = None;
        for (i, inst) in self.instances.iter().enumerate() {
            let world_from_object = inst.motion.world_from_object(ray.time);
            let object_from_world = world_from_object.inverse();
            let local = Ray {
                origin: object_from_world.transform_point3a(r.origin),
                dir: object_from_world.transform_vector3a(r.dir),
                ..r
            };
            if let Some(h) = inst.shape.intersect(&local) {
                r.t_max = h.t;
                // Normals transform by the inverse transpose.
                let nmat = object_from_world.matrix3.transpose();
                best = Some(SurfaceHit {
                    t: h.t,
                    point: ray.at(h.t),
                    geometric_normal: (nmat * h.geometric_normal).normalize_or_zero(),
                    shading_normal: (nmat * h.shading_normal).normalize_or_zero(),
                    instance: i as u32,
                    material: inst.material,
                });
            }
        }
        best
    }

    /// Whether anything is hit with `ray.t_min < t < ray.t_max` (shadow rays).
    pub fn occluded(&self, ray: &Ray) -> bool {
        self.instances.iter().any(|inst| {
            let object_from_world = inst.motion.world_from_object(ray.time).inverse();
            let local = Ray {
                origin: object_from_world.transform_point3a(ray.origin),
                dir: object_from_world.transform_vector3a(ray.dir),
                ..*ray
            };
            inst.shape.occluded(&local)
        })
    }
}
