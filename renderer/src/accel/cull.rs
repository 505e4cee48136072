//! Which rays of a packet can hit nothing: one box around the whole world, tested in lanes.
//!
//! Why: in the thesis's plane scene most camera rays see only the sky, yet each went through
//! the scalar path to find that out (the top level's ray set-up, the airliner's pose, the ray
//! moved into object space, the mesh BVH's own set-up and root test), part of the 15% of a
//! sample's time `World::intersect_cached` took (`perf`, lanes3; `git show
//! 1615eed:docs/benchmarks/lanes.md`). Eight rays against one box in lanes cost a few
//! instructions per ray.
//!
//! Bit identity: a culled lane is one the scalar path answers with no hit, so its radiance is
//! the environment's, looked up as before. The box is the union of the instances' padded
//! swept bounds (which hold every instance at every time of the shutter), grown by
//! [`MARGIN`] of its size; a lane is culled only when its ray misses that box by more than
//! the rounding of the test itself can explain: the slab parameters `(b - o) / d` carry a
//! relative error of at most three roundings each, so entry and exit are compared with a
//! relative slack of `8u` (`u = 2^-24`). A ray that truly misses the grown box passes at least
//! [`MARGIN`] times the scene's size from any surface, far beyond the scalar tests' rounding,
//! provided its origin is not far outside the scene ([`MAX_ORIGIN`]; else the scalar path's
//! own rounding, which grows with the origin's coordinates, is left to decide). Lanes the box
//! cannot decide (a time outside the shutter, `t_min != 0` is never the case for camera rays,
//! a NaN, an origin inside the box) are kept; a world with unbounded instances (infinite
//! planes) culls nothing.

use super::lanes::{LANES, Lanes, RayPacket};
use crate::geometry::Bounds;

/// Growth of the box per unit of the scene's size (its diagonal plus its largest coordinate).
const MARGIN: f32 = 1e-3;

/// Origins farther than this many scene sizes from zero on any axis are left to the scalar path.
const MAX_ORIGIN: f32 = 100.0;

/// The box every surface of the world lies in during the shutter, grown by [`MARGIN`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct CullBox {
    min: [f32; 3],
    max: [f32; 3],
    /// Largest origin coordinate culled ([`MAX_ORIGIN`] scene sizes).
    origin_limit: f32,
    shutter: (f32, f32),
}

impl CullBox {
    /// The box of `swept` (each bounded instance's padded swept bounds); `None` when some
    /// instance is unbounded or there is nothing to box.
    pub(crate) fn new(swept: &[Bounds], unbounded: bool, shutter: (f32, f32)) -> Option<Self> {
        if unbounded {
            return None;
        }
        let b = swept.iter().fold(Bounds::EMPTY, |b, s| b.union(*s));
        if b.is_empty() || !b.is_finite() {
            return None;
        }
        let size = b.diagonal() + b.magnitude();
        let grown = b.padded(MARGIN * size);
        let limit = MAX_ORIGIN * size;
        (grown.is_finite() && limit.is_finite()).then_some(Self {
            min: grown.min.to_array(),
            max: grown.max.to_array(),
            origin_limit: limit,
            shutter,
        })
    }

