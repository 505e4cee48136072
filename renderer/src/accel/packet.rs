//! [`LANES`] rays at once against a small analytic world: the "small world" packet form of a
//! [`World`] made only of spheres and planes.
//!
//! Why: on a scene of a sphere over a plane, one camera sample is a chain of dependent square
//! roots and divisions (top-level traversal, sphere roots, normals, the shadow ray), so a
//! single ray keeps the core waiting on latency. Independent rays in the lanes of a [`Lane`]
//! vector fill those waits: every instance is tested for all lanes at once, brute force
//! (with a handful of instances a top-level BVH costs more than it saves).
//!
//! Bit identity with [`World::intersect`] and [`World::occluded`] is the contract: every lane
//! does the scalar code's f32 operations in the scalar code's order (glam's SSE2 `dot` is
//! `(x x' + y y') + z z'`, `Mat3A * v` is `(c0 v.x + c1 v.y) + c2 v.z`; Rust never fuses a
//! multiply-add), so a lane's parameter `t` is the scalar one to the bit. The winner's normals
//! are worked out lane by lane the same way. What brute force
//! cannot promise, the lane hands back to the scalar path:
//! - two instances at exactly the same nearest `t` (the scalar path keeps the first in its
//!   top-level BVH order, which brute force does not know);
//! - a ray the scalar path treats specially: non-finite or zero direction, non-finite origin
//!   (bounded instances are skipped there), a time outside the shutter, `t_min != 0`, a NaN
//!   `t_max`.
//!
//! Otherwise the top level cannot change the answer: its boxes are the instances' swept bounds,
//! padded, so it only culls instances that cannot hold a nearer hit, and each shape's nearest
//! root below the running `t_max` is its nearest root below the ray's `t_max` whenever it can
//! win. Fixed and translating instances, turned or not, are computed exactly; so are spheres
//! orbiting under a chain of one spin ([`crate::accel::pose::PoseOverTime::Orbiting`]): their
//! centres at the packet's eight times are worked out once per packet, each when first asked
//! for (`SmallWorld::centres`: each spin's rotation per lane by
//! [`Spin::at`](super::chain::Spin::at), the scalar path's own call, then
//! [`SpinChain::centre`]'s products in lanes), and shared by the packet's shadow and mirror
//! rays, which carry the same times. Other spinning instances are not packet-eligible.
//!
//! [`SpinChain::centre`]: super::chain::SpinChain::centre
//! [`World`]: super::World
//! [`World::intersect`]: super::World::intersect
//! [`World::occluded`]: super::World::occluded

use super::Instance;
use super::around::Around;
use super::instant::Pose;
use super::lanes::{Lane, Lanes, MAX_INSTANCES, RayPacket, SLACK, dot, each, mul, point_at};
pub(crate) use super::orbits::Centres;
use super::orbits::Orbits;
use super::pose::{PoseOverTime, Spins};
#[cfg(test)]
use super::{SurfaceHit, World, lanes::LANES};
#[cfg(test)]
use crate::geometry::Ray;
use crate::geometry::{Bounds, Shape};
use glam::{Mat3A, Vec3A};

/// The packet form of a world of at most [`MAX_INSTANCES`] spheres and planes.
#[derive(Clone, Debug)]
pub struct SmallWorld {
    /// One per instance, in the world's instance order.
    shapes: Vec<SmallShape>,
    /// The orbiting spheres ([`SmallPose::orbit`] indexes them) and their groups.
    orbits: Orbits,
    /// The instances tested by every ray: all but the orbiting spheres of a group.
    loose: Vec<u32>,
    /// Per instance, a sphere around it over the shutter ([`Around`]); a grouped orbiting
    /// sphere is placed and tested only for the lanes that may meet it.
    around: Vec<Option<Around>>,
}

#[derive(Clone, Copy, Debug)]
struct SmallShape {
    kind: Kind,
    pose: SmallPose,
    material: u32,
    /// A plane's world normal, the same for every point: worked out once, by the lane code
    /// (so to the bit what each lane would compute).
    plane_normal: [f32; 3],
}

#[derive(Clone, Copy, Debug)]
enum Kind {
    Sphere {
        radius: f32,
    },
    /// `None`: infinite; else the rectangle's half extents in x and z.
    Plane {
        half_extent: Option<(f32, f32)>,
    },
}

/// A fixed or translating pose: translation `at + velocity * t` (as [`PoseOverTime::at`]
/// computes it; a fixed pose adds nothing, not even `0 * t`, which would turn `-0` into `+0`),
/// and the object-from-world matrix unless the pose is unturned; or an orbiting sphere's,
/// whose translation is its centre at the packet's times.
#[derive(Clone, Copy, Debug)]
struct SmallPose {
    translation: Vec3A,
    velocity: Option<Vec3A>,
    matrix: Option<Mat3A>,
    /// `matrix` transposed (normals go to world space through it).
    transposed: Mat3A,
    /// An orbiting sphere's index in [`Orbits`] (and in [`Centres`]).
    orbit: Option<usize>,
}

