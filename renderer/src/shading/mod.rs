//! Whitted-style shading (thesis Chapter II, "Ray Tracing"): at a hit, the ambient term, Lambert
//! and Phong terms from every point and directional light that a shadow ray finds unblocked,
//! and a Fresnel-weighted mirror reflection up to `max_depth` bounces; rays that leave the scene
//! see the environment map. No global illumination. Shadow and reflection rays start at
//! [`SurfaceHit::spawn_point`] and keep the primary ray's time.
//!
//! The radiance of a hit with view direction `v`, normal `n` and material (ka, kd, ks, p, F):
//!
//! ```text
//! L = ka * A + Σ_lights V * E * (kd * max(0, n·l) + ks * max(0, r_l·v)^p) + F(n·v) * ks * L(reflected ray)
//! ```
//!
//! with A the ambient light, E the light's irradiance, V its visibility, r_l the mirror image of
//! the light direction l, and F the material's Fresnel curve.

mod chains;
mod packet;

use crate::accel::packet::Centres;
use crate::accel::pose::PoseCache;
use crate::accel::{SurfaceHit, World};
use crate::geometry::Ray;
use crate::light::{Light, LightSample};
use crate::material::Material;
use crate::scene::Scene;
use glam::{Vec3, Vec3A};
use std::cell::{Cell, RefCell};

/// Traces rays through one frame's world (one tracer per thread's piece of work: it counts
/// the rays it casts).
pub struct Tracer<'a> {
    pub world: &'a World,
    pub scene: &'a Scene,
    max_depth: u32,
    rays: Cell<u64>,
    /// The spinning instances' poses at the current camera sample's time.
    poses: PoseCache,
    /// The packet form's orbiting centres, reset per camera packet (`radiance_packet`).
    centres: RefCell<Option<Centres<'a>>>,
}

impl<'a> Tracer<'a> {
    pub fn new(world: &'a World, scene: &'a Scene) -> Self {
        let max_depth = if scene.has_reflections() {
            scene.settings.max_depth
        } else {
            0
        };
        Self {
            world,
            scene,
            max_depth,
            rays: Cell::new(0),
            poses: world.pose_cache(),
            centres: RefCell::new(None),
        }
    }

    /// Rays cast so far (primary, shadow, reflection).
    pub fn rays(&self) -> u64 {
        self.rays.get()
    }

    /// Radiance arriving at `ray.origin` from direction `-ray.dir` (`ray.dir` unit length);
    /// `depth` mirror bounces have been taken already.
    pub fn radiance(&self, ray: &Ray, depth: u32) -> Vec3 {
        self.rays.set(self.rays.get() + 1);
        match self.world.intersect_cached(ray, &self.poses) {
            Some(hit) => self.shade(ray, &hit, depth),
            None => self.background(ray.dir),
        }
    }

    fn background(&self, dir: Vec3A) -> Vec3 {
        match &self.scene.environment {
            Some(env) => env.radiance(dir),
            None => Vec3::ZERO,
        }
    }

    fn shade(&self, ray: &Ray, hit: &SurfaceHit, depth: u32) -> Vec3 {
        let s = Surface::new(self.scene, ray, hit);
        let mut l = self.local(&s, || self.direct(ray, &s));
        if self.reflects(&s, depth) {
            l += self.reflection(ray, &s, depth);
        }
        l
    }

    /// The radiance of a hit before its mirror reflection: the ambient term, then the direct
    /// light (asked of `direct` only for a lit material). With [`Tracer::reflects`], the one
    /// formula of the scalar path, the packet path and the lanes' mirror chains
    /// (`l = local + reflection`).
    #[inline(always)]
    fn local(&self, s: &Surface, direct: impl FnOnce() -> Vec3) -> Vec3 {
        let mut l = s.m.ambient * self.scene.settings.ambient_light;
        if s.m.lit() {
            l += direct();
        }
        l
    }

    /// Whether a hit reached after `depth` bounces adds its mirror reflection.
    #[inline(always)]
    fn reflects(&self, s: &Surface, depth: u32) -> bool {
        depth < self.max_depth && s.m.reflective()
    }

    /// Lambert and Phong terms of every light that reaches the point.
    fn direct(&self, ray: &Ray, s: &Surface) -> Vec3 {
        let mut sum = Vec3::ZERO;
        for light in &self.scene.lights {
            let Some((shadow, sample, cos)) = shadow_ray(ray, s, light) else {
                continue;
            };
            self.rays.set(self.rays.get() + 1);
            if self.world.occluded_cached(&shadow, &self.poses) {
                continue;
            }
            sum += lit_by(s, &sample, cos);
        }
        sum
    }

    fn reflection(&self, ray: &Ray, s: &Surface, depth: u32) -> Vec3 {
        match bounce(ray, s) {
            Some((bounce, weight)) => weight * self.radiance(&bounce, depth + 1),
            None => Vec3::ZERO,
        }
    }
}

/// The mirror ray of a hit and its Fresnel weight; `None` for a material without a Fresnel
/// curve (its reflection is zero).
#[inline]
fn bounce(ray: &Ray, s: &Surface) -> Option<(Ray, Vec3)> {
    let fresnel = s.m.fresnel?;
    let mut dir = reflect(ray.dir, s.ns);
    // An interpolated normal can send the mirror ray into the surface; mirror about the
    // true surface instead.
    if dir.dot(s.ng) <= 0.0 {
        dir = reflect(ray.dir, s.ng);
    }
    let weight = fresnel.reflectance(s.ns.dot(s.v)) * s.m.specular;
    Some((Ray::new(s.hit.spawn_point(dir), dir, ray.time), weight))
}

