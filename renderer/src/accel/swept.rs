//! World bounds of an instance over one frame's shutter interval (thesis Chapter III: "a
//! smaller bounding box is used for each frame" instead of one over the whole sequence).
//!
//! - Fixed: the object's box transformed once.
//! - Translating: the union of the boxes at the two ends of the interval. Exact: every corner
//!   moves on a straight segment, so the union of the end boxes holds all of it, and nothing
//!   smaller does.
//! - Spinning: conservative. The interval is cut into [`SPIN_STEPS`] pieces; at each cut the
//!   object's box corners are placed exactly, and every box is grown by `V dt / 2`, `V` a bound
//!   on the corners' speed ([`Motion::speed_bound`]): between two cuts a corner is never farther
//!   than that from its place at the nearer cut. The transformed object lies in the convex hull
//!   of its transformed box corners (rigid motion and scale keep convex hulls), so the grown
//!   union holds it at every time.
//!
//! The result is not padded for rounding; [`crate::accel::World`] pads it.

use crate::geometry::Bounds;
use crate::motion::Motion;
use glam::{Affine3A, Vec3A};

/// Time steps for spinning objects: the growth `V dt / 2` shrinks as 1/steps.
pub const SPIN_STEPS: usize = 16;

/// Bounds of `object` (object space) moved by `motion` over every time in `[t0, t1]`.
/// Not finite when `object` is not (an infinite plane).
pub fn swept_bounds(object: Bounds, motion: &Motion, shutter: (f32, f32)) -> Bounds {
    if !object.is_finite() || object.is_empty() {
        return object;
    }
    let (t0, t1) = (shutter.0.min(shutter.1), shutter.0.max(shutter.1));
    let placed = |m: Affine3A| {
        object
            .corners()
            .iter()
            .fold(Bounds::EMPTY, |b, &c| b.include(m.transform_point3a(c)))
    };
    if motion.is_static() {
        return placed(motion.world_from_object(t0));
    }
    if motion.is_translation_only() {
        let at_zero = motion.world_from_object(0.0);
        let w = motion.linear_velocity();
        let at = |t: f32| Affine3A {
            translation: at_zero.translation + w * t,
            ..at_zero
        };
        return placed(at(t0)).union(placed(at(t1)));
    }
    let dt = (t1 - t0) / SPIN_STEPS as f32;
    let speed = object
        .corners()
        .iter()
        .map(|&c| motion.speed_bound(c, (t0, t1)))
        .fold(0.0f32, f32::max);
    let grow = Vec3A::splat(speed * dt * 0.5);
    let cuts = (0..=SPIN_STEPS).map(|i| {
        if i == SPIN_STEPS {
            t1
        } else {
            t0 + dt * i as f32
        }
    });
    let b = cuts.fold(Bounds::EMPTY, |b, t| {
        b.union(placed(motion.world_from_object(t)))
    });
    Bounds {
        min: b.min - grow,
        max: b.max + grow,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::MotionLayer;
    use glam::{Quat, Vec3};
    use proptest::prelude::*;

    fn unit_box() -> Bounds {
        Bounds {
            min: Vec3A::splat(-1.0),
            max: Vec3A::splat(1.0),
        }
    }

    #[test]
    fn translation_is_exactly_the_union_of_the_end_boxes() {
        let m = Motion {
            layers: vec![MotionLayer {
                location: Vec3::new(100.0, 0.0, 0.0),
                velocity: Vec3::new(-8.0, 0.0, 2.0),
                ..MotionLayer::default()
            }],
        };
        let b = swept_bounds(unit_box(), &m, (0.0, 0.5));
        assert_eq!(b.min, Vec3A::new(95.0, -1.0, -1.0));
        assert_eq!(b.max, Vec3A::new(101.0, 1.0, 2.0));
    }

    #[test]
    fn unbounded_shapes_stay_unbounded() {
        let inf = Bounds {
            min: Vec3A::splat(f32::NEG_INFINITY),
            max: Vec3A::splat(f32::INFINITY),
        };
        assert!(!swept_bounds(inf, &Motion::default(), (0.0, 1.0)).is_finite());
    }

    fn vec3(r: f32) -> impl Strategy<Value = Vec3> {
        (-r..r, -r..r, -r..r).prop_map(|(x, y, z)| Vec3::new(x, y, z))
    }

    fn layer() -> impl Strategy<Value = MotionLayer> {
        (
            vec3(50.0),
            vec3(20.0),
            vec3(3.0),
            prop::bool::ANY,
            vec3(4.0),
            (0.2f32..3.0, 0.2f32..3.0, 0.2f32..3.0),
        )
            .prop_map(
                |(location, velocity, axis_angle, spins, spin, (sx, sy, sz))| MotionLayer {
                    location,
                    velocity,
                    rotation: Quat::from_scaled_axis(axis_angle),
                    angular_velocity: if spins { spin } else { Vec3::ZERO },
                    scale: Vec3::new(sx, sy, sz),
                },
            )
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        /// Every point of the object's box, at every time of the shutter, lies in the swept
        /// bounds as the world pads them (the padding covers the rounding of the transforms).
        #[test]
        fn swept_bounds_hold_the_object_at_every_time(
            layers in prop::collection::vec(layer(), 1..3),
            t0 in -13.0f32..13.0,
            len in 0.0f32..0.5,
            samples in prop::collection::vec((0.0f32..=1.0, 0.0f32..=1.0, 0.0f32..=1.0, 0.0f32..=1.0), 64),
        ) {
            let motion = Motion { layers };
            let object = Bounds { min: Vec3A::new(-2.0, -0.5, -1.0), max: Vec3A::new(1.0, 0.5, 3.0) };
            let swept = swept_bounds(object, &motion, (t0, t0 + len));
            let padded = super::super::world::pad_top_level(swept, swept.diagonal());
            for &(s, x, y, z) in &samples {
                let t = t0 + len * s;
                // Corners and interior points (the snapping to 0/1 picks corners often).
                let snap = |v: f32| if v < 0.2 { 0.0 } else if v > 0.8 { 1.0 } else { v };
                let f = Vec3A::new(snap(x), snap(y), snap(z));
                let p = object.min + (object.max - object.min) * f;
                let w = motion.point_at(p, t);
                prop_assert!(padded.contains(w), "{w} at t={t} outside {padded:?}");
            }
        }
    }
}