impl SmallPose {
    /// The packet form of `pose`; an orbiting one's chain goes into `orbits`.
    fn new(pose: &PoseOverTime, orbits: &mut Orbits) -> Option<Self> {
        let (p, velocity): (&Pose, _) = match pose {
            PoseOverTime::Fixed(p) => (p, None),
            PoseOverTime::Translating { at_zero, velocity } => (at_zero, Some(*velocity)),
            PoseOverTime::Spinning(_) => return None,
            PoseOverTime::Orbiting(o) => {
                let k = orbits.add(o)?;
                // Unturned: rays move by the centre alone.
                return Some(Self {
                    translation: Vec3A::ZERO,
                    velocity: None,
                    matrix: None,
                    transposed: Mat3A::IDENTITY,
                    orbit: Some(k),
                });
            }
        };
        Some(Self {
            translation: p.translation,
            velocity,
            matrix: (!p.unturned).then_some(p.object_from_world),
            transposed: p.object_from_world.transpose(),
            orbit: None,
        })
    }

    /// The unit world-space normal of the object-space normal `local`: through the inverse
    /// transpose, normalised, as `World::intersect` does it.
    #[inline(always)]
    fn world_normal<L: Lanes>(&self, local: [L; 3]) -> [L; 3] {
        let world = match self.matrix {
            None => local,
            Some(_) => mul(&self.transposed, local),
        };
        normalize_or_zero(world)
    }

    /// The packet's rays in object space: `(origin, dir)` per axis.
    #[inline(always)]
    fn ray_to_object<L: Lanes>(&self, ray: &RayPacket<L>, centres: &Centres) -> ([L; 3], [L; 3]) {
        let p = self.translation.to_array();
        let tr: [L; 3] = match (self.orbit, self.velocity) {
            (Some(k), _) => centres.of(k),
            (None, None) => p.map(L::splat),
            (None, Some(v)) => {
                let v = v.to_array();
                each(|k| L::splat(p[k]) + L::splat(v[k]) * ray.time)
            }
        };
        let o = each(|k| ray.origin[k] - tr[k]);
        match &self.matrix {
            None => (o, ray.dir),
            Some(m) => (mul(m, o), mul(m, ray.dir)),
        }
    }
}

/// `f32::min` / `f32::max` lane by lane where it matters: a NaN operand gives the other one.
/// (Which zero two equal zeros give does not matter: a zero is never above `t_min = 0`.)
#[inline(always)]
fn min_max<L: Lanes>(a: L, b: L) -> (L, L) {
    let a_nan = a.is_nan();
    let min_is_b = b.simd_lt(a) | a_nan;
    let max_is_b = a.simd_lt(b) | a_nan;
    (min_is_b.bitselect(b, a), max_is_b.bitselect(b, a))
}

/// The nearest sphere root in `(0, t_max)` per lane ([`crate::geometry::Sphere::closest`]'s
/// arithmetic), `+inf` where there is none; only the lanes of `active` need be right. `a` is
/// `d · d`, worked out once per packet for the spheres that take the rays' own directions.
#[inline(always)]
fn sphere<L: Lanes>(radius: f32, o: &[L; 3], d: &[L; 3], a: L, t_max: L, active: u32) -> L {
    let r = L::splat(radius);
    let half_b = dot(o, d);
    let oo = dot(o, o);
    let c = oo - L::splat(radius * radius);
    // Outside (c > 0) and moving away (half_b > 0): q = -(half_b + sqrt(disc)) < 0, so both
    // roots, q / a and c / q, are negative or -0 and neither is above 0. If every active lane
    // is so, skip the division and the square roots (a shadow ray leaving the sphere).
    let away = c.simd_gt(L::ZERO) & half_b.simd_gt(L::ZERO);
    if active & !away.to_bitmask() == 0 {
        return L::splat(f32::INFINITY);
    }
    // Passing clearly outside: the line's squared distance from the centre times `a`,
    // `a |o|^2 - (o·d)^2`, above `a r^2 (1 + 2^-10)^2` by more than its rounding
    // ([`SLACK`]` a |o|^2`), so the foot `f` below, off by a few `u |o|`, is above `r` too and the
    // lane misses ([`SLACK`]). If every active lane passes outside or moves away, skip the rest.
    let oo_a = a * oo;
    let wide = radius * (1.0 + 1.0 / 1024.0);
    let limit = a * L::splat(wide * wide) + L::splat(SLACK) * oo_a;
    let past = (oo_a - half_b * half_b).simd_gt(limit);
    if active & !(away | past).to_bitmask() == 0 {
        return L::splat(f32::INFINITY);
    }
    let k = half_b / a;
    let foot: [L; 3] = each(|i| o[i] - d[i] * k);
    let f = dot(&foot, &foot).sqrt();
    let disc = a * ((r - f) * (r + f));
    // `signum`: 1 with half_b's sign (a NaN half_b makes q NaN either way).
    let ok = a.simd_ne(L::ZERO) & a.is_finite() & disc.simd_ge(L::ZERO);
    if !ok.any() {
        // Every lane misses: skip the roots' square root and two divisions.
        return L::splat(f32::INFINITY);
    }
    let sign = (half_b & L::splat(-0.0)) | L::ONE;
    let q = -(half_b + sign * disc.sqrt());
    // q == 0 gives the roots (0, 0) in the scalar code: never above t_min = 0.
    let ok = ok & q.simd_ne(L::ZERO);
    let (t0, t1) = min_max(q / a, c / q);
    let (in0, in1) = (in_range(t0, t_max), in_range(t1, t_max));
    let t = in0.bitselect(t0, in1.bitselect(t1, L::splat(f32::INFINITY)));
    ok.bitselect(t, L::splat(f32::INFINITY))
}