/// A hit ready to shade: its material, its normals turned towards the viewer, and the
/// direction towards the viewer.
struct Surface<'a> {
    hit: &'a SurfaceHit,
    m: &'a Material,
    ng: Vec3A,
    ns: Vec3A,
    v: Vec3A,
}

impl<'a> Surface<'a> {
    #[inline]
    fn new(scene: &'a Scene, ray: &Ray, hit: &'a SurfaceHit) -> Self {
        let v = -ray.dir;
        let (ng, ns) = facing_normals(hit, v);
        Self {
            hit,
            m: &scene.materials[hit.material as usize],
            ng,
            ns,
            v,
        }
    }
}

/// The shadow ray towards `light` from `hit`, the light's sample and `ns · l`; `None` when the
/// light cannot light the point (it sits on a point light, or lies below the shading or the
/// geometric surface).
#[inline]
fn shadow_ray(ray: &Ray, surface: &Surface, light: &Light) -> Option<(Ray, LightSample, f32)> {
    let hit = surface.hit;
    let s = light.sample(hit.point)?;
    let cos = surface.ns.dot(s.towards);
    if cos <= 0.0 || surface.ng.dot(s.towards) <= 0.0 {
        return None;
    }
    let origin = hit.spawn_point(s.towards);
    let shadow = Ray {
        origin,
        dir: s.towards,
        time: ray.time,
        t_min: 0.0,
        t_max: if s.distance.is_finite() {
            (hit.point - origin).dot(s.towards) + s.distance
        } else {
            f32::INFINITY
        },
    };
    Some((shadow, s, cos))
}

/// The Lambert and Phong terms of an unblocked light sample `s` with `cos = ns · l`.
#[inline]
fn lit_by(surface: &Surface, s: &LightSample, cos: f32) -> Vec3 {
    let (m, ns, v) = (surface.m, surface.ns, surface.v);
    // powf is the dearest step of a diffuse hit: skip it where it adds 0 (same bits:
    // the lobe is finite, so `0 * lobe` is +0 and `x + 0 = x`).
    let specular = if m.specular == Vec3::ZERO {
        Vec3::ZERO
    } else {
        m.specular * phong(reflect(-s.towards, ns).dot(v), m.phong_exponent)
    };
    s.irradiance * (m.diffuse * cos + specular)
}

/// Geometric and shading normals turned towards the viewer `v` (surfaces are two-sided); a
/// degenerate normal falls back to facing the viewer.
#[inline]
fn facing_normals(hit: &SurfaceHit, v: Vec3A) -> (Vec3A, Vec3A) {
    let mut ng = hit.geometric_normal;
    if ng == Vec3A::ZERO || !ng.is_finite() {
        ng = v;
    }
    if ng.dot(v) < 0.0 {
        ng = -ng;
    }
    let mut ns = hit.shading_normal;
    if ns == Vec3A::ZERO || !ns.is_finite() {
        ns = ng;
    }
    if ns.dot(ng) < 0.0 {
        ns = -ns;
    }
    (ng, ns)
}

/// The Phong lobe `max(0, r·v)^p`. `r·v` of two unit vectors can round a hair above 1, and
/// `(1 + 6e-8)^1e9` is infinite: clamped to [0, 1], the lobe stays in [0, 1] for any exponent
/// (the scene loader also bounds `p`: `scene::build::MAX_PHONG_EXPONENT`).
#[inline]
fn phong(r_dot_v: f32, exponent: f32) -> f32 {
    r_dot_v.clamp(0.0, 1.0).powf(exponent)
}

/// `d` mirrored about the unit normal `n`.
#[inline]
fn reflect(d: Vec3A, n: Vec3A) -> Vec3A {
    d - n * (2.0 * d.dot(n))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_phong_lobe_stays_in_the_unit_interval_for_any_exponent() {
        // The overflow seen in mirror renders: r·v one step above 1, exponent 1e9.
        let above = 1.0f32.next_up();
        assert_eq!(
            above.powf(1e9),
            f32::INFINITY,
            "the unclamped lobe overflows"
        );
        for p in [0.0, 1.0, 20.0, 1e6, 1e9, f32::MAX] {
            for c in [above, 1.0 + 1e-3, 1.0, 0.5, 0.0, -0.3] {
                let l = phong(c, p);
                assert!((0.0..=1.0).contains(&l), "phong({c}, {p}) = {l}");
            }
        }
        assert_eq!(phong(above, 1e9), 1.0);
        assert_eq!(phong(0.5, 2.0), 0.25);
        assert_eq!(phong(-0.3, 3.0), 0.0);
    }

    /// A reflected light direction and the view can both be unit length to rounding and give
    /// r·v > 1; over many directions some do, and every lobe stays finite.
    #[test]
    fn mirror_aligned_views_never_give_non_finite_light() {
        let mut above = 0;
        for i in 0..20_000u64 {
            let h = |k: u64| crate::hash::unit_f32(crate::hash::hash(7, &[i, k])) * 2.0 - 1.0;
            let n = Vec3A::new(h(0), 1.0, h(1)).normalize();
            let l = Vec3A::new(h(2), h(3).abs() + 0.1, h(4)).normalize();
            let v = reflect(-l, n);
            let c = reflect(-l, n).dot(v);
            above += usize::from(c > 1.0);
            assert!(phong(c, 1e9).is_finite() && phong(c, MAX_P).is_finite());
        }
        assert!(
            above > 0,
            "no direction rounded above 1: the test would not fail"
        );
    }

    const MAX_P: f32 = crate::scene::build::MAX_PHONG_EXPONENT;
}
