//! Shapes in their own (object) space and the ray they are hit by.
//!
//! A shape knows nothing of motion or of the scene: [`crate::accel::World`] moves each ray into
//! an instance's object space at the ray's time and asks the shape there.

pub mod mesh;
pub mod plane;
pub mod ray;
pub mod sphere;
pub mod triangle;

pub use mesh::TriangleMesh;
pub use plane::Plane;
pub use ray::Ray;
pub use sphere::Sphere;

use glam::Vec3A;
use std::sync::Arc;

/// Axis-aligned bounds in object space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    pub min: Vec3A,
    pub max: Vec3A,
}

impl Bounds {
    /// The empty box (min > max), the identity of [`Bounds::union`].
    pub const EMPTY: Bounds = Bounds {
        min: Vec3A::splat(f32::INFINITY),
        max: Vec3A::splat(f32::NEG_INFINITY),
    };

    pub fn union(self, o: Bounds) -> Bounds {
        Bounds {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    pub fn include(self, p: Vec3A) -> Bounds {
        Bounds {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// Whether every coordinate is finite (an unbounded shape has no finite bounds).
    pub fn is_finite(&self) -> bool {
        self.min.is_finite() && self.max.is_finite()
    }
}

/// Where a ray met a shape, in the shape's object space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectHit {
    /// Ray parameter (the same in object and world space: rays are transformed, not normalised).
    pub t: f32,
    /// Geometric normal, object space, not necessarily unit length.
    pub geometric_normal: Vec3A,
    /// Shading normal (interpolated vertex normals where the mesh has them), object space.
    pub shading_normal: Vec3A,
}

/// One of the shapes a scene can hold.
#[derive(Clone, Debug)]
pub enum Shape {
    Mesh(Arc<TriangleMesh>),
    Sphere(Sphere),
    Plane(Plane),
}

impl Shape {
    /// Closest hit with `ray.t_min < t < ray.t_max`, in object space.
    pub fn intersect(&self, ray: &Ray) -> Option<ObjectHit> {
        match self {
            Shape::Mesh(m) => m.intersect(ray),
            Shape::Sphere(s) => s.intersect(ray),
            Shape::Plane(p) => p.intersect(ray),
        }
    }

    /// Whether anything is hit with `ray.t_min < t < ray.t_max` (may stop at the first hit).
    pub fn occluded(&self, ray: &Ray) -> bool {
        match self {
            Shape::Mesh(m) => m.occluded(ray),
            _ => self.intersect(ray).is_some(),
        }
    }

    /// Object-space bounds; not finite for an unbounded plane.
    pub fn bounds(&self) -> Bounds {
        match self {
            Shape::Mesh(m) => m.bounds(),
            Shape::Sphere(s) => s.bounds(),
            Shape::Plane(p) => p.bounds(),
        }
    }
}
