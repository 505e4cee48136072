//! The top level cut in time: one BVH per equal piece of the frame's shutter.
//!
//! Why: a ray has one time, but a top level over the whole shutter boxes each instance at every
//! time of it. The thesis's spheres spin 1.5 to 3.6 turns in a shutter (77-190 rad/s over
//! 0.12 s), so each spinning sphere's box holds its whole ring, and a ray that crosses a ring
//! visits every sphere on it (the pose, the ray moved into object space, the root test) to
//! find the one or none it hits at its time; the airliner moves 120 ft in a shutter, so most
//! of the plane scene's camera rays enter its box. Here the shutter is cut into pieces, each
//! with its own top level over the instances' bounds swept over that piece only
//! ([`swept_bounds`], as conservative over a piece as over the whole shutter), and a ray walks
//! the piece its time lies in ([`Slices::at`]).
//!
//! The answers do not change: each box still holds its instance at every time of its piece, so
//! an instance a ray's piece leaves out is one the ray cannot hit at its time. The same hits
//! are found and the nearest kept, except where two instances are hit at exactly the same `t`
//! (the first visited wins, in this top level's order as in any other: see
//! `accel::packet`'s ties); the thesis's films are byte-identical (`docs/benchmarks/lanes.md`,
//! "Fifth pass").

use super::Instance;
use super::swept::swept_bounds;
use crate::bvh::Bvh4;
use crate::geometry::Bounds;
use obvhs::BvhBuildParams;
use obvhs::bvh2::builder::build_bvh2;
use std::time::Duration;

/// Pieces of the shutter for a world where something moves (a still world has one): the
/// largest box of a thesis sphere shrinks from its whole ring to an arc of 0.6-1.4 rad, and
/// the airliner's from 120 ft of travel to 7.5 ft. More pieces cost only the build (22
/// instances swept 16 times per frame: microseconds against the frame's seconds).
pub const SLICES: usize = 16;

/// One top level per piece of the shutter: piece `k` covers `cuts[k]..=cuts[k + 1]`; a
/// top level's primitive `p` is the world's bounded instance `p` (the same order in all).
#[derive(Clone)]
pub(super) struct Slices {
    cuts: Vec<f32>,
    tops: Vec<Bvh4>,
    /// Pieces per unit of time, for the guess of a time's piece (a product, not a division:
    /// every ray asks).
    per_time: f32,
}

impl Slices {
    /// `pieces` top levels (at least one) over `bounded` instances in the shutter `(t0, t1)`
    /// (`t0 <= t1`), each box padded by `pad`.
    pub(super) fn build(
        instances: &[Instance],
        bounded: &[u32],
        shutter: (f32, f32),
        pieces: usize,
        pad: impl Fn(Bounds) -> Bounds,
    ) -> Self {
        let pieces = pieces.max(1);
        let (t0, t1) = shutter;
        let cuts: Vec<f32> = (0..=pieces)
            .map(|k| match k {
                0 => t0,
                k if k == pieces => t1,
                k => t0 + (t1 - t0) * (k as f32 / pieces as f32),
            })
            .collect();
        let tops = cuts
            .windows(2)
            .map(|piece| {
                let boxes: Vec<_> = bounded
                    .iter()
                    .map(|&i| {
                        let inst = &instances[i as usize];
                        let swept =
                            swept_bounds(inst.shape.bounds(), &inst.motion, (piece[0], piece[1]));
                        pad(swept).to_aabb()
                    })
                    .collect();
                top_level(&boxes)
            })
            .collect();
        let per_time = pieces as f32 / (t1 - t0);
        Self {
            cuts,
            tops,
            per_time,
        }
    }

    /// The top level of the piece that holds time `t`, which lies in the shutter: `t` is in
    /// `cuts[k]..=cuts[k + 1]` of the piece returned, whatever the rounding of the guess.
    #[inline(always)]
    pub(super) fn at(&self, t: f32) -> &Bvh4 {
        let n = self.tops.len();
        if n == 1 {
            return &self.tops[0];
        }
        // A NaN (a zero shutter) or negative guess saturates to 0.
        let mut k = (((t - self.cuts[0]) * self.per_time) as usize).min(n - 1);
        while k > 0 && t < self.cuts[k] {
            k -= 1;
        }
        while k + 1 < n && t > self.cuts[k + 1] {
            k += 1;
        }
        &self.tops[k]
    }
}

