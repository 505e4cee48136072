//! An analytic sphere centred at the object-space origin.

use super::{Bounds, ObjectHit, Ray, ShapeHit};
use glam::Vec3A;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    pub radius: f32,
}

impl Sphere {
    pub fn bounds(&self) -> Bounds {
        Bounds {
            min: Vec3A::splat(-self.radius),
            max: Vec3A::splat(self.radius),
        }
    }

    /// Nearest root of |o + t d|^2 = r^2 in `(t_min, t_max)`.
    pub fn intersect(&self, ray: &Ray) -> Option<ObjectHit> {
        self.closest(ray).map(|h| self.surface(ray, h))
    }

    /// The nearest root in range.
    ///
    /// The discriminant `b'^2 - a c` (with `b' = o.d`, `c = |o|^2 - r^2`) cancels
    /// catastrophically when the ray starts far away (both terms ~ |o|^4); it equals
    /// `a (r - |f|)(r + |f|)` with `f = o - (b'/a) d` the sphere centre's foot on the ray
    /// (pbrt-v4, after Haines et al., "Precision Improvements for Ray/Sphere Intersection",
    /// Ray Tracing Gems 2019), which keeps its relative accuracy at any distance. The roots
    /// come as `q/a` and `c/q`, so neither subtracts nearly equal numbers.
    pub fn closest(&self, ray: &Ray) -> Option<ShapeHit> {
        let (o, d, r) = (ray.origin, ray.dir, self.radius);
        let a = d.length_squared();
        if a == 0.0 || !a.is_finite() {
            return None;
        }
        let half_b = o.dot(d);
        let c = o.length_squared() - r * r;
        let f = (o - d * (half_b / a)).length();
        let disc = a * ((r - f) * (r + f));
        if disc.is_nan() || disc < 0.0 {
            return None;
        }
        let q = -(half_b + half_b.signum() * disc.sqrt());
        let (t0, t1) = if q == 0.0 { (0.0, 0.0) } else { (q / a, c / q) };
        let (t0, t1) = (t0.min(t1), t0.max(t1));
        let t = [t0, t1]
            .into_iter()
            .find(|&t| t > ray.t_min && t < ray.t_max)?;
        Some(ShapeHit { t, primitive: 0 })
    }

    pub fn surface(&self, ray: &Ray, hit: ShapeHit) -> ObjectHit {
        let n = ray.at(hit.t);
        ObjectHit {
            t: hit.t,
            geometric_normal: n,
            shading_normal: n,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roots_are_accurate_from_far_away() {
        // From 1e4 radii away the naive discriminant b'^2 - ac loses every digit
        // (b'^2 ~ 1e16 in f32 has an ulp of 1e9 > ac's variation); the foot form keeps it.
        let s = Sphere { radius: 1.0 };
        for dist in [3.0f32, 1e2, 1e4, 1e5] {
            let r = Ray::new(Vec3A::new(0.6, 0.0, dist), Vec3A::new(0.0, 0.0, -1.0), 0.0);
            let h = s.intersect(&r).expect("hit");
            let exact = dist as f64 - (1.0f64 - 0.36).sqrt();
            // t ~ dist: a few ulps of dist, plus the error of |f| (~u) in sqrt(1 - f^2)/... .
            assert!((h.t as f64 - exact).abs() <= 4.0 * f32::EPSILON as f64 * dist as f64 + 1e-5);
        }
    }

    #[test]
    fn misses_and_degenerate_rays() {
        let s = Sphere { radius: 1.0 };
        let miss = Ray::new(Vec3A::new(1.5, 0.0, 5.0), Vec3A::new(0.0, 0.0, -1.0), 0.0);
        assert!(s.intersect(&miss).is_none());
        let zero = Ray::new(Vec3A::ZERO, Vec3A::ZERO, 0.0);
        assert!(s.intersect(&zero).is_none());
        // From inside, the far root.
        let inside = Ray::new(Vec3A::ZERO, Vec3A::X, 0.0);
        assert_eq!(s.intersect(&inside).map(|h| h.t), Some(1.0));
    }
}
