//! Watertight ray-triangle intersection (Woop, Benthin and Wald, "Watertight Ray/Triangle
//! Intersection", JCGT 2013).
//!
//! The ray is made the +z axis of a sheared frame; every vertex is moved into that frame by the
//! same per-ray map, and the hit test is the signs of three 2D edge functions. Because a shared
//! vertex is mapped to the same bits in every triangle that uses it, and `a*b - c*d` computed for
//! the edge (P, Q) is exactly the negation of the value computed for (Q, P), a ray can never slip
//! between two triangles that share an edge or a vertex. When an edge function rounds to zero it
//! is recomputed in f64, where the products of f32 values are exact, so its sign is exact.
//!
//! Möller-Trumbore (the previous placeholder, and obvhs's own test) lacks that property: rays
//! aimed at vertices and edge midpoints of a closed mesh escape through it
//! (`docs/geometry.md`, "Ray-triangle intersection").

use super::Ray;
use glam::Vec3A;

/// A ray prepared for many triangle tests: its origin and the shear that maps `dir` to +z.
#[derive(Clone, Copy, Debug)]
pub struct WatertightRay {
    origin: Vec3A,
    /// The axis permutation (kx, ky, kz): kz the dominant axis of `dir`.
    pub(crate) axes: [usize; 3],
    /// The shear (Sx, Sy, Sz) = (d_kx / d_kz, d_ky / d_kz, 1 / d_kz).
    pub(crate) shear: [f32; 3],
    /// False when the direction is zero or not finite, or the origin is not finite: such a ray
    /// hits nothing.
    valid: bool,
}

/// A hit of a ray with one triangle: parameter and barycentric weights of the three corners.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    pub t: f32,
    /// Weights of corners (a, b, c); they sum to 1 up to rounding.
    pub barycentric: [f32; 3],
}

impl WatertightRay {
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        let valid = ray.dir.is_finite() && ray.dir != Vec3A::ZERO && ray.origin.is_finite();
        // Arrays, not glam's `Vec3A[i]`, whose runtime index is a three-way branch.
        let d = ray.dir.to_array();
        let a = d.map(f32::abs);
        // kz: the dominant axis, so the divisions below are by the largest component.
        let kz = if a[0] >= a[1] && a[0] >= a[2] {
            0
        } else if a[1] >= a[2] {
            1
        } else {
            2
        };
        let (mut kx, mut ky) = ([1, 2, 0][kz], [2, 0, 1][kz]);
        // Keep the winding (and so the sign of the determinant) independent of the direction.
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let shear = if valid {
            [d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]]
        } else {
            [0.0; 3]
        };
        Self {
            origin: ray.origin,
            axes: [kx, ky, kz],
            shear,
            valid,
        }
    }

    pub(crate) fn origin(&self) -> Vec3A {
        self.origin
    }

    /// Whether the ray can hit anything (finite origin, finite non-zero direction).
    #[inline]
    pub fn is_valid(&self) -> bool {
        self.valid
    }

    /// The vertex `p` in the ray's sheared frame: (x, y) in the plane across the ray, and z
    /// scaled so that the hit parameter is an interpolation of the corners' z. The same
    /// operations, in the same order, as each lane of [`super::triangle4`].
    #[inline(always)]
    fn shear(&self, p: Vec3A) -> Vec3A {
        let d = (p - self.origin).to_array();
        let [kx, ky, kz] = self.axes;
        let [sx, sy, sz] = self.shear;
        Vec3A::new(d[kx] - sx * d[kz], d[ky] - sy * d[kz], sz * d[kz])
    }

    /// The hit with triangle `(a, b, c)` for `t_min < t < t_max`, or `None`. Both faces count.
    /// Never returns a non-finite `t` and never hits a zero-area triangle or a ray lying in the
    /// triangle's plane (both have determinant 0).
    #[inline(always)]
    pub fn intersect(
        &self,
        a: Vec3A,
        b: Vec3A,
        c: Vec3A,
        t_min: f32,
        t_max: f32,
    ) -> Option<TriangleHit> {
        let (t, [u, v, w], det) = self.intersect_raw(a, b, c, t_min, t_max)?;
        let inv = 1.0 / det;
        Some(TriangleHit {
            t,
            barycentric: [u * inv, v * inv, w * inv],
        })
    }

    /// Like [`WatertightRay::intersect`] but returns only `t` (the traversal's inner loop).
    #[inline(always)]
    pub fn intersect_t(&self, a: Vec3A, b: Vec3A, c: Vec3A, t_min: f32, t_max: f32) -> Option<f32> {
        self.intersect_raw(a, b, c, t_min, t_max).map(|h| h.0)
    }

    /// `(t, unnormalised barycentrics (U, V, W), det)`.
    #[inline(always)]
    fn intersect_raw(
        &self,
        a: Vec3A,
        b: Vec3A,
        c: Vec3A,
        t_min: f32,
        t_max: f32,
    ) -> Option<(f32, [f32; 3], f32)> {
        if !self.valid {
            return None;
        }
        let (a, b, c) = (self.shear(a), self.shear(b), self.shear(c));
        let mut u = c.x * b.y - c.y * b.x;
        let mut v = a.x * c.y - a.y * c.x;
        let mut w = b.x * a.y - b.y * a.x;
        if u == 0.0 || v == 0.0 || w == 0.0 {
            [u, v, w] = exact_edges(a, b, c);
        }
        // Mixed signs: the ray passes outside one edge (zeros are on the edge: inside).
        if u.min(v).min(w) < 0.0 && u.max(v).max(w) > 0.0 {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        // t * det, as the paper writes it: the corners' depths weighted by the edge functions.
        let t_scaled = u * a.z + v * b.z + w * c.z;
        let t = t_scaled / det;
        // NaN and infinities fail both comparisons.
        (t > t_min && t < t_max).then_some((t, [u, v, w], det))
    }
}

