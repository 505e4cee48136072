//! The plane y = 0 in object space, normal +y: infinite, or the rectangle
//! |x| <= half_extent.x, |z| <= half_extent.y.

use super::{Bounds, ObjectHit, Ray, ShapeHit};
use glam::{Vec2, Vec3A};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// `None`: infinite.
    pub half_extent: Option<Vec2>,
}

impl Plane {
    pub fn bounds(&self) -> Bounds {
        match self.half_extent {
            Some(h) => Bounds {
                min: Vec3A::new(-h.x, 0.0, -h.y),
                max: Vec3A::new(h.x, 0.0, h.y),
            },
            None => Bounds {
                min: Vec3A::new(f32::NEG_INFINITY, 0.0, f32::NEG_INFINITY),
                max: Vec3A::new(f32::INFINITY, 0.0, f32::INFINITY),
            },
        }
    }

    pub fn intersect(&self, ray: &Ray) -> Option<ObjectHit> {
        self.closest(ray).map(|h| self.surface(ray, h))
    }

    /// One division: `t = -o.y / d.y` (NaN and infinities fail the range test).
    pub fn closest(&self, ray: &Ray) -> Option<ShapeHit> {
        if ray.dir.y == 0.0 {
            return None;
        }
        let t = -ray.origin.y / ray.dir.y;
        if t.is_nan() || t <= ray.t_min || t >= ray.t_max {
            return None;
        }
        if let Some(h) = self.half_extent {
            let p = ray.at(t);
            if !(p.x.abs() <= h.x && p.z.abs() <= h.y) {
                return None;
            }
        }
        Some(ShapeHit { t, primitive: 0 })
    }

    pub fn surface(&self, _ray: &Ray, hit: ShapeHit) -> ObjectHit {
        ObjectHit {
            t: hit.t,
            geometric_normal: Vec3A::Y,
            shading_normal: Vec3A::Y,
        }
    }
}