/// The lanes where `t` is in `(0, t_max)`.
#[inline(always)]
fn in_range<L: Lanes>(t: L, t_max: L) -> L {
    t.simd_gt(L::ZERO) & t.simd_lt(t_max)
}

/// The lanes where every component of `v` is finite.
#[inline(always)]
fn finite<L: Lanes>(v: &[L; 3]) -> L {
    v[0].is_finite() & v[1].is_finite() & v[2].is_finite()
}

/// The plane y = 0 per lane ([`crate::geometry::Plane::closest`]'s arithmetic), `+inf` where
/// it is missed; only the lanes of `active` need be right.
#[inline(always)]
fn plane<L: Lanes>(half: Option<(f32, f32)>, o: &[L; 3], d: &[L; 3], t_max: L, active: u32) -> L {
    // t = -o.y / d.y is above 0 only where o.y and d.y are non-zero with opposite signs
    // (else it is negative, a zero or NaN): if no active lane is so, skip the division (a
    // shadow ray leaving the plane, a camera ray looking up).
    let (oy, dy) = (o[1], d[1]);
    let towards =
        (oy.simd_lt(L::ZERO) & dy.simd_gt(L::ZERO)) | (oy.simd_gt(L::ZERO) & dy.simd_lt(L::ZERO));
    if active & towards.to_bitmask() == 0 {
        return L::splat(f32::INFINITY);
    }
    let t = -o[1] / d[1];
    // A zero d.y gives an infinite or NaN t, which fails the range test anyway.
    let mut ok = d[1].simd_ne(L::ZERO) & t.simd_gt(L::ZERO) & t.simd_lt(t_max);
    if let Some((hx, hz)) = half {
        let px = o[0] + d[0] * t;
        let pz = o[2] + d[2] * t;
        ok = ok & px.abs().simd_le(L::splat(hx)) & pz.abs().simd_le(L::splat(hz));
    }
    ok.bitselect(t, L::splat(f32::INFINITY))
}

/// The lanes as vectors.
#[cfg(test)]
#[inline(always)]
fn lanes_of<L: Lanes>(v: &[L; 3]) -> [Vec3A; LANES] {
    let [x, y, z] = v.map(|c| c.to_array());
    std::array::from_fn(|i| Vec3A::new(x[i], y[i], z[i]))
}

/// glam's `normalize_or_zero` lane by lane: `v * (1 / sqrt(v.v))` where that factor is finite
/// and positive, else zero.
#[inline(always)]
fn normalize_or_zero<L: Lanes>(v: [L; 3]) -> [L; 3] {
    let rcp = L::ONE / dot(&v, &v).sqrt();
    let ok = rcp.is_finite() & rcp.simd_gt(L::ZERO);
    each(|k| ok.bitselect(v[k] * rcp, L::ZERO))
}

impl SmallShape {
    /// The unit world-space normal at parameter `t` of each lane's ray (geometric and shading
    /// normal alike for spheres and planes): the object-space normal ([`Shape::surface`]),
    /// through the inverse transpose, normalised, as `World::intersect` does it.
    #[inline(always)]
    fn world_normal<L: Lanes>(&self, ray: &RayPacket<L>, t: L, centres: &Centres) -> [L; 3] {
        match self.kind {
            Kind::Sphere { .. } => {
                let (o, d) = self.pose.ray_to_object(ray, centres);
                self.pose.world_normal(point_at(&o, &d, t))
            }
            Kind::Plane { .. } => self.plane_normal.map(L::splat),
        }
    }

    /// Each lane's nearest hit in `(0, t_max)`, `+inf` for none; only the lanes of `active`
    /// need be right. `dd` is the rays' `d · d`.
    #[inline(always)]
    fn closest<L: Lanes>(&self, ray: &RayPacket<L>, dd: L, active: u32, centres: &Centres) -> L {
        let (o, d) = self.pose.ray_to_object(ray, centres);
        match self.kind {
            Kind::Sphere { radius } => {
                // An unturned pose keeps the rays' directions, so their `d · d`.
                let a = match self.pose.matrix {
                    None => dd,
                    Some(_) => dot(&d, &d),
                };
                sphere(radius, &o, &d, a, ray.t_max, active)
            }
            Kind::Plane { half_extent } => plane(half_extent, &o, &d, ray.t_max, active),
        }
    }
}

