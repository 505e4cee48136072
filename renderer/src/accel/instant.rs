//! An instance's pose at one instant: the map from world to object space that a ray at that
//! time takes (thesis Chapter III, "Transform Nodes in Scene Graph": rays move, geometry does
//! not). How the pose depends on time is `pose`'s; `chain` computes a spinning one per ray.

use crate::geometry::Ray;
use glam::{Affine3A, Mat3A, Vec3A};

/// World-from-object as `p + L x`, kept as `p` and `L^-1`: a ray becomes
/// `(L^-1 (o - p), L^-1 d)`, with the same parameter t in both spaces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    pub translation: Vec3A,
    pub object_from_world: Mat3A,
    /// `object_from_world` is exactly the identity (a placed but unturned, unscaled object,
    /// the common case): rays and normals skip the matrix (the products with 0 and 1 it saves
    /// are exact, so results differ at most in the sign of a zero).
    pub unturned: bool,
}

impl Pose {
    pub fn new(translation: Vec3A, object_from_world: Mat3A) -> Self {
        Self {
            translation,
            object_from_world,
            unturned: object_from_world == Mat3A::IDENTITY,
        }
    }

    /// A pose that only places: rays move by `-centre` alone (a sphere's,
    /// [`PoseOverTime::centred`](super::pose::PoseOverTime::centred)).
    #[inline]
    pub fn centred(centre: Vec3A) -> Self {
        Self {
            translation: centre,
            object_from_world: Mat3A::IDENTITY,
            unturned: true,
        }
    }

    pub fn from_world_from_object(m: Affine3A) -> Self {
        Self::new(m.translation, m.matrix3.inverse())
    }

    /// The ray in object space (same time and t range).
    #[inline]
    pub fn ray_to_object(&self, ray: &Ray) -> Ray {
        if self.unturned {
            return Ray {
                origin: ray.origin - self.translation,
                ..*ray
            };
        }
        Ray {
            origin: self.object_from_world * (ray.origin - self.translation),
            dir: self.object_from_world * ray.dir,
            ..*ray
        }
    }

    /// An object-space normal in world space (inverse transpose), not normalised.
    #[inline]
    pub fn normal_to_world(&self, n: Vec3A) -> Vec3A {
        if self.unturned {
            return n;
        }
        self.object_from_world.transpose() * n
    }
}
