//! Ray-triangle intersection.
//!
//! Placeholder: Moller-Trumbore, which is *not* watertight (rays through shared edges and
//! vertices can slip between triangles). To be replaced by the watertight test of Woop, Benthin
//! and Wald (2013); see `../shared/notes/obvhs.md`.

use super::Ray;
use glam::Vec3A;

/// Parameter `t` of the hit of `ray` with triangle `(a, b, c)` within `(t_min, t_max)`.
#[inline]
pub fn intersect(ray: &Ray, a: Vec3A, b: Vec3A, c: Vec3A) -> Option<f32> {
    let e1 = b - a;
    let e2 = c - a;
    let p = ray.dir.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    let s = ray.origin - a;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = ray.dir.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv;
    (t > ray.t_min && t < ray.t_max).then_some(t)
}

/// Barycentric coordinates `(1 - u - v, u, v)` of point `p` in triangle `(a, b, c)`.
pub fn barycentric(p: Vec3A, a: Vec3A, b: Vec3A, c: Vec3A) -> (f32, f32, f32) {
    let v0 = b - a;
    let v1 = c - a;
    let v2 = p - a;
    let d00 = v0.dot(v0);
    let d01 = v0.dot(v1);
    let d11 = v1.dot(v1);
    let d20 = v2.dot(v0);
    let d21 = v2.dot(v1);
    let denom = d00 * d11 - d01 * d01;
    if denom == 0.0 || !denom.is_finite() {
        return (1.0, 0.0, 0.0);
    }
    let v = (d11 * d20 - d01 * d21) / denom;
    let w = (d00 * d21 - d01 * d20) / denom;
    (1.0 - v - w, v, w)
}