impl SmallWorld {
    /// The packet form of a world with these instances, their shapes as their poses place
    /// them, their poses and the distinct spins (`World`'s), or `None` if it has a mesh, a
    /// spinning instance other than a sphere orbiting under one spin, or more than
    /// [`MAX_INSTANCES`] instances.
    /// `swept` holds each instance's padded box over the shutter.
    pub fn new(
        instances: &[Instance],
        shapes: &[Shape],
        poses: &[PoseOverTime],
        spins: &Spins,
        swept: &[Bounds],
    ) -> Option<Self> {
        if instances.len() > MAX_INSTANCES {
            return None;
        }
        let spins = (0..spins.len() as u32).map(|i| *spins.get(i)).collect();
        let mut orbits = Orbits::new(spins);
        let shapes = instances
            .iter()
            .zip(shapes)
            .zip(poses)
            .map(|((instance, shape), pose)| {
                let kind = match shape {
                    Shape::Sphere(s) => Kind::Sphere { radius: s.radius },
                    Shape::Plane(p) => Kind::Plane {
                        half_extent: p.half_extent.map(|h| (h.x, h.y)),
                    },
                    Shape::Mesh(_) => return None,
                };
                let pose = SmallPose::new(pose, &mut orbits)?;
                let y = pose.world_normal([Lane::ZERO, Lane::ONE, Lane::ZERO]);
                Some(SmallShape {
                    kind,
                    pose,
                    material: instance.material,
                    plane_normal: y.map(|c| c.as_array()[0]),
                })
            })
            .collect::<Option<Vec<_>>>()?;
        let spheres: Vec<(u32, usize, f32)> = (0..shapes.len() as u32)
            .zip(&shapes)
            .filter_map(|(i, s)| match (s.pose.orbit, s.kind) {
                (Some(k), Kind::Sphere { radius }) => Some((i, k, radius)),
                _ => None,
            })
            .collect();
        let grouped = orbits.group(&spheres);
        let mut loose: Vec<u32> = (0..shapes.len() as u32)
            .filter(|&i| shapes[i as usize].pose.orbit.is_none())
            .collect();
        loose.extend(grouped);
        let around = swept
            .iter()
            .zip(&shapes)
            .map(|(b, shape)| match shape.kind {
                Kind::Sphere { radius } => Around::new(*b, radius),
                Kind::Plane { .. } => Around::new(*b, 0.0),
            })
            .collect();
        Some(Self {
            shapes,
            orbits,
            loose,
            around,
        })
    }

    /// The orbiting spheres' centres (and their groups' heads) at the times `time` of a
    /// packet's lanes ([`Orbits::centres`]), for every ray of the packet.
    #[inline]
    pub(crate) fn centres(&self, time: Lane) -> Centres<'_> {
        self.orbits.centres(time)
    }
}

/// Rays laid out one by one: the entry points of the bit-identity tests, which hold these
/// answers against `World::intersect` and `World::occluded`. They wrap the packet API
/// below ([`SmallWorld::nearest`], [`SmallShape::world_normal`], [`SmallWorld::blocked`]),
/// which is what the renderer calls with rays that stay in lanes.
#[cfg(test)]
impl SmallWorld {
    /// The lanes (bit `i` for lane `i`) of `live` this form answers itself; the others go to
    /// the scalar path.
    #[inline]
    fn simple_lanes(world: &World, rays: &[Ray; LANES], live: u32) -> u32 {
        let lanes = (0..LANES).fold(0, |m, i| m | (u32::from(simple(world, &rays[i])) << i));
        lanes & live
    }

    /// `World::intersect` for each live lane (bit `i` of `live`), in lanes of type `L`;
    /// `None` for the others.
    #[inline(always)]
    pub fn intersect_lanes<L: Lanes>(
        &self,
        world: &World,
        rays: &[Ray; LANES],
        live: u32,
    ) -> [Option<SurfaceHit>; LANES] {
        let simple = Self::simple_lanes(world, rays, live);
        let mut out = [None; LANES];
        let mut scalar = live & !simple;
        if simple != 0 {
            let packet = RayPacket::<L>::of(rays, simple);
            let centres = self.centres(packet.time.to_wide());
            let nearest = self.nearest(&packet, simple, &centres);
            scalar |= self.surfaces(&packet, &nearest, simple, &centres, &mut out);
        }
        for (i, slot) in out.iter_mut().enumerate() {
            if scalar & (1 << i) != 0 {
                *slot = world.intersect(&rays[i]);
            }
        }
        out
    }

    /// The world-space hits of the lanes of `simple` that hit one instance first
    /// (`World::intersect`'s last step), one instance at a time for the lanes it won;
    /// returns the lanes with a tie, left to the scalar path.
    #[inline(always)]
    fn surfaces<L: Lanes>(
        &self,
        ray: &RayPacket<L>,
        nearest: &Nearest<L>,
        simple: u32,
        centres: &Centres,
        out: &mut [Option<SurfaceHit>; LANES],
    ) -> u32 {
        let tie = simple & nearest.tie.to_bitmask();
        let hit = nearest.hit();
        let mut pending = simple & !tie & hit;
        if pending == 0 {
            return tie;
        }
        let t = nearest.t.to_array();
        let instances = nearest.instance.to_array().map(|i| i as u32);
        let point = lanes_of(&point_at(&ray.origin, &ray.dir, nearest.t));
        while pending != 0 {
            let instance = instances[pending.trailing_zeros() as usize];
            let shape = &self.shapes[instance as usize];
            let normal = lanes_of(&shape.world_normal(ray, nearest.t, centres));
            for (i, slot) in out.iter_mut().enumerate() {
                if pending & (1 << i) != 0 && instances[i] == instance {
                    *slot = Some(SurfaceHit {
                        t: t[i],
                        point: point[i],
                        geometric_normal: normal[i],
                        shading_normal: normal[i],
                        instance,
                        material: shape.material,
                    });
                    pending &= !(1 << i);
                }
            }
        }
        tie
    }

