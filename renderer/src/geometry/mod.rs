//! Shapes in their own (object) space and the ray they are hit by.
//!
//! A shape knows nothing of motion or of the scene: [`crate::accel::World`] moves each ray into
//! an instance's object space at the ray's time and asks the shape there.

pub mod bounds;
pub mod mesh;
pub mod obj;
pub mod plane;
pub mod ray;
pub mod sphere;
pub mod tessellate;
pub mod triangle;
pub mod triangle4;

pub use bounds::Bounds;
pub use mesh::TriangleMesh;
pub use obj::ObjError;
pub use plane::Plane;
pub use ray::Ray;
pub use sphere::Sphere;

use glam::Vec3A;
use std::sync::Arc;

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

/// A hit before its normals are worked out: what traversal compares and keeps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeHit {
    pub t: f32,
    /// Triangle index for meshes ([`TriangleMesh::indices`] order), 0 for other shapes.
    pub primitive: u32,
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

    /// The closest hit's parameter and primitive, without normals (cheaper: the world asks
    /// this of every candidate instance and works out normals for the winner only).
    pub fn closest(&self, ray: &Ray) -> Option<ShapeHit> {
        match self {
            Shape::Mesh(m) => m.closest(ray),
            Shape::Sphere(s) => s.closest(ray),
            Shape::Plane(p) => p.closest(ray),
        }
    }

    /// Normals at `hit`, which [`Shape::closest`] returned for the same `ray`.
    pub fn surface(&self, ray: &Ray, hit: ShapeHit) -> ObjectHit {
        match self {
            Shape::Mesh(m) => m.surface(ray, hit),
            Shape::Sphere(s) => s.surface(ray, hit),
            Shape::Plane(p) => p.surface(ray, hit),
        }
    }

    /// Whether anything is hit with `ray.t_min < t < ray.t_max` (may stop at the first hit).
    pub fn occluded(&self, ray: &Ray) -> bool {
        match self {
            Shape::Mesh(m) => m.occluded(ray),
            _ => self.closest(ray).is_some(),
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
