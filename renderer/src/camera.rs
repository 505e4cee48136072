//! The pinhole camera (thesis Chapter II, "Sampling"): every primary ray starts at the eye
//! where it is at the ray's time and passes through the sample's point on the image plane.
//! Location, look-at point and up vector each move linearly with their own velocity; a camera
//! with no velocity builds its frame once and pays nothing per sample.

use glam::{Vec3, Vec3A};

/// Eye position and orthonormal basis at one time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraFrame {
    pub eye: Vec3A,
    pub forward: Vec3A,
    pub right: Vec3A,
    pub up: Vec3A,
}

impl CameraFrame {
    /// The frame looking from `eye` at `target` with `up` as the rough up direction; `None`
    /// when the view direction is undefined or parallel to `up`.
    pub fn look_at(eye: Vec3A, target: Vec3A, up: Vec3A) -> Option<Self> {
        let forward = (target - eye).try_normalize()?;
        let right = forward.cross(up).try_normalize()?;
        let up = right.cross(forward);
        Some(Self {
            eye,
            forward,
            right,
            up,
        })
    }
}

/// A point and its velocity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Moving {
    pub at_zero: Vec3,
    pub velocity: Vec3,
}

impl Moving {
    pub fn still(p: Vec3) -> Self {
        Self {
            at_zero: p,
            velocity: Vec3::ZERO,
        }
    }

    #[inline]
    pub fn at(&self, t: f32) -> Vec3A {
        Vec3A::from(self.at_zero + self.velocity * t)
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    pub location: Moving,
    pub look_at: Moving,
    pub up: Moving,
    /// Field of view across the image's shorter side, degrees.
    pub fov_degrees: f32,
    /// The frame when nothing moves.
    fixed: Option<CameraFrame>,
}

impl Camera {
    /// A camera; `None` when a motionless camera has no valid frame.
    pub fn new(location: Moving, look_at: Moving, up: Moving, fov_degrees: f32) -> Option<Self> {
        let still = [location, look_at, up]
            .iter()
            .all(|m| m.velocity == Vec3::ZERO);
        let fixed = if still {
            Some(CameraFrame::look_at(
                location.at(0.0),
                look_at.at(0.0),
                up.at(0.0),
            )?)
        } else {
            None
        };
        Some(Self {
            location,
            look_at,
            up,
            fov_degrees,
            fixed,
        })
    }

    /// Whether the camera moves.
    pub fn is_moving(&self) -> bool {
        self.fixed.is_none()
    }

    /// The frame at scene time `t`, or `None` where the look-at point meets the eye or the
    /// up vector lines up with the view.
    #[inline]
    pub fn frame_at(&self, t: f32) -> Option<CameraFrame> {
        match self.fixed {
            Some(f) => Some(f),
            None => CameraFrame::look_at(self.location.at(t), self.look_at.at(t), self.up.at(t)),
        }
    }

    /// The projection for a `width` x `height` image.
    pub fn projection(&self, width: u32, height: u32) -> Projection {
        let half = (self.fov_degrees.to_radians() * 0.5).tan();
        let (w, h) = (width as f32, height as f32);
        let short = w.min(h);
        Projection {
            half_width: half * w / short,
            half_height: half * h / short,
            inv_width: 1.0 / w,
            inv_height: 1.0 / h,
        }
    }
}

/// Image position to ray direction for one image size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    pub(crate) half_width: f32,
    pub(crate) half_height: f32,
    pub(crate) inv_width: f32,
    pub(crate) inv_height: f32,
}

impl Projection {
    /// Unit direction through the film point `(fx, fy)` in pixels from the image's top-left
    /// corner (x right, y down).
    #[inline]
    pub fn direction(&self, frame: &CameraFrame, fx: f32, fy: f32) -> Vec3A {
        let sx = (2.0 * fx * self.inv_width - 1.0) * self.half_width;
        let sy = (1.0 - 2.0 * fy * self.inv_height) * self.half_height;
        (frame.forward + frame.right * sx + frame.up * sy).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera(v: Vec3) -> Camera {
        Camera::new(
            Moving {
                at_zero: Vec3::new(0.0, 0.0, 10.0),
                velocity: v,
            },
            Moving::still(Vec3::ZERO),
            Moving::still(Vec3::Y),
            90.0,
        )
        .unwrap()
    }

    #[test]
    fn centre_and_corners_map_to_the_field_of_view() {
        let cam = camera(Vec3::ZERO);
        assert!(!cam.is_moving());
        let f = cam.frame_at(3.0).unwrap();
        // 4x2 image: the shorter side (height) spans 90°, so tan(half) = 1 vertically and 2
        // horizontally at the edges.
        let p = cam.projection(4, 2);
        let centre = p.direction(&f, 2.0, 1.0);
        assert!((centre - Vec3A::NEG_Z).length() < 1e-6);
        let top_right = p.direction(&f, 4.0, 0.0);
        let expect = Vec3A::new(2.0, 1.0, -1.0).normalize();
        assert!((top_right - expect).length() < 1e-6, "{top_right}");
    }

    #[test]
    fn a_moving_camera_moves_its_eye_and_a_still_one_does_not() {
        let cam = camera(Vec3::new(1.0, 0.0, 0.0));
        assert!(cam.is_moving());
        let f = cam.frame_at(2.0).unwrap();
        assert_eq!(f.eye, Vec3A::new(2.0, 0.0, 10.0));
        assert_eq!(camera(Vec3::ZERO).frame_at(2.0).unwrap().eye.x, 0.0);
    }

    #[test]
    fn degenerate_views_are_refused() {
        let at = Moving::still(Vec3::ZERO);
        assert!(Camera::new(at, at, Moving::still(Vec3::Y), 50.0).is_none());
        let eye = Moving::still(Vec3::new(0.0, 5.0, 0.0));
        assert!(Camera::new(eye, at, Moving::still(Vec3::Y), 50.0).is_none());
    }
}
