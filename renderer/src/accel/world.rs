//! The two-level structure rays are traced through in one frame.
//!
//! Bottom level: each mesh's own BVH, in object space, built once ([`TriangleMesh::new`]).
//! Top level: a 4-wide BVH ([`Bvh4`], collapsed from obvhs's binary one) over the instances'
//! world bounds swept over this frame's shutter ([`swept_bounds`]), padded for rounding,
//! rebuilt per frame (`fastest_build`: one instance per leaf, so an instance's box is never
//! merged with its neighbours'); in a world where something moves, one per piece of the
//! shutter, each ray walking its time's ([`Slices`]). The top level's leaf test
//! moves the ray into the instance's object space at the ray's time ([`PoseOverTime`]) and asks
//! the shape (a sphere in centre form is met in world space, about its centre: `traced`).
//! Unbounded planes cannot be boxed: every ray tests them after the top level.
//!
//! obvhs's `CwBvh::ray_traverse_tlas_blas` cannot do this: it does not transform rays.
//!
//! [`TriangleMesh::new`]: crate::geometry::TriangleMesh::new

use super::cull::CullBox;
use super::instant::Pose;
use super::lanes::{Lanes, RayPacket};
use super::packet::SmallWorld;
use super::pose::{PoseCache, PoseOverTime, Spins};
use super::slices::{SLICES, Slices};
use super::swept::swept_bounds;
use super::{Instance, SurfaceHit};
use crate::bvh::BoxRay;
use crate::geometry::bounds::SLACK_PER_DIAGONAL;
use crate::geometry::{Bounds, Ray, Shape, ShapeHit, Sphere};

/// Every instance, ready to be traced for the shutter interval `[t0, t1]` of one frame.
#[derive(Clone)]
pub struct World {
    instances: Vec<Instance>,
    poses: Vec<PoseOverTime>,
    /// Each instance's shape as its pose places it ([`traced`]).
    shapes: Vec<Shape>,
    /// The distinct spins of the orbiting spheres (their rotations are cached per spin).
    spins: Spins,
    /// Top-level BVHs over the bounded instances, one per piece of the shutter; their
    /// primitive `p` is instance `bounded[p]`.
    top: Slices,
    bounded: Vec<u32>,
    /// Instances without finite bounds (infinite planes), tested by every ray.
    unbounded: Vec<u32>,
    shutter: (f32, f32),
    /// The packet form, for a world of a few spheres and planes ([`SmallWorld`]).
    small: Option<SmallWorld>,
    /// One box around every surface in the shutter, for culling packets' rays ([`CullBox`]).
    cull: Option<CullBox>,
}

impl std::fmt::Debug for World {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("World")
            .field("instances", &self.instances)
            .field("bounded", &self.bounded.len())
            .field("unbounded", &self.unbounded.len())
            .field("shutter", &self.shutter)
            .finish()
    }
}

/// An instance's pose and its shape as that pose places it: a sphere whose chain scales
/// uniformly in centre form ([`PoseOverTime::centred`], the radius scaled by the chain's
/// scale), every other instance as given, moved into object space by the full inverse.
fn traced(instance: &Instance, spins: &mut Spins) -> (PoseOverTime, Shape) {
    let motion = &instance.motion;
    match (&instance.shape, motion.uniform_scale()) {
        (Shape::Sphere(s), Some(scale)) => (
            PoseOverTime::centred(motion, spins),
            Shape::Sphere(Sphere {
                radius: s.radius * scale,
            }),
        ),
        (shape, _) => (PoseOverTime::new(motion), shape.clone()),
    }
}

/// Top-level boxes are padded like mesh primitives ([`Bounds::padded`]), with a slack scaled
/// by the whole scene's diagonal, since camera rays come from anywhere in the scene.
pub(crate) fn pad_top_level(b: Bounds, scene_diagonal: f32) -> Bounds {
    b.padded(SLACK_PER_DIAGONAL * scene_diagonal)
}

impl World {
    /// Build for rays whose times lie in `[shutter.0, shutter.1]`. Rays at other times are
    /// still traced correctly, by testing every instance (slow, but never wrong).
    pub fn build(instances: Vec<Instance>, shutter: (f32, f32)) -> Self {
        Self::build_sliced(instances, shutter, SLICES)
    }

