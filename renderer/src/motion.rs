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

    /// The linear part (rotation times scale) without the spin.
    pub fn linear_at_rest(&self) -> glam::Mat3A {
        glam::Mat3A::from_quat(self.rotation) * glam::Mat3A::from_diagonal(self.scale)
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

    /// The chain's scale when every layer scales uniformly (the product of the layers' factors,
    /// outermost first; exactly 1 for a chain without scale), else `None`. A sphere under such
    /// a chain is a sphere of the scaled radius about the chain's translation, at any time.
    pub fn uniform_scale(&self) -> Option<f32> {
        self.layers.iter().try_fold(1.0f32, |s, l| {
            let k = l.scale;
            (k.x == k.y && k.y == k.z).then_some(s * k.x)
        })
    }

    /// Whether no layer spins: the pose then only translates, linearly in time
    /// (see [`Motion::linear_velocity`]).
    pub fn is_translation_only(&self) -> bool {
        self.layers.iter().all(|l| l.angular_velocity == Vec3::ZERO)
    }

    /// For a motion without spin, the world velocity of the object's origin: the chain's
    /// translation is `p0 + w t` with `w = v0 + L0 v1 + L0 L1 v2 + ...` (`L_k` the constant
    /// linear part of layer k), because each layer maps its child's translation linearly.
    /// Meaningless when a layer spins.
    pub fn linear_velocity(&self) -> Vec3A {
        let mut w = Vec3A::ZERO;
        let mut outer = glam::Mat3A::IDENTITY;
        for l in &self.layers {
            w += outer * Vec3A::from(l.velocity);
            outer *= l.linear_at_rest();
        }
        w
    }

    /// An upper bound on the speed of the object-space point `p` over `[t0, t1]`, for swept
    /// bounds of spinning objects. Innermost layer first: with `x_k = l_k + v_k t + R_k(t) S_k
    /// x_{k+1}` and `R_k` a rotation at angular speed `|w_k|`,
    /// `|x_k'| <= |v_k| + |w_k| s_k |x_{k+1}| + s_k |x_{k+1}'|` (`s_k` the largest scale), and
    /// `|x_k| <= max(|l_k + v_k t0|, |l_k + v_k t1|) + s_k |x_{k+1}|` (a norm of a linear
    /// function of t is largest at an end of the interval).
    pub fn speed_bound(&self, p: Vec3A, (t0, t1): (f32, f32)) -> f32 {
        let (mut reach, mut speed) = (p.length(), 0.0f32);
        for l in self.layers.iter().rev() {
            let s = l.scale.abs().max_element();
            speed = l.velocity.length() + l.angular_velocity.length() * s * reach + s * speed;
            let at = |t: f32| (l.location + l.velocity * t).length();
            reach = at(t0).max(at(t1)) + s * reach;
        }
        speed
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
