//! Rays and vectors in lanes, one value per ray of a packet: what the packet form of the world
//! (`packet`, `orbits`, `around`, `cull`, each spin's rotation in `chain`), the shading in
//! lanes and the camera rays in lanes share. Imports nothing else from `accel`.
//!
//! Each operation does the scalar code's f32 operations in the scalar code's order (glam's SSE2
//! `dot` is `(x x' + y y') + z z'`, `Mat3A * v` is `(c0 v.x + c1 v.y) + c2 v.z`), so a lane's
//! result is the scalar one to the bit.

use crate::geometry::Ray;
pub(crate) use crate::simd::Lanes;
use glam::{Mat3A, Vec3A};

/// Rays per packet: the lanes of [`Lane`]. (With baseline x86-64's SSE2, `f32x8` is two
/// `f32x4` halves per operation: no wider arithmetic, but two independent latency chains
/// interleaved.)
pub const LANES: usize = 8;

/// One `f32` per ray of a packet.
pub type Lane = wide::f32x8;

/// At most this many instances in a world's packet form (`packet::SmallWorld`): brute force
/// tests each for every ray (an orbiting group's spheres only where its bound lets a lane
/// through, `accel::orbits`), and past some number the top-level BVH (which skips most of them)
/// wins even against a packet. The thesis's spheres scene, 22 instances (20 of them orbiting in
/// 3 groups), takes 0.73x the time and 0.93x the instructions in packets, mirror bounces
/// included, that it takes through the top level (measured at spin6, commit 1615eed's
/// `docs/benchmarks/lanes.md`); larger worlds were not measured.
pub const MAX_INSTANCES: usize = 24;

/// `[f(0), f(1), f(2)]`: `std::array::from_fn` for a vector in lanes, always inlined (the
/// AVX2 form of the packet code needs every lane operation inlined into its entry,
/// `simd::run_in`, and `from_fn` is not always).
#[inline(always)]
pub(crate) fn each<L: Lanes>(f: impl Fn(usize) -> L) -> [L; 3] {
    [f(0), f(1), f(2)]
}

/// `m * v` lane by lane in glam's order: `(x_axis v.x + y_axis v.y) + z_axis v.z`.
#[inline(always)]
pub(crate) fn mul<L: Lanes>(m: &Mat3A, v: [L; 3]) -> [L; 3] {
    let (cx, cy, cz) = (
        m.x_axis.to_array(),
        m.y_axis.to_array(),
        m.z_axis.to_array(),
    );
    each(|k| L::splat(cx[k]) * v[0] + L::splat(cy[k]) * v[1] + L::splat(cz[k]) * v[2])
}

/// glam's SSE2 `Vec3A::dot`, lane by lane.
#[inline(always)]
pub(crate) fn dot<L: Lanes>(a: &[L; 3], b: &[L; 3]) -> L {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// [`LANES`] rays, lane `i` holding ray `i` (only origin, direction, time and `t_max`: the lanes
/// traced here all have `t_min = 0`).
#[derive(Clone, Copy, Debug)]
pub struct RayPacket<L: Lanes = Lane> {
    pub(crate) origin: [L; 3],
    pub(crate) dir: [L; 3],
    pub(crate) time: L,
    pub(crate) t_max: L,
}

impl<L: Lanes> RayPacket<L> {
    /// The same rays in lanes of type `M`.
    #[inline(always)]
    pub(crate) fn cast<M: Lanes>(&self) -> RayPacket<M> {
        let v = |c: &[L; 3]| each(|k| M::from_wide(c[k].to_wide()));
        RayPacket {
            origin: v(&self.origin),
            dir: v(&self.dir),
            time: M::from_wide(self.time.to_wide()),
            t_max: M::from_wide(self.t_max.to_wide()),
        }
    }

    /// The lanes of `simple` (not empty); the others repeat one of them, so that no lane
    /// computes with a NaN or a zero direction (their results are dropped anyway).
    #[cfg(test)]
    pub(crate) fn of(rays: &[Ray; LANES], simple: u32) -> Self {
        let first = &rays[simple.trailing_zeros() as usize];
        Self::new(&std::array::from_fn(|i| {
            if simple & (1 << i) != 0 {
                rays[i]
            } else {
                *first
            }
        }))
    }

    /// Rays laid out one by one, in lanes (the tests build their packets so; the renderer
    /// makes its packets in lanes from the start).
    #[cfg(test)]
    pub fn new(rays: &[Ray; LANES]) -> Self {
        let lanes = |v: [Vec3A; LANES]| -> [L; 3] {
            let v = v.map(|v| v.to_array());
            std::array::from_fn(|k| L::new(std::array::from_fn(|i| v[i][k])))
        };
        Self {
            origin: lanes(rays.each_ref().map(|r| r.origin)),
            dir: lanes(rays.each_ref().map(|r| r.dir)),
            time: L::new(rays.each_ref().map(|r| r.time)),
            t_max: L::new(rays.each_ref().map(|r| r.t_max)),
        }
    }

    /// Lane `i` as a ray (for the lanes the scalar path takes).
    pub(crate) fn lane(&self, i: usize) -> Ray {
        let v = |c: &[L; 3]| Vec3A::new(c[0].as_array()[i], c[1].as_array()[i], c[2].as_array()[i]);
        Ray {
            origin: v(&self.origin),
            dir: v(&self.dir),
            time: self.time.as_array()[i],
            t_min: 0.0,
            t_max: self.t_max.as_array()[i],
        }
    }
}

/// The rounding slack of the lanes' "passes clearly outside" tests (the spheres' and the
/// spinning groups' bounds, `accel::orbits`): `64u` of the squared distance's largest term.
/// `a |o|^2 - (o·d)^2` is computed with an error of at most `8u a |o|^2` (`(o·d)^2 <= a |o|^2`),
/// and a line that passes at distance `D` with `D^2 > r^2 + 64u |o|^2` (and `D <= |o|`) passes
/// at least `32u |o|` outside `r`, more than the foot's rounding in the exact test.
pub(crate) const SLACK: f32 = 64.0 * f32::EPSILON / 2.0;

/// `o + d t` lane by lane ([`Ray::at`]).
#[inline(always)]
pub(crate) fn point_at<L: Lanes>(o: &[L; 3], d: &[L; 3], t: L) -> [L; 3] {
    each(|k| o[k] + d[k] * t)
}
