//! A moving camera's frame at [`LANES`] sample times at once, in lanes: eye, forward, right and
//! up as [`Camera::frame_at`] makes them, for the lanes of a packet.
//!
//! Why: with a moving camera (the thesis's plane scene), each camera sample builds its own
//! frame, two normalisations (a square root and a division each) and two cross products in one
//! dependent chain, then the ray direction's normalisation: one lane at a time, the core waits
//! on each square root. In lanes, eight chains run side by side.
//!
//! Bit identity with [`Camera::frame_at`] and [`CameraFrame::look_at`]: each lane does glam's
//! SSE2 operations in their order. [`Moving::at`] is `at_zero + velocity t` per axis;
//! `try_normalize` is `v * (1 / sqrt((x x + y y) + z z))` where that factor is finite and
//! positive (else the frame is undefined and the sample black); `cross` is
//! `(a.y b.z - a.z b.y, a.z b.x - a.x b.z, a.x b.y - a.y b.x)` (glam's shuffled form computes
//! these very products and differences; a product of two floats does not depend on their
//! order, and Rust never fuses a multiply-add).
//!
//! [`CameraFrame::look_at`]: crate::camera::CameraFrame::look_at

use crate::accel::lanes::{LANES, Lanes, dot, each};
use crate::camera::{Camera, Moving};

/// A vector per lane.
type V3<L> = [L; 3];

/// The frames of `camera` at the times `time` per lane: eye, forward, right, up (per axis, in
/// lanes), and the lanes where the frame is defined (bit `i` for lane `i`).
#[inline(always)]
pub(super) fn frames_at<L: Lanes>(camera: &Camera, time: L) -> ([V3<L>; 4], u32) {
    let eye = at(&camera.location, time);
    let target = at(&camera.look_at, time);
    let up = at(&camera.up, time);
    let (forward, has_forward) = try_normalize(each(|k| target[k] - eye[k]));
    let (right, has_right) = try_normalize(cross(&forward, &up));
    let up = cross(&right, &forward);
    let defined = (has_forward & has_right).to_bitmask() & ((1 << LANES) - 1);
    ([eye, forward, right, up], defined)
}

/// [`Moving::at`] in lanes.
#[inline(always)]
fn at<L: Lanes>(m: &Moving, time: L) -> V3<L> {
    let (p, v) = (m.at_zero.to_array(), m.velocity.to_array());
    each(|k| L::splat(p[k]) + L::splat(v[k]) * time)
}

/// glam's `Vec3A::try_normalize` in lanes: the unit vector, and where it exists.
#[inline(always)]
fn try_normalize<L: Lanes>(v: V3<L>) -> (V3<L>, L) {
    let rcp = L::ONE / dot(&v, &v).sqrt();
    let ok = rcp.is_finite() & rcp.simd_gt(L::ZERO);
    (each(|k| v[k] * rcp), ok)
}

/// glam's `Vec3A::cross` in lanes.
#[inline(always)]
fn cross<L: Lanes>(a: &V3<L>, b: &V3<L>) -> V3<L> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::lanes::Lane;
    use glam::Vec3;

    /// Every lane's frame is [`Camera::frame_at`]'s to the bit, and undefined exactly where it
    /// is, over many random cameras and times (and ones that pass the look-at point through
    /// the eye, or turn the view onto the up vector).
    #[test]
    fn every_lane_is_the_scalar_frame_bit_for_bit() {
        let h =
            |i: u64, k: u64| crate::hash::unit_f32(crate::hash::hash(11, &[i, k])) * 20.0 - 10.0;
        let v = |i: u64, k: u64| Vec3::new(h(i, k), h(i, k + 1), h(i, k + 2));
        let mut undefined = 0;
        for i in 0..2000u64 {
            let moving = |k| Moving {
                at_zero: v(i, k),
                velocity: v(i, k + 3),
            };
            let (mut location, mut look_at, mut up) = (moving(0), moving(6), moving(12));
            match i % 4 {
                // The look-at point sits on the eye: no forward direction.
                0 => look_at = location,
                // The view runs along the up vector: no right direction.
                1 => {
                    up = Moving::still(Vec3::Y);
                    let (x, z) = (location.at_zero.x, location.at_zero.z);
                    let on_y = |m: Moving| Moving {
                        at_zero: Vec3::new(x, m.at_zero.y, z),
                        velocity: Vec3::new(0.0, m.velocity.y, 0.0),
                    };
                    (location, look_at) = (on_y(location), on_y(look_at));
                }
                _ => {}
            }
            let Some(camera) = Camera::new(location, look_at, up, 50.0) else {
                continue;
            };
            let times = std::array::from_fn(|k| h(i, 30 + k as u64) * 0.1);
            let (frames, defined) = frames_at(&camera, Lane::new(times));
            for (k, &t) in times.iter().enumerate() {
                let lane = |v: &V3<Lane>| v.map(|c| c.as_array()[k].to_bits());
                match camera.frame_at(t) {
                    Some(f) => {
                        assert!(defined & (1 << k) != 0, "camera {i}, lane {k}: undefined");
                        let want = [f.eye, f.forward, f.right, f.up]
                            .map(|v| v.to_array().map(f32::to_bits));
                        assert_eq!(frames.each_ref().map(lane), want, "camera {i}, lane {k}");
                    }
                    None => {
                        undefined += 1;
                        assert!(defined & (1 << k) == 0, "camera {i}, lane {k}: defined");
                    }
                }
            }
        }
        assert!(
            undefined > 0,
            "no undefined frame was tried: the test would not fail"
        );
    }
}