    /// `World::occluded` for each live lane (bit `i` of `live`), in lanes of type `L`; `false`
    /// for the others.
    #[inline(always)]
    pub fn occluded_lanes<L: Lanes>(
        &self,
        world: &World,
        rays: &[Ray; LANES],
        live: u32,
    ) -> [bool; LANES] {
        let simple = Self::simple_lanes(world, rays, live);
        let blocked = match simple {
            0 => 0,
            _ => {
                let packet = RayPacket::<L>::of(rays, simple);
                self.blocked(&packet, simple, &self.centres(packet.time.to_wide()))
            }
        };
        std::array::from_fn(|i| {
            if live & (1 << i) == 0 {
                false
            } else if simple & (1 << i) == 0 {
                world.occluded(&rays[i])
            } else {
                blocked & (1 << i) != 0
            }
        })
    }
}

/// The packet API: rays that stay in lanes from the camera to the shadow test.
impl SmallWorld {
    /// The lanes of `live` (bit `i` for lane `i`) whose ray this form traces as the scalar
    /// path of a world with this `shutter` (`World::shutter`) does: `simple` (the tests' scalar
    /// specification) in lanes (every packet ray has `t_min = 0`).
    #[inline(always)]
    pub(crate) fn simple_packet<L: Lanes>(
        shutter: (f32, f32),
        ray: &RayPacket<L>,
        live: u32,
    ) -> u32 {
        let d = &ray.dir;
        let zero = d[0].simd_eq(L::ZERO) & d[1].simd_eq(L::ZERO) & d[2].simd_eq(L::ZERO);
        let (t0, t1) = shutter;
        let in_shutter = ray.time.simd_ge(L::splat(t0)) & ray.time.simd_le(L::splat(t1));
        let t_max_ok = ray.t_max.simd_eq(ray.t_max);
        let ok = finite(&ray.origin) & finite(d) & in_shutter & t_max_ok;
        ok.to_bitmask() & !zero.to_bitmask() & live
    }

    /// Each lane's nearest hit over every instance, right for the lanes of `simple` (from
    /// [`SmallWorld::simple_packet`]).
    #[inline(always)]
    pub(crate) fn nearest<L: Lanes>(
        &self,
        ray: &RayPacket<L>,
        simple: u32,
        centres: &Centres,
    ) -> Nearest<L> {
        let mut nearest = Nearest::new();
        let dd = dot(&ray.dir, &ray.dir);
        for &i in &self.loose {
            let shape = &self.shapes[i as usize];
            nearest.add(shape.closest(ray, dd, simple, centres), i);
        }
        // A group's spheres only for the lanes passing near it (a lane culled would miss).
        for (g, members) in self.orbits.groups() {
            let near = self.orbits.near(g, ray, dd, centres, simple);
            if near == 0 {
                continue;
            }
            for &i in members {
                let lanes = self.near(i, ray, dd, near);
                if lanes == 0 {
                    continue;
                }
                let t = self.shapes[i as usize].closest(ray, dd, lanes, centres);
                nearest.add(L::lane_mask(lanes).bitselect(t, L::splat(f32::INFINITY)), i);
            }
        }
        nearest
    }

    /// The lanes of `active` whose ray may meet instance `i` over the shutter ([`Around`]).
    #[inline(always)]
    fn near<L: Lanes>(&self, i: u32, ray: &RayPacket<L>, dd: L, active: u32) -> u32 {
        match &self.around[i as usize] {
            Some(around) => around.near(ray, dd, active),
            None => active,
        }
    }

    /// The lanes of `active` whose ray hits instance `i` (`dd` the rays' `d · d`).
    #[inline(always)]
    fn hits<L: Lanes>(&self, i: u32, ray: &RayPacket<L>, dd: L, active: u32, c: &Centres) -> u32 {
        let t = self.shapes[i as usize].closest(ray, dd, active, c);
        t.simd_lt(L::splat(f32::INFINITY)).to_bitmask() & active
    }

    /// Instance `i`'s material.
    #[inline]
    pub(crate) fn material(&self, i: usize) -> u32 {
        self.shapes[i].material
    }

    /// The unit world-space normal of instance `i` at parameter `t` of each lane's ray, as
    /// `World::intersect` gives it (geometric and shading normal alike).
    #[inline]
    pub(crate) fn normal<L: Lanes>(
        &self,
        i: usize,
        ray: &RayPacket<L>,
        t: L,
        centres: &Centres,
    ) -> [L; 3] {
        self.shapes[i].world_normal(ray, t, centres)
    }