/// A top level over `boxes` (obvhs's fastest build: one instance per leaf, so an instance's box
/// is never merged with its neighbours').
fn top_level(boxes: &[obvhs::aabb::Aabb]) -> Bvh4 {
    if boxes.is_empty() {
        return Bvh4::default();
    }
    Bvh4::from_bvh2(&build_bvh2(
        boxes,
        BvhBuildParams::fastest_build(),
        &mut Duration::default(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::World;
    use crate::geometry::Ray;
    use crate::hash::{hash, unit_f32};
    use crate::scene::Scene;
    use glam::Vec3A;
    use std::path::Path;

    /// The thesis's spheres at frame 100 with the top level in pieces and in one: rays from
    /// the camera and from the floor towards the sun, at times all over the shutter, find the
    /// same nearest hit (instance, t, point, normals: bit for bit) and the same occlusion;
    /// most of the hits are on spinning spheres, whose boxes the pieces shrink most.
    #[test]
    fn pieces_of_the_shutter_give_the_whole_shutters_hits() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/thesis/spheres.json");
        let scene = Scene::load(&path).unwrap();
        let (t0, t1) = scene.settings.shutter(100);
        let sliced = World::build_sliced(scene.instances.clone(), (t0, t1), SLICES);
        let whole = World::build_sliced(scene.instances.clone(), (t0, t1), 1);
        let (mut spinning, mut blocked) = (0, 0);
        for i in 0..20_000u64 {
            let h = |k: u64| unit_f32(hash(i, &[k]));
            let time = t0 + (t1 - t0) * h(0);
            let target = Vec3A::new(6.0 * h(1) - 3.0, 3.0 * h(2) - 0.3, 6.0 * h(3) - 3.0);
            let from = if i % 2 == 0 {
                Vec3A::new(0.0, 1.6, 5.5)
            } else {
                Vec3A::new(target.x, 1e-3, target.z)
            };
            let towards_sun = Vec3A::new(0.262, 0.643, 0.72).normalize();
            let dir = match i % 2 {
                0 => (target - from).normalize(),
                _ => towards_sun,
            };
            let ray = Ray::new(from, dir, time);
            let hit = sliced.intersect(&ray);
            assert_eq!(hit, whole.intersect(&ray), "ray {i}");
            let occluded = sliced.occluded(&ray);
            assert_eq!(occluded, whole.occluded(&ray), "ray {i}");
            spinning += usize::from(hit.is_some_and(|h| h.instance > 1));
            blocked += usize::from(i % 2 == 1 && occluded);
        }
        assert!(spinning > 2_000 && blocked > 200, "{spinning} {blocked}");
    }

    /// Whatever the rounding of the cuts, the piece chosen holds the time: the shutter's ends,
    /// the cuts themselves and their neighbours, and times across a shutter at the thesis's
    /// start (t = -12.5 s, where the cuts round) and at a zero-length shutter.
    #[test]
    fn the_piece_chosen_holds_the_time() {
        for (t0, t1) in [(-12.5f32, -12.38), (0.0, 0.12), (11.9, 12.02), (3.0, 3.0)] {
            let s = Slices::build(&[], &[], (t0, t1), SLICES, |b| b);
            let mut times: Vec<f32> = s.cuts.clone();
            times.extend(s.cuts.iter().flat_map(|c| [c.next_down(), c.next_up()]));
            times.extend((0..=1000).map(|i| t0 + (t1 - t0) * (i as f32 / 1000.0)));
            for t in times.into_iter().filter(|&t| t >= t0 && t <= t1) {
                let top: *const Bvh4 = s.at(t);
                let k = s.tops.iter().position(|b| std::ptr::eq(b, top)).unwrap();
                assert!(
                    s.cuts[k] <= t && t <= s.cuts[k + 1],
                    "{t} in piece {k} ({}..{})",
                    s.cuts[k],
                    s.cuts[k + 1]
                );
            }
        }
    }
}