    /// [`World::build`] with the top level cut into `pieces` pieces of the shutter where
    /// something moves (one where nothing does).
    pub(crate) fn build_sliced(
        instances: Vec<Instance>,
        shutter: (f32, f32),
        pieces: usize,
    ) -> Self {
        let shutter = (shutter.0.min(shutter.1), shutter.0.max(shutter.1));
        let mut spins = Spins::default();
        let (poses, shapes): (Vec<_>, Vec<_>) =
            instances.iter().map(|i| traced(i, &mut spins)).unzip();
        let swept: Vec<Bounds> = instances
            .iter()
            .map(|i| swept_bounds(i.shape.bounds(), &i.motion, shutter))
            .collect();
        let (bounded, unbounded): (Vec<u32>, Vec<u32>) =
            (0..instances.len() as u32).partition(|&i| swept[i as usize].is_finite());
        let scene = bounded
            .iter()
            .fold(Bounds::EMPTY, |b, &i| b.union(swept[i as usize]));
        let still = poses.iter().all(PoseOverTime::is_fixed);
        let pieces = if still { 1 } else { pieces };
        let top = Slices::build(&instances, &bounded, shutter, pieces, |b| {
            pad_top_level(b, scene.diagonal())
        });
        // Each instance's box as the top level pads it (an unbounded one stays unbounded).
        let padded: Vec<Bounds> = swept
            .iter()
            .map(|b| pad_top_level(*b, scene.diagonal()))
            .collect();
        let small = SmallWorld::new(&instances, &shapes, &poses, &spins, &padded);
        let padded: Vec<Bounds> = bounded.iter().map(|&i| padded[i as usize]).collect();
        let cull = CullBox::new(&padded, !unbounded.is_empty(), shutter);
        Self {
            instances,
            poses,
            shapes,
            spins,
            top,
            bounded,
            unbounded,
            shutter,
            small,
            cull,
        }
    }

    /// The lanes of `live` whose ray may hit something: the others' rays surely hit nothing
    /// ([`CullBox`]; with no box, all of `live`).
    #[inline(always)]
    pub fn may_hit_lanes<L: Lanes>(&self, ray: &RayPacket<L>, live: u32) -> u32 {
        match &self.cull {
            Some(c) => c.may_hit(ray, live),
            None => live,
        }
    }

    /// The packet form, if this world is small and analytic enough to have one.
    pub fn small(&self) -> Option<&SmallWorld> {
        self.small.as_ref()
    }

    pub fn instances(&self) -> &[Instance] {
        &self.instances
    }

    /// A pose cache for this world (one per thread's piece of work).
    pub fn pose_cache(&self) -> PoseCache {
        PoseCache::new(self.instances.len(), self.spins.len())
    }

    /// Whether no instance moves (every pose was computed once at build).
    pub fn is_static(&self) -> bool {
        self.poses.iter().all(PoseOverTime::is_fixed)
    }

    /// The shutter interval the top level was built for.
    pub(crate) fn shutter(&self) -> (f32, f32) {
        self.shutter
    }

    /// Whether the ray's time lies in the shutter interval the top level was built for.
    #[inline]
    pub(super) fn in_shutter(&self, ray: &Ray) -> bool {
        ray.time >= self.shutter.0 && ray.time <= self.shutter.1
    }

    /// Closest hit with `ray.t_min < t < ray.t_max`.
    pub fn intersect(&self, ray: &Ray) -> Option<SurfaceHit> {
        self.intersect_cached(ray, &PoseCache::default())
    }

    /// [`World::intersect`], spinning poses from and into `cache`.
    pub fn intersect_cached(&self, ray: &Ray, cache: &PoseCache) -> Option<SurfaceHit> {
        let mut best: Option<(u32, ShapeHit, Pose)> = None;
        let mut t_max = ray.t_max;
        let mut visit = |instance: u32, t_max: f32| -> f32 {
            let pose = cache.at(instance, &self.poses[instance as usize], ray.time);
            let local = pose.ray_to_object(&Ray { t_max, ..*ray });
            match self.shapes[instance as usize].closest(&local) {
                Some(h) => {
                    best = Some((instance, h, pose));
                    h.t
                }
                None => f32::INFINITY,
            }
        };
        if self.in_shutter(ray) {
            if let Some(boxes) = BoxRay::new(ray.origin, ray.dir) {
                let top = self.top.at(ray.time);
                t_max = top.closest(&boxes, t_max, |leaf, t_max| {
                    let mut t = t_max;
                    for &p in top.leaf(leaf) {
                        t = t.min(visit(self.bounded[p as usize], t));
                    }
                    t
                });
            }
            for &i in &self.unbounded {
                t_max = t_max.min(visit(i, t_max));
            }
        } else {
            for i in 0..self.instances.len() as u32 {
                t_max = t_max.min(visit(i, t_max));
            }
        }
        let (instance, h, pose) = best?;
        let inst = &self.instances[instance as usize];
        let local = pose.ray_to_object(ray);
        let o = self.shapes[instance as usize].surface(&local, h);
        Some(SurfaceHit {
            t: h.t,
            point: ray.at(h.t),
            geometric_normal: pose.normal_to_world(o.geometric_normal).normalize_or_zero(),
            shading_normal: pose.normal_to_world(o.shading_normal).normalize_or_zero(),
            instance,
            material: inst.material,
        })
    }