    /// `World::occluded` for the lanes of `simple` (from [`SmallWorld::simple_packet`]):
    /// the lanes blocked.
    #[inline(always)]
    pub(crate) fn blocked<L: Lanes>(
        &self,
        ray: &RayPacket<L>,
        simple: u32,
        centres: &Centres,
    ) -> u32 {
        let mut blocked = 0;
        let dd = dot(&ray.dir, &ray.dir);
        // Only the lanes not yet blocked need an answer.
        let hits = |i: u32, active: u32| self.hits(i, ray, dd, active, centres);
        for &i in &self.loose {
            blocked |= hits(i, simple & !blocked);
            if blocked & simple == simple {
                return simple;
            }
        }
        for (g, members) in self.orbits.groups() {
            let near = self.orbits.near(g, ray, dd, centres, simple & !blocked);
            if near == 0 {
                continue;
            }
            for &i in members {
                let lanes = self.near(i, ray, dd, near & !blocked);
                if lanes != 0 {
                    blocked |= hits(i, lanes);
                }
            }
            if blocked & simple == simple {
                return simple;
            }
        }
        blocked & simple
    }
}

/// A ray this form traces exactly as the scalar path does (see the module notes): the
/// specification [`SmallWorld::simple_packet`] is tested against.
#[cfg(test)]
fn simple(world: &World, ray: &Ray) -> bool {
    ray.origin.is_finite()
        & ray.dir.is_finite()
        & (ray.dir != Vec3A::ZERO)
        & world.in_shutter(ray)
        & (ray.t_min == 0.0)
        & !ray.t_max.is_nan()
}

/// The running nearest hit per lane: its `t` (`+inf` for none), its instance (an index, as
/// an `f32`: exact, and compared in lanes), and whether another instance gave exactly the
/// same `t`.
pub(crate) struct Nearest<L: Lanes = Lane> {
    pub(crate) t: L,
    pub(crate) tie: L,
    pub(crate) instance: L,
}

impl<L: Lanes> Nearest<L> {
    #[inline(always)]
    fn new() -> Self {
        Self {
            t: L::splat(f32::INFINITY),
            tie: L::ZERO,
            instance: L::ZERO,
        }
    }

    #[inline(always)]
    fn add(&mut self, t: L, instance: u32) {
        let closer = t.simd_lt(self.t);
        let same = t.simd_eq(self.t) & t.simd_lt(L::splat(f32::INFINITY));
        self.tie = closer.bitselect(L::ZERO, self.tie) | same;
        self.t = closer.bitselect(t, self.t);
        self.instance = closer.bitselect(L::splat(instance as f32), self.instance);
    }

    /// The lanes whose nearest hit is instance `i`'s (whether or not they hit at all).
    #[inline(always)]
    pub(crate) fn is(&self, i: usize) -> L {
        self.instance.simd_eq(L::splat(i as f32))
    }

