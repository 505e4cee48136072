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
//! the piece its time lies in ([`Slices::at`]: a product and a truncation, the pieces widened
//! by the guess's rounding).
//!
//! The answers do not change: each box still holds its instance at every time of its piece, so
//! an instance a ray's piece leaves out is one the ray cannot hit at its time. The same hits
//! are found and the nearest kept, except where two instances are hit at exactly the same `t`
//! (the first visited wins, in this top level's order as in any other: see
//! `accel::packet`'s ties); the thesis's films are byte-identical (`docs/benchmarks/lanes.md`,
//! "Output bytes changed at rounding level").

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

/// One top level per piece of the shutter: piece `k` covers `spans[k]`, the times whose guess
/// ([`Slices::at`]) is `k`, and a little more; a top level's primitive `p` is the world's
/// bounded instance `p` (the same order in all).
#[derive(Clone)]
pub(super) struct Slices {
    tops: Vec<Bvh4>,
    /// The times each piece's boxes hold (kept for the tests).
    #[cfg(test)]
    spans: Vec<(f32, f32)>,
    t0: f32,
    /// Pieces per unit of time, for the guess of a time's piece (a product, not a division:
    /// every ray asks).
    per_time: f32,
}

impl Slices {
    /// `pieces` top levels (at least one) over `bounded` instances in the shutter `(t0, t1)`
    /// (`t0 <= t1`), each box padded by `pad`.
    ///
    /// The guess `k = floor((t - t0) * per_time)` rounds three times (the difference, the
    /// product, and `per_time = n / (t1 - t0)` twice), so it is `x (1 + e)` with `|e| < 4u`
    /// (u = 2^-24) of the exact `x = n (t - t0) / (t1 - t0)`: a time is at most
    /// `4u (t1 - t0)` outside the piece it is guessed into, and the computed ends of a piece
    /// are within a few `u (|t0| + |t1|)` of the exact ones. Each piece is therefore built over
    /// its ends widened by `margin = 32u (|t0| + |t1|)` (at the thesis's times 5e-5 s, against
    /// pieces of 7.5e-3 s), so every time of the shutter lies in its guessed piece's span, with
    /// no correction at trace time (`the_guessed_piece_holds_the_time`).
    pub(super) fn build(
        instances: &[Instance],
        bounded: &[u32],
        shutter: (f32, f32),
        pieces: usize,
        pad: impl Fn(Bounds) -> Bounds,
    ) -> Self {
        let pieces = pieces.max(1);
        let (t0, t1) = shutter;
        let margin = 32.0 * (f32::EPSILON / 2.0) * (t0.abs() + t1.abs());
        let at = |k: usize| t0 + (t1 - t0) * (k as f32 / pieces as f32);
        let spans: Vec<(f32, f32)> = (0..pieces)
            .map(|k| match pieces {
                1 => (t0, t1),
                _ => (at(k) - margin, at(k + 1) + margin),
            })
            .collect();
        let tops = spans
            .iter()
            .map(|&span| {
                let boxes: Vec<_> = bounded
                    .iter()
                    .map(|&i| {
                        let inst = &instances[i as usize];
                        pad(swept_bounds(inst.shape.bounds(), &inst.motion, span)).to_aabb()
                    })
                    .collect();
                top_level(&boxes)
            })
            .collect();
        Self {
            tops,
            #[cfg(test)]
            spans,
            t0,
            per_time: pieces as f32 / (t1 - t0),
        }
    }

    /// The top level of the piece that holds time `t`, which lies in the shutter.
    #[inline(always)]
    pub(super) fn at(&self, t: f32) -> &Bvh4 {
        &self.tops[self.piece(t)]
    }

    /// The guessed piece of `t` (a NaN guess, from a zero-length shutter, and a negative one
    /// saturate to 0; `t1` itself to the last piece).
    #[inline(always)]
    fn piece(&self, t: f32) -> usize {
        (((t - self.t0) * self.per_time) as usize).min(self.tops.len() - 1)
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

    /// Whatever the rounding, the guessed piece's span holds the time: the shutter's ends,
    /// the exact cuts and their neighbours, and times across shutters at the thesis's start
    /// (t = -12.5 s, where the cuts round), at 0, late, far out, and of zero length.
    #[test]
    fn the_guessed_piece_holds_the_time() {
        for (t0, t1) in [
            (-12.5f32, -12.38),
            (0.0, 0.12),
            (11.9, 12.02),
            (-0.06, 0.06),
            (1000.0, 1000.04),
            (3.0, 3.0),
        ] {
            let s = Slices::build(&[], &[], (t0, t1), SLICES, |b| b);
            let n = SLICES as f32;
            let cuts = (0..=SLICES).map(|k| t0 + (t1 - t0) * (k as f32 / n));
            let mut times: Vec<f32> = cuts.flat_map(|c| [c, c.next_down(), c.next_up()]).collect();
            times.extend((0..=10_000).map(|i| t0 + (t1 - t0) * (i as f32 / 10_000.0)));
            times.extend([t0, t1]);
            for t in times.into_iter().filter(|&t| t >= t0 && t <= t1) {
                let k = s.piece(t);
                let (a, b) = s.spans[k];
                assert!(
                    a <= t && t <= b,
                    "{t} in piece {k} ({a}..{b}) of {t0}..{t1}"
                );
            }
        }
    }
}