    /// The lanes of `live` whose ray may hit something (the others surely hit nothing).
    #[inline(always)]
    pub(crate) fn may_hit<L: Lanes>(&self, ray: &RayPacket<L>, live: u32) -> u32 {
        let slack = L::splat(8.0 * f32::EPSILON * 0.5);
        let (mut entry, mut exit) = (L::ZERO, L::splat(f32::INFINITY));
        let mut decidable = ray.time.simd_ge(L::splat(self.shutter.0))
            & ray.time.simd_le(L::splat(self.shutter.1))
            & ray.t_max.simd_ge(L::ZERO);
        for k in 0..3 {
            let (o, d) = (ray.origin[k], ray.dir[k]);
            decidable &= o.abs().simd_le(L::splat(self.origin_limit));
            let near = (L::splat(self.min[k]) - o) / d;
            let far = (L::splat(self.max[k]) - o) / d;
            // NaN (a zero direction with the origin on a face) fails every comparison below
            // and keeps the lane.
            decidable &= !near.is_nan() & !far.is_nan();
            entry = entry.max(near.min(far));
            exit = exit.min(near.max(far));
        }
        // A miss beyond rounding: entry (>= 0) above exit even after both move by the slack.
        // (Written with products, not `exit + |exit| slack`, which is NaN at `exit = -inf`.)
        let lo = entry * (L::ONE - slack);
        let hi = (exit * (L::ONE + slack)).max(exit * (L::ONE - slack));
        let miss = decidable & lo.simd_gt(hi);
        live & !miss.to_bitmask() & ((1 << LANES) - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Ray;
    use glam::Vec3A;

    fn packet(rays: &[Ray; LANES]) -> RayPacket {
        RayPacket::new(rays)
    }

    fn unit_box() -> CullBox {
        let b = Bounds {
            min: Vec3A::splat(-1.0),
            max: Vec3A::splat(1.0),
        };
        CullBox::new(&[b], false, (0.0, 1.0)).unwrap()
    }

    /// Rays aimed at, past and away from the box: culled exactly when they pass well clear of
    /// it; grazing, parallel, inside, out-of-shutter and NaN rays are kept.
    #[test]
    fn culls_only_rays_that_clearly_miss() {
        let c = unit_box();
        let ray = |o: [f32; 3], d: [f32; 3], time: f32| Ray {
            origin: Vec3A::from(o),
            dir: Vec3A::from(d).normalize(),
            time,
            t_min: 0.0,
            t_max: f32::INFINITY,
        };
        let rays = [
            ray([0.0, 0.0, -5.0], [0.0, 0.0, 1.0], 0.5), // through the centre: kept
            ray([0.0, 1.0, -5.0], [0.0, 0.0, 1.0], 0.5), // along a face: kept
            ray([0.0, 3.0, -5.0], [0.0, 0.0, 1.0], 0.5), // parallel, clear: culled
            ray([0.0, 0.0, -5.0], [0.0, 0.0, -1.0], 0.5), // away from it: culled
            ray([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], 0.5),  // from inside: kept
            ray([0.0, 3.0, -5.0], [0.0, 0.0, 1.0], 2.0), // clear but out of shutter: kept
            ray([0.0, 3.0, -5.0], [0.0, -0.4, 1.0], 0.5), // slanting into it: kept
            ray([0.0, 3.0, -5.0], [0.0, f32::NAN, 1.0], 0.5),
        ];
        assert_eq!(c.may_hit(&packet(&rays), 0xff), 0b1111_0011);
        assert_eq!(c.may_hit(&packet(&rays), 0b0000_0001), 0b0000_0001);
    }

    /// Against the world: no ray the scalar path sees hit anything is ever culled (random boxes
    /// of spheres, rays from all around, many of them grazing).
    #[test]
    fn never_culls_a_ray_the_world_hits() {
        use crate::accel::{Instance, World};
        use crate::geometry::{Shape, Sphere};
        use crate::motion::{Motion, MotionLayer};
        use glam::Vec3;
        let h = |i: u64, k: u64| crate::hash::unit_f32(crate::hash::hash(31, &[i, k]));
        let mut culled = 0;
        for w in 0..20u64 {
            let r = 0.5 + 3.0 * h(w, 0);
            let at = Vec3::new(h(w, 1), h(w, 2), h(w, 3)) * 20.0 - 10.0;
            let velocity = Vec3::new(h(w, 4), 0.0, 0.0) * 30.0;
            let instance = Instance {
                shape: Shape::Sphere(Sphere { radius: r }),
                motion: Motion {
                    layers: vec![MotionLayer {
                        location: at,
                        velocity,
                        ..MotionLayer::default()
                    }],
                },
                material: 0,
            };
            let world = World::build(vec![instance], (0.0, 0.1));
            for p in 0..64u64 {
                let rays: [Ray; LANES] = std::array::from_fn(|k| {
                    let q = p * LANES as u64 + k as u64;
                    let o = Vec3A::new(h(q, 10), h(q, 11), h(q, 12)) * 200.0 - 100.0;
                    // Aim at the sphere, near its silhouette and past it, at a random time.
                    let t = 0.1 * h(q, 13);
                    let c = Vec3A::from(at + velocity * t);
                    let j = Vec3A::new(h(q, 14), h(q, 15), h(q, 16)) * 2.0 - 1.0;
                    let aim = c + j.normalize_or_zero() * r * (0.8 + 2.0 * h(q, 17));
                    Ray::new(o, (aim - o).normalize(), t)
                });
                let keep = world.may_hit_lanes(&packet(&rays), 0xff);
                for (k, ray) in rays.iter().enumerate() {
                    let hit = world.intersect(ray).is_some();
                    assert!(!hit || keep & (1 << k) != 0, "world {w} ray {p}/{k} culled");
                    culled += u32::from(keep & (1 << k) == 0);
                }
            }
        }
        // Most rays aimed past the silhouette pass through the sphere's swept box or near it,
        // but those aimed far enough past it are culled.
        assert!(culled > 500, "culled {culled} of {}", 20 * 64 * LANES);
    }
}
