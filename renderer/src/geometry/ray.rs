//! A ray with a time: every ray of a sample carries the shutter time it was born at, and its
//! shadow and reflection rays inherit it (thesis Chapter II, "Motion Blur").

use glam::Vec3A;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: Vec3A,
    /// Not necessarily unit length (object-space rays keep the world ray's parameterisation).
    pub dir: Vec3A,
    /// Scene time in seconds.
    pub time: f32,
    /// Hits count only for `t_min < t < t_max`.
    pub t_min: f32,
    pub t_max: f32,
}

impl Ray {
    /// A ray from `origin` towards `dir` with no far limit.
    pub fn new(origin: Vec3A, dir: Vec3A, time: f32) -> Self {
        Self {
            origin,
            dir,
            time,
            t_min: 0.0,
            t_max: f32::INFINITY,
        }
    }

    /// The point at parameter `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3A {
        self.origin + self.dir * t
    }
}

impl Ray {
    /// The ray as obvhs traverses it. The reciprocal direction is exact where it is finite and
    /// +-f32::MAX where a component is 0 (obvhs's own `safe_inverse` replaces every component
    /// below f32::EPSILON by 1/EPSILON, which makes its box test drop rays that are nearly
    /// parallel to a face; with +-MAX, `0 * inv` is 0, never NaN). obvhs's box test ignores
    /// `tmin`; the shapes apply `t_min` themselves.
    #[inline]
    pub fn traversal_ray(&self) -> obvhs::ray::Ray {
        obvhs::ray::Ray {
            origin: self.origin,
            direction: self.dir,
            inv_direction: self
                .dir
                .recip()
                .clamp(Vec3A::splat(-f32::MAX), Vec3A::splat(f32::MAX)),
            tmin: self.t_min,
            tmax: self.t_max,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn traversal_ray_has_finite_signed_reciprocals() {
        let r = Ray::new(Vec3A::ZERO, Vec3A::new(0.0, -0.0, 1e-9), 0.0).traversal_ray();
        assert_eq!(r.inv_direction.x, f32::MAX);
        assert_eq!(r.inv_direction.y, -f32::MAX);
        assert_eq!(r.inv_direction.z, 1.0 / 1e-9f32);
    }
}