    /// Whether anything is hit with `ray.t_min < t < ray.t_max` (shadow rays; stops at the
    /// first hit found).
    pub fn occluded(&self, ray: &Ray) -> bool {
        self.occluded_cached(ray, &PoseCache::default())
    }

    /// [`World::occluded`], spinning poses from and into `cache`.
    pub fn occluded_cached(&self, ray: &Ray, cache: &PoseCache) -> bool {
        let blocks = |instance: u32| {
            let local = cache
                .at(instance, &self.poses[instance as usize], ray.time)
                .ray_to_object(ray);
            self.shapes[instance as usize].occluded(&local)
        };
        if !self.in_shutter(ray) {
            return (0..self.instances.len() as u32).any(blocks);
        }
        let top = BoxRay::new(ray.origin, ray.dir).is_some_and(|boxes| {
            let top = self.top.at(ray.time);
            top.any(&boxes, ray.t_max, |leaf| {
                top.leaf(leaf)
                    .iter()
                    .any(|&p| blocks(self.bounded[p as usize]))
            })
        });
        top || self.unbounded.iter().any(|&i| blocks(i))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hash::HashRng;
    use crate::motion::{Motion, MotionLayer};
    use glam::{Quat, Vec3, Vec3A};
    use rand::Rng;

    const U: f32 = f32::EPSILON / 2.0;

    fn vec3(rng: &mut HashRng, r: f32) -> Vec3 {
        Vec3::from_array(std::array::from_fn(|_| rng.random_range(-r..r)))
    }

    /// A group (spinning, moving or still, turned) over a ball's own layer (turned, offset),
    /// every layer scaled by `scale(rng)`.
    fn chain(rng: &mut HashRng, scale: impl Fn(&mut HashRng) -> Vec3) -> Motion {
        let group = MotionLayer {
            location: vec3(rng, 3.0),
            velocity: if rng.random_bool(0.3) {
                vec3(rng, 2.0)
            } else {
                Vec3::ZERO
            },
            rotation: Quat::from_scaled_axis(vec3(rng, 3.0)),
            angular_velocity: if rng.random_bool(0.7) {
                vec3(rng, 200.0)
            } else {
                Vec3::ZERO
            },
            scale: scale(rng),
        };
        let ball = MotionLayer {
            location: vec3(rng, 2.0),
            rotation: Quat::from_scaled_axis(vec3(rng, 3.0)),
            scale: scale(rng),
            ..MotionLayer::default()
        };
        Motion {
            layers: vec![group, ball],
        }
    }

    /// The object-space path's nearest hit (the pose's full inverse, as before the centre
    /// form): its `t` and unit world normal.
    fn through_the_inverse(motion: &Motion, radius: f32, ray: &Ray) -> Option<(f32, Vec3A)> {
        let pose = PoseOverTime::new(motion).at(ray.time);
        let local = pose.ray_to_object(ray);
        let h = Sphere { radius }.closest(&local)?;
        Some((h.t, pose.normal_to_world(local.at(h.t)).normalize_or_zero()))
    }

    /// Spheres under uniformly scaled, turned, moving and spinning chains (the thesis's spin
    /// rates, times around its -12.5 s) meet rays in centre form where the object-space path
    /// does: every ray aimed through the sphere (its centre's foot within 0.9 of the radius)
    /// hits both ways with `t` within `64u (|o - c| + R)` (each path rounds the ray or the
    /// radius a few times, and the root's sensitivity at 0.9 R is 1 / sqrt(1 - 0.81) < 2.3),
    /// the normals within `64u (1 + |o - c| / R)`; every ray passing outside 1.1 R misses both
    /// ways. A centre, radius or normal that were wrong by more than rounding would fail.
    #[test]
    fn spheres_from_their_centre_meet_rays_where_the_inverse_does() {
        let (mut hits, mut misses, mut orbiting) = (0, 0, 0);
        for case in 0..400u64 {
            let mut rng = HashRng::new(0x5fe7e, &[case]);
            let uniform = |rng: &mut HashRng| Vec3::splat(rng.random_range(0.3..3.0));
            let motion = chain(&mut rng, uniform);
            let radius = rng.random_range(0.05..1.0);
            let shape = Shape::Sphere(Sphere { radius });
            let shutter = (-12.5, -12.38);
            let world = World::build(
                vec![Instance {
                    shape,
                    motion: motion.clone(),
                    material: 0,
                }],
                shutter,
            );
            orbiting += usize::from(matches!(world.poses[0], PoseOverTime::Orbiting(_)));
            let big = radius * motion.uniform_scale().expect("uniform");
            for k in 0..20 {
                let time = rng.random_range(shutter.0..shutter.1);
                let centre = motion.point_at(Vec3A::ZERO, time);
                // From 4-24 radii (and up to 5 units) away, aimed to pass the centre at a
                // distance of up to 0.9 R (through) or 1.1-3 R (past).
                let away = Vec3A::from(vec3(&mut rng, 1.0)).normalize_or(Vec3A::X);
                let l = big * rng.random_range(4.0..24.0) + rng.random_range(0.0..5.0);
                let origin = centre + away * l;
                let through = k % 2 == 0;
                let pass = big
                    * if through {
                        rng.random_range(0.0..0.9)
                    } else {
                        rng.random_range(1.1..3.0)
                    };
                let side = Vec3A::from(vec3(&mut rng, 1.0));
                let off =
                    (side - away * side.dot(away)).normalize_or(away.any_orthonormal_vector());
                let aim = centre + off * (pass * l / (l * l - pass * pass).sqrt());
                let ray = Ray::new(origin, (aim - origin).normalize(), time);
                let new = world.intersect(&ray);
                let old = through_the_inverse(&motion, radius, &ray);
                let scale = (origin - centre).length() + big;
                match (new, old, through) {
                    (Some(n), Some((t, normal)), true) => {
                        assert!(
                            (n.t - t).abs() <= 64.0 * U * scale,
                            "case {case}: t {} against {t}",
                            n.t
                        );
                        let e = (n.geometric_normal - normal).abs().max_element();
                        assert!(
                            e <= 64.0 * U * (1.0 + scale / big),
                            "case {case}: normal {e}"
                        );
                        hits += 1;
                    }
                    (None, None, false) => misses += 1,
                    (n, o, _) => panic!("case {case}, ray {k}: {n:?} against {o:?}"),
                }
            }
        }
        assert!(
            hits == 4000 && misses == 4000 && orbiting > 200,
            "{orbiting}"
        );
    }

    /// A sphere scaled unevenly is an ellipsoid: it keeps the object-space path, bit for bit.
    #[test]
    fn unevenly_scaled_spheres_keep_the_object_space_path() {
        for case in 0..50u64 {
            let mut rng = HashRng::new(0xe111, &[case]);
            let uneven = |rng: &mut HashRng| {
                Vec3::from_array(std::array::from_fn(|_| rng.random_range(0.3..3.0)))
            };
            let motion = chain(&mut rng, uneven);
            assert_eq!(motion.uniform_scale(), None);
            let world = World::build(
                vec![Instance {
                    shape: Shape::Sphere(Sphere { radius: 0.5 }),
                    motion: motion.clone(),
                    material: 0,
                }],
                (0.0, 1.0),
            );
            assert!(!matches!(world.poses[0], PoseOverTime::Orbiting(_)));
            for _ in 0..20 {
                let time = rng.random_range(0.0..1.0);
                let centre = motion.point_at(Vec3A::ZERO, time);
                let origin = centre + Vec3A::from(vec3(&mut rng, 8.0));
                let aim = centre + Vec3A::from(vec3(&mut rng, 0.5));
                let ray = Ray::new(origin, (aim - origin).normalize(), time);
                let new = world.intersect(&ray).map(|h| (h.t, h.geometric_normal));
                assert_eq!(new, through_the_inverse(&motion, 0.5, &ray), "case {case}");
            }
        }
    }

    /// An orbiting sphere's centre is the spinning pose's translation (equal values), whether
    /// computed alone or through a cache that shares each group's rotation between its
    /// spheres; a sphere without scale keeps its radius exactly.
    #[test]
    fn orbiting_centres_are_the_spinning_poses_translation() {
        let group = MotionLayer {
            location: Vec3::new(0.0, 0.75, 0.0),
            angular_velocity: Vec3::new(0.0, 77.0, 0.0),
            ..MotionLayer::default()
        };
        let ball = |x: f32| Instance {
            shape: Shape::Sphere(Sphere { radius: 0.28 }),
            motion: Motion {
                layers: vec![
                    group,
                    MotionLayer {
                        location: Vec3::new(x, -0.12, 0.3),
                        ..MotionLayer::default()
                    },
                ],
            },
            material: 0,
        };
        let world = World::build(vec![ball(1.8), ball(-0.5562)], (-9.2, -9.08));
        assert_eq!(world.spins.len(), 1, "one group, one spin");
        let Shape::Sphere(s) = &world.shapes[1] else {
            panic!("a sphere")
        };
        assert_eq!(s.radius, 0.28);
        let cache = world.pose_cache();
        for t in [-9.2f32, -9.15, -9.15, -9.08, 0.0] {
            for i in [0u32, 1, 0] {
                let spinning = PoseOverTime::new(&world.instances[i as usize].motion);
                let want = spinning.at(t).translation;
                let pose = &world.poses[i as usize];
                assert_eq!(pose.at(t), Pose::centred(want), "{i} at {t}");
                assert_eq!(cache.at(i, pose, t), Pose::centred(want), "{i} at {t}");
            }
        }
    }
}
