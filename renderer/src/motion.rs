//! Rigid motion over time (thesis Chapter III, "Transform Nodes in Scene Graph").
//!
//! An object's pose at scene time `t` is a chain of [`MotionLayer`]s, outermost (a group) first.
//! Each layer places its child at `location + velocity * t`, turned by `rotation` followed by a
//! spin of `angular_velocity * t` (axis times radians per second), and scaled by `scale`.

use glam::{Affine3A, Quat, Vec3, Vec3A};

/// One level of the scene graph: a group's or an object's own transform and its velocities.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionLayer {
    /// Position at scene time 0.
    pub location: Vec3,
    /// Units per second.
    pub velocity: Vec3,
    /// Orientation at scene time 0.
    pub rotation: Quat,
    /// Rotation axis times radians per second (world axes of the parent's frame).
    pub angular_velocity: Vec3,
    /// Per-axis scale (positive).
    pub scale: Vec3,
}

impl Default for MotionLayer {
    fn default() -> Self {
        Self {
            location: Vec3::ZERO,
            velocity: Vec3::ZERO,
            rotation: Quat::IDENTITY,
            angular_velocity: Vec3::ZERO,
            scale: Vec3::ONE,
        }
    }
}

impl MotionLayer {
    /// Whether the layer is the same at every time.
    pub fn is_static(&self) -> bool {
        self.velocity == Vec3::ZERO && self.angular_velocity == Vec3::ZERO
    }

    /// Parent-from-child transform at time `t`.
    pub fn pose(&self, t: f32) -> Affine3A {
        let spin = if self.angular_velocity == Vec3::ZERO {
            Quat::IDENTITY
        } else {
            Quat::from_scaled_axis(self.angular_velocity * t)
        };
        Affine3A::from_scale_rotation_translation(
            self.scale,
            spin * self.rotation,
            self.location + self.velocity * t,
        )
    }
}

/// The whole chain of an object: world-from-object at any time.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Motion {
    /// Outermost first.
    pub layers: Vec<MotionLayer>,
}

impl Motion {
    pub fn is_static(&self) -> bool {
        self.layers.iter().all(MotionLayer::is_static)
    }

    /// World-from-object transform at time `t`.
    pub fn world_from_object(&self, t: f32) -> Affine3A {
        self.layers
            .iter()
            .fold(Affine3A::IDENTITY, |acc, l| acc * l.pose(t))
    }

    /// Where the object-space point `p` is at time `t`.
    pub fn point_at(&self, p: Vec3A, t: f32) -> Vec3A {
        self.world_from_object(t).transform_point3a(p)
    }
}