    /// The lanes (bit `i` for lane `i`) that hit something.
    #[inline(always)]
    pub(crate) fn hit(&self) -> u32 {
        self.t.simd_lt(L::splat(f32::INFINITY)).to_bitmask()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::Instance;
    use crate::geometry::{Plane, Sphere};
    use crate::hash::{HashRng, unit_f32};
    use crate::motion::{Motion, MotionLayer};
    use glam::{Quat, Vec2, Vec3};
    use rand::RngCore;

    struct Draw(HashRng);

    impl Draw {
        fn unit(&mut self) -> f32 {
            unit_f32(self.0.next_u64())
        }
        fn range(&mut self, lo: f32, hi: f32) -> f32 {
            lo + (hi - lo) * self.unit()
        }
        fn pick(&mut self, n: u64) -> u64 {
            self.0.next_u64() % n
        }
        fn vec(&mut self, s: f32) -> Vec3 {
            Vec3::new(self.range(-s, s), self.range(-s, s), self.range(-s, s))
        }
        fn dir(&mut self) -> Vec3A {
            let d = Vec3A::from(self.vec(1.0));
            if d.length() < 1e-3 {
                Vec3A::X
            } else {
                d.normalize()
            }
        }
    }

    /// A layer at `location`, moving or not, turned and scaled or not.
    fn layer(d: &mut Draw, location: Vec3) -> MotionLayer {
        let mut l = MotionLayer {
            location,
            ..MotionLayer::default()
        };
        if d.pick(3) == 0 {
            l.velocity = d.vec(4.0);
        }
        if d.pick(4) == 0 {
            l.rotation = Quat::from_axis_angle(Vec3::from(d.dir()), d.range(0.0, 3.0));
            l.scale = Vec3::new(d.range(0.5, 2.0), d.range(0.5, 2.0), d.range(0.5, 2.0));
        }
        l
    }

    fn instance(shape: Shape, layer: MotionLayer, material: u32) -> Instance {
        Instance {
            shape,
            motion: Motion {
                layers: vec![layer],
            },
            material,
        }
    }

    /// Makes a sphere orbit: its layer becomes a group spinning by one of three spins (a
    /// packet form takes at most [`super::super::orbits::MAX_SPINS`]), the thesis's rates
    /// among them, unscaled or scaled uniformly, over the ball's own turned offset.
    fn orbiting(d: &mut Draw, ball: &mut Instance) {
        let group = &mut ball.motion.layers[0];
        group.angular_velocity = [
            Vec3::new(0.0, 77.0, 0.0),
            Vec3::new(0.0, 0.0, -113.0),
            Vec3::new(0.3, -190.0, 0.2),
        ][d.pick(3) as usize];
        group.scale = match d.pick(2) {
            0 => Vec3::ONE,
            _ => Vec3::splat(d.range(0.5, 2.0)),
        };
        let own = MotionLayer {
            location: d.vec(1.5),
            rotation: Quat::from_axis_angle(Vec3::from(d.dir()), d.range(0.0, 3.0)),
            ..MotionLayer::default()
        };
        ball.motion.layers.push(own);
    }

    /// Spheres and planes (infinite and rectangles), some touching exactly, some copies of
    /// another (equal t: ties), some moving, some turned.
    fn random_world(d: &mut Draw, offset: Vec3) -> World {
        let n = 1 + d.pick(MAX_INSTANCES as u64) as usize;
        let mut instances = Vec::new();
        for m in 0..n as u32 {
            let inst = match d.pick(6) {
                0 | 1 => {
                    let radius = [0.5, 1.0, 2.5, d.range(0.01, 3.0)][d.pick(4) as usize];
                    let at = d.vec(5.0);
                    let l = layer(d, at);
                    let mut ball = instance(Shape::Sphere(Sphere { radius }), l, m);
                    if d.pick(3) == 0 {
                        orbiting(d, &mut ball);
                    }
                    ball
                }
                2 => {
                    // A sphere resting exactly on the plane y = 0 (and the plane).
                    let radius = [1.0, 0.5, 2.0][d.pick(3) as usize];
                    let (x, z) = (d.range(-3.0, 3.0), d.range(-3.0, 3.0));
                    let at = MotionLayer {
                        location: Vec3::new(x, radius, z),
                        ..MotionLayer::default()
                    };
                    instances.push(instance(Shape::Sphere(Sphere { radius }), at, m));
                    let floor = Plane { half_extent: None };
                    instance(Shape::Plane(floor), MotionLayer::default(), m + 100)
                }
                3 => {
                    let half_extent = match d.pick(3) {
                        0 => None,
                        _ => Some(Vec2::new(d.range(0.5, 20.0), d.range(0.5, 20.0))),
                    };
                    let at = d.vec(3.0);
                    let l = layer(d, at);
                    instance(Shape::Plane(Plane { half_extent }), l, m)
                }
                4 if !instances.is_empty() => {
                    let twin = instances[d.pick(instances.len() as u64) as usize].clone();
                    Instance {
                        material: m,
                        ..twin
                    }
                }
                _ => {
                    let p = Plane {
                        half_extent: Some(Vec2::new(20.0, 20.0)),
                    };
                    instance(Shape::Plane(p), MotionLayer::default(), m)
                }
            };
            instances.push(inst);
        }
        instances.truncate(MAX_INSTANCES);
        for i in &mut instances {
            i.motion.layers[0].location += offset;
        }
        World::build(instances, (0.0, 1.0))
    }

    /// Rays from outside and inside, aimed at centres and grazing silhouettes, with limits,
    /// out-of-shutter times and degenerate directions.
    fn random_ray(d: &mut Draw, world: &World, offset: Vec3) -> Ray {
        let target = {
            let i = d.pick(world.instances().len() as u64) as usize;
            let m = &world.instances()[i].motion;
            Vec3A::from(m.layers[0].location)
        };
        let origin = match d.pick(4) {
            0 => target + d.dir() * d.range(0.0, 0.9),
            1 => Vec3A::new(d.range(-3.0, 3.0), 0.0, d.range(-3.0, 3.0)) + Vec3A::from(offset),
            _ => Vec3A::from(d.vec(12.0) + offset),
        };
        let mut dir = match d.pick(3) {
            0 => d.dir(),
            _ => (target + d.dir() * d.range(0.0, 2.6) - origin).normalize_or_zero(),
        };
        if d.pick(10) == 0 {
            dir.y = 0.0;
        }
        let mut ray = Ray::new(origin, dir, d.range(-0.05, 1.05).clamp(0.0, 1.0));
        match d.pick(40) {
            0 => ray.dir = Vec3A::ZERO,
            1 => ray.origin.x = f32::NAN,
            2 => ray.dir.z = f32::INFINITY,
            3 => ray.time = 1.5,
            4 => ray.time = -0.25,
            5 => ray.t_min = 0.5,
            6 => ray.t_max = f32::NAN,
            _ => {}
        }
        if d.pick(3) == 0 {
            ray.t_max = d.range(0.0, 15.0);
        }
        ray
    }

    fn bits(h: &Option<SurfaceHit>) -> Option<[u32; 12]> {
        h.map(|h| {
            let v = |v: Vec3A| v.to_array().map(f32::to_bits);
            let [p, g, s] = [v(h.point), v(h.geometric_normal), v(h.shading_normal)];
            [
                h.t.to_bits(),
                p[0],
                p[1],
                p[2],
                g[0],
                g[1],
                g[2],
                s[0],
                s[1],
                s[2],
                h.instance,
                h.material,
            ]
        })
    }

    #[test]
    fn packets_match_the_scalar_world_bit_for_bit() {
        packets_match::<crate::simd::Sse2>();
    }

    /// The same in AVX2 lanes, where this CPU has AVX2 (called outside the AVX2 entry: each
    /// operation a call, the same bits).
    #[test]
    #[cfg(target_arch = "x86_64")]
    fn avx2_packets_match_the_scalar_world_bit_for_bit() {
        if !std::is_x86_feature_detected!("avx2") {
            eprintln!("skipped: this CPU has no AVX2");
            return;
        }
        packets_match::<crate::simd::Avx2>();
    }

    #[inline(always)]
    fn packets_match<L: Lanes>() {
        let (mut rays_traced, mut hits, mut blocked, mut orbits) = (0, 0, 0, 0);
        for w in 0..300u64 {
            let mut d = Draw(HashRng::new(0x9ac7e7, &[w]));
            // Every fourth world far from the origin (coordinates in the thousands).
            let offset = if w % 4 == 3 {
                Vec3::new(3000.0, -1500.0, 2500.0)
            } else {
                Vec3::ZERO
            };
            let world = random_world(&mut d, offset);
            let small = world.small().expect("spheres and planes only");
            for g in 0..40u64 {
                let rays: [Ray; LANES] =
                    std::array::from_fn(|_| random_ray(&mut d, &world, offset));
                let all = (1u32 << LANES) - 1;
                let live = (d.pick(u64::from(all) + 1) as u32) | if g % 2 == 0 { all } else { 0 };
                let got = small.intersect_lanes::<L>(&world, &rays, live);
                // The packet API's test in lanes (for its rays: `t_min = 0`).
                let packet_rays =
                    (0..LANES).fold(0, |m, i| m | u32::from(rays[i].t_min == 0.0) << i);
                assert_eq!(
                    SmallWorld::simple_packet(
                        world.shutter(),
                        &RayPacket::<Lane>::new(&rays),
                        live
                    ) & packet_rays,
                    SmallWorld::simple_lanes(&world, &rays, live) & packet_rays,
                    "world {w}, group {g}"
                );
                let occ = small.occluded_lanes::<L>(&world, &rays, live);
                for i in 0..LANES {
                    if live & (1 << i) == 0 {
                        assert!(got[i].is_none() && !occ[i]);
                        continue;
                    }
                    let want = world.intersect(&rays[i]);
                    assert_eq!(
                        bits(&got[i]),
                        bits(&want),
                        "world {w}, group {g}, lane {i}: {:?}",
                        rays[i]
                    );
                    assert_eq!(
                        occ[i],
                        world.occluded(&rays[i]),
                        "world {w}, group {g}, lane {i}"
                    );
                    rays_traced += 1;
                    hits += usize::from(want.is_some());
                    orbits += usize::from(want.is_some_and(|h| {
                        world.instances()[h.instance as usize].motion.layers.len() == 2
                    }));
                    blocked += usize::from(occ[i]);
                }
            }
        }
        // The draws must exercise both outcomes.
        assert!(rays_traced > 30_000 && hits > rays_traced / 4 && blocked > hits / 2);
        assert!(hits < rays_traced * 9 / 10);
        assert!(
            orbits > hits / 20,
            "{orbits} of {hits} hits on orbiting spheres"
        );
    }

    /// Spinning instances have a small form only as spheres scaled uniformly under one spin.
    #[test]
    fn meshes_and_spinning_instances_have_no_small_form() {
        let spin = MotionLayer {
            angular_velocity: Vec3::Y,
            ..MotionLayer::default()
        };
        let sphere = Shape::Sphere(Sphere { radius: 1.0 });
        let small = |layers: Vec<MotionLayer>| {
            let ball = Instance {
                shape: sphere.clone(),
                motion: Motion { layers },
                material: 0,
            };
            World::build(vec![ball], (0.0, 1.0)).small().is_some()
        };
        let uneven = MotionLayer {
            scale: Vec3::new(1.0, 2.0, 1.0),
            ..spin
        };
        let cube = Shape::Mesh(std::sync::Arc::new(crate::geometry::tessellate::cube(1.0)));
        assert!(small(vec![spin]));
        assert!(small(vec![MotionLayer {
            scale: Vec3::splat(2.0),
            ..spin
        }]));
        assert!(!small(vec![uneven]), "an ellipsoid");
        assert!(!small(vec![
            spin,
            MotionLayer {
                angular_velocity: Vec3::X,
                ..spin
            }
        ]));
        let world = World::build(vec![instance(cube, spin, 0)], (0.0, 1.0));
        assert!(world.small().is_none());
        let many = vec![instance(sphere, MotionLayer::default(), 0); MAX_INSTANCES + 1];
        assert!(World::build(many.clone(), (0.0, 1.0)).small().is_none());
        assert!(
            World::build(many[1..].to_vec(), (0.0, 1.0))
                .small()
                .is_some()
        );
    }
}
