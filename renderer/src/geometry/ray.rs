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