/// The edge functions with exact signs: each f32 x f32 product is exact in f64, and the
/// difference of two exact values is rounded once, which cannot change its sign. Rare (the ray
/// passes exactly through an edge or vertex in the sheared frame), so kept out of line: the
/// traversal's closure stays small enough to be inlined.
#[cold]
#[inline(never)]
pub(crate) fn exact_edges(a: Vec3A, b: Vec3A, c: Vec3A) -> [f32; 3] {
    let e = |p: Vec3A, q: Vec3A| (p.x as f64 * q.y as f64 - p.y as f64 * q.x as f64) as f32;
    [e(c, b), e(a, c), e(b, a)]
}

/// Parameter `t` of the hit of `ray` with triangle `(a, b, c)` within `(t_min, t_max)`
/// (watertight; prepares the ray each call, so prefer [`WatertightRay`] for many triangles).
#[inline]
pub fn intersect(ray: &Ray, a: Vec3A, b: Vec3A, c: Vec3A) -> Option<f32> {
    WatertightRay::new(ray).intersect_t(a, b, c, ray.t_min, ray.t_max)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(o: [f32; 3], d: [f32; 3]) -> Ray {
        Ray::new(Vec3A::from(o), Vec3A::from(d), 0.0)
    }

    const A: Vec3A = Vec3A::new(0.0, 0.0, 0.0);
    const B: Vec3A = Vec3A::new(1.0, 0.0, 0.0);
    const C: Vec3A = Vec3A::new(0.0, 1.0, 0.0);

    #[test]
    fn hits_inside_with_the_right_t_and_weights() {
        let r = ray([0.25, 0.25, 2.0], [0.0, 0.0, -1.0]);
        let h = WatertightRay::new(&r).intersect(A, B, C, 0.0, f32::INFINITY);
        let h = h.expect("hit");
        // All inputs are dyadic rationals, so every operation is exact.
        assert_eq!(h.t, 2.0);
        assert_eq!(h.barycentric, [0.5, 0.25, 0.25]);
        // Both faces count, and the weights do not depend on the side.
        let back = ray([0.25, 0.25, -2.0], [0.0, 0.0, 1.0]);
        let hb = WatertightRay::new(&back).intersect(A, B, C, 0.0, f32::INFINITY);
        assert_eq!(hb, Some(h));
    }

    #[test]
    fn misses_outside_behind_and_beyond_t_max() {
        let outside = ray([0.75, 0.75, 2.0], [0.0, 0.0, -1.0]);
        assert_eq!(intersect(&outside, A, B, C), None);
        let behind = ray([0.25, 0.25, 2.0], [0.0, 0.0, 1.0]);
        assert_eq!(intersect(&behind, A, B, C), None);
        let mut short = ray([0.25, 0.25, 2.0], [0.0, 0.0, -1.0]);
        short.t_max = 2.0; // open interval: t = 2 exactly is out
        assert_eq!(intersect(&short, A, B, C), None);
        short.t_max = 2.0f32.next_up();
        assert_eq!(intersect(&short, A, B, C), Some(2.0));
    }

    #[test]
    fn both_triangles_of_a_shared_edge_agree() {
        // Square split along its diagonal; rays through points of the diagonal from oblique
        // directions hit at least one of the two halves.
        let d = Vec3A::new(1.0, 1.0, 0.0);
        let mut missed = 0;
        for i in 0..=1000 {
            let p = Vec3A::new(0.0, 0.0, 0.0).lerp(d, i as f32 / 1000.0);
            let dir = Vec3A::new(0.3, -0.7, -1.0);
            let r = Ray::new(p - dir * 3.7, dir, 0.0);
            let w = WatertightRay::new(&r);
            let h1 = w.intersect_t(A, B, d, 0.0, f32::INFINITY);
            let h2 = w.intersect_t(A, d, C, 0.0, f32::INFINITY);
            missed += usize::from(h1.is_none() && h2.is_none());
        }
        assert_eq!(missed, 0);
    }

    #[test]
    fn degenerate_triangles_and_rays_never_hit_and_never_give_nan() {
        let r = ray([0.2, 0.2, 1.0], [0.0, 0.0, -1.0]);
        // Zero area: a point, and three collinear points (through the ray's foot).
        assert_eq!(intersect(&r, B, B, B), None);
        let line = Vec3A::new(0.2, 0.2, 0.0);
        assert_eq!(intersect(&r, A, line, line * 2.0), None);
        // A ray in the triangle's plane, through its interior.
        let grazing = ray([-1.0, 0.2, 0.0], [1.0, 0.0, 0.0]);
        assert_eq!(intersect(&grazing, A, B, C), None);
        // Zero and non-finite directions and origins.
        for d in [[0.0; 3], [f32::NAN, 0.0, -1.0], [0.0, f32::INFINITY, -1.0]] {
            assert_eq!(intersect(&ray([0.2, 0.2, 1.0], d), A, B, C), None);
        }
        assert_eq!(
            intersect(&ray([f32::NAN, 0.2, 1.0], [0.0, 0.0, -1.0]), A, B, C),
            None
        );
        // Huge coordinates: t stays finite or the test misses.
        let far = ray([0.2, 0.2, 3e38], [0.0, 0.0, -1.0]);
        if let Some(t) = intersect(&far, A, B, C) {
            assert!(t.is_finite());
        }
    }

    #[test]
    fn nearly_grazing_rays_give_finite_t_inside_the_range() {
        for k in 1..40 {
            let dz = -(2.0f32).powi(-k);
            let r = ray([-0.5, 0.3, 0.5 * (2.0f32).powi(-k)], [1.0, 0.0, dz]);
            if let Some(h) = WatertightRay::new(&r).intersect(A, B, C, 0.0, f32::INFINITY) {
                assert!(h.t.is_finite() && h.t > 0.0);
                assert!(h.barycentric.iter().all(|b| b.is_finite()));
            }
        }
    }
}
