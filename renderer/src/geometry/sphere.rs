//! An analytic sphere centred at the object-space origin.

use super::{Bounds, ObjectHit, Ray};
use glam::Vec3A;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    pub radius: f32,
}

impl Sphere {
    pub fn bounds(&self) -> Bounds {
        Bounds {
            min: Vec3A::splat(-self.radius),
            max: Vec3A::splat(self.radius),
        }
    }

    /// Nearest root of |o + t d|^2 = r^2 in `(t_min, t_max)`.
    pub fn intersect(&self, ray: &Ray) -> Option<ObjectHit> {
        let a = ray.dir.length_squared();
        let half_b = ray.origin.dot(ray.dir);
        let c = ray.origin.length_squared() - self.radius * self.radius;
        let disc = half_b * half_b - a * c;
        if disc.is_nan() || disc < 0.0 || a == 0.0 {
            return None;
        }
        let sq = disc.sqrt();
        // Numerically stable pair of roots (no cancellation in the larger one).
        let q = -(half_b + half_b.signum() * sq);
        let (t0, t1) = if q == 0.0 { (0.0, 0.0) } else { (q / a, c / q) };
        let (t0, t1) = (t0.min(t1), t0.max(t1));
        let t = [t0, t1]
            .into_iter()
            .find(|&t| t > ray.t_min && t < ray.t_max)?;
        let n = ray.at(t);
        Some(ObjectHit {
            t,
            geometric_normal: n,
            shading_normal: n,
        })
    }
}
