//! The two-level structure rays are traced through in one frame.
//!
//! Bottom level: each mesh's own BVH, in object space, built once ([`TriangleMesh::new`]).
//! Top level: a 4-wide BVH ([`Bvh4`], collapsed from obvhs's binary one) over the instances'
//! world bounds swept over this frame's shutter ([`swept_bounds`]), padded for rounding,
//! rebuilt per frame (`fastest_build`: one instance per leaf, so an instance's box is never
//! merged with its neighbours'); in a world where something moves, one per piece of the
//! shutter, each ray walking its time's ([`Slices`]). The top level's leaf test
//! moves the ray into the instance's object space at the ray's time ([`PoseOverTime`]) and asks
//! the shape. Unbounded planes cannot be boxed: every ray tests them after the top level.
//!
//! obvhs's `CwBvh::ray_traverse_tlas_blas` cannot do this: it does not transform rays.
//!
//! [`TriangleMesh::new`]: crate::geometry::TriangleMesh::new

use super::cull::CullBox;
use super::packet::{RayPacket, SmallWorld};
use super::pose::{Pose, PoseCache, PoseOverTime};
use super::slices::{SLICES, Slices};
use super::swept::swept_bounds;
use super::{Instance, SurfaceHit};
use crate::bvh::BoxRay;
use crate::geometry::bounds::SLACK_PER_DIAGONAL;
use crate::geometry::{Bounds, Ray, ShapeHit};

/// Every instance, ready to be traced for the shutter interval `[t0, t1]` of one frame.
#[derive(Clone)]
pub struct World {
    instances: Vec<Instance>,
    poses: Vec<PoseOverTime>,
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
        let poses: Vec<_> = instances
            .iter()
            .map(|i| PoseOverTime::new(&i.motion))
            .collect();
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
        let small = SmallWorld::new(&instances, &poses);
        let padded: Vec<Bounds> = bounded
            .iter()
            .map(|&i| pad_top_level(swept[i as usize], scene.diagonal()))
            .collect();
        let cull = CullBox::new(&padded, !unbounded.is_empty(), shutter);
        Self {
            instances,
            poses,
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
    #[inline]
    pub fn may_hit_lanes(&self, ray: &RayPacket, live: u32) -> u32 {
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

    /// Whether no instance moves (every pose was computed once at build).
    pub fn is_static(&self) -> bool {
        self.poses.iter().all(PoseOverTime::is_fixed)
    }

    /// The shutter interval the top level was built for.
    pub(super) fn shutter(&self) -> (f32, f32) {
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
            match self.instances[instance as usize].shape.closest(&local) {
                Some(h) => {
                    best = Some((instance, h, pose));
                    h.t
                }
                None => f32::INFINITY,
            }
        };
        if self.in_shutter(ray) {
            if let Some(boxes) = BoxRay::new(ray) {
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
        let o = inst.shape.surface(&local, h);
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
            self.instances[instance as usize].shape.occluded(&local)
        };
        if !self.in_shutter(ray) {
            return (0..self.instances.len() as u32).any(blocks);
        }
        let top = BoxRay::new(ray).is_some_and(|boxes| {
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
