//! The watertight test ([`super::triangle`]) on four triangles at once, one per SIMD lane
//! (`wide::f32x4`).
//!
//! Lane by lane it does the scalar test's arithmetic in the scalar test's order: each corner
//! relative to the origin, sheared as `(d_kx - Sx d_kz, d_ky - Sy d_kz, Sz d_kz)`, the edge functions
//! `U = C'x B'y - C'y B'x` and its two rotations, the exact f64 recomputation when one of them
//! is zero, the sign test, `det = U + V + W` and `t = (U A'z + V B'z + W C'z) / det`. So every
//! lane returns bit for bit the scalar test's `t`, and watertightness carries over: a shared
//! vertex is sheared to the same bits in every lane and every leaf, and an edge's function is
//! the exact negation of its neighbour's. No FMA: products and sums are rounded separately, as
//! in the scalar test (Rust never contracts them).

use super::triangle::{WatertightRay, exact_edges};
use glam::Vec3A;
use wide::f32x4;

/// Four triangles' corners, lane `i` holding triangle `i`: `corner[k][axis]`. 144 bytes.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub struct Triangle4 {
    corner: [[f32x4; 3]; 3],
}

impl Triangle4 {
    /// One to four triangles; missing lanes repeat the last one (a copy finds the same hit as
    /// its original, at a later lane, so it changes no result).
    pub fn new(tris: &[[Vec3A; 3]]) -> Self {
        debug_assert!((1..=4).contains(&tris.len()));
        let tri = |lane: usize| tris[lane.min(tris.len() - 1)];
        let corner = std::array::from_fn(|k| {
            std::array::from_fn(|axis| f32x4::new(std::array::from_fn(|l| tri(l)[k][axis])))
        });
        Self { corner }
    }
}

/// A ray prepared for four-lane tests: the shear's constants in every lane.
#[derive(Clone, Copy, Debug)]
pub struct WatertightRay4 {
    /// Origin coordinates in the permuted order (o_kx, o_ky, o_kz).
    origin: [f32x4; 3],
    shear: [f32x4; 3],
    axes: [usize; 3],
}

impl WatertightRay4 {
    pub fn new(ray: &WatertightRay) -> Self {
        let o = ray.origin().to_array();
        Self {
            origin: ray.axes.map(|a| f32x4::splat(o[a])),
            shear: ray.shear.map(f32x4::splat),
            axes: ray.axes,
        }
    }

    /// Corner `k` of the four triangles in the ray's sheared frame: (x, y, z) lanes.
    #[inline(always)]
    fn sheared(&self, tri: &Triangle4, k: usize) -> [f32x4; 3] {
        let [kx, ky, kz] = self.axes;
        let c = &tri.corner[k];
        let dz = c[kz] - self.origin[2];
        [
            (c[kx] - self.origin[0]) - self.shear[0] * dz,
            (c[ky] - self.origin[1]) - self.shear[1] * dz,
            self.shear[2] * dz,
        ]
    }

    /// Each lane's hit parameter for `t_min < t < t_max`, `+inf` where it misses. The ray must
    /// be valid ([`WatertightRay::is_valid`]).
    #[inline(always)]
    pub fn intersect(&self, tri: &Triangle4, t_min: f32, t_max: f32) -> f32x4 {
        let [ax, ay, az] = self.sheared(tri, 0);
        let [bx, by, bz] = self.sheared(tri, 1);
        let [cx, cy, cz] = self.sheared(tri, 2);
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        let zero = u.simd_eq(f32x4::ZERO) | v.simd_eq(f32x4::ZERO) | w.simd_eq(f32x4::ZERO);
        if zero.any() {
            [u, v, w] = exact_lanes(
                zero.to_bitmask(),
                [u, v, w],
                [ax, ay, az, bx, by, bz, cx, cy, cz],
            );
        }
        let neg = u.simd_lt(f32x4::ZERO) | v.simd_lt(f32x4::ZERO) | w.simd_lt(f32x4::ZERO);
        let pos = u.simd_gt(f32x4::ZERO) | v.simd_gt(f32x4::ZERO) | w.simd_gt(f32x4::ZERO);
        let det = u + v + w;
        let t = (u * az + v * bz + w * cz) / det;
        // NaN fails every comparison, so it never passes.
        let hit = !(neg & pos)
            & det.simd_ne(f32x4::ZERO)
            & det.abs().simd_lt(f32x4::splat(f32::INFINITY))
            & t.simd_gt(f32x4::splat(t_min))
            & t.simd_lt(f32x4::splat(t_max));
        hit.bitselect(t, f32x4::splat(f32::INFINITY))
    }
}

/// The lanes of `mask` with their edge functions recomputed with exact signs, as the scalar
/// test does when one rounds to zero. Rare, so out of line.
#[cold]
#[inline(never)]
fn exact_lanes(mask: u32, uvw: [f32x4; 3], s: [f32x4; 9]) -> [f32x4; 3] {
    let mut e = uvw.map(f32x4::to_array);
    let s = s.map(f32x4::to_array);
    for lane in (0..4).filter(|l| mask & (1 << l) != 0) {
        let p = |i: usize| Vec3A::new(s[i][lane], s[i + 1][lane], s[i + 2][lane]);
        let exact = exact_edges(p(0), p(3), p(6));
        for (k, value) in exact.into_iter().enumerate() {
            e[k][lane] = value;
        }
    }
    e.map(f32x4::new)
}

/// The nearest lane of `t` (`+inf` lanes are misses): `(t, lane)`, the lowest lane on ties.
#[inline(always)]
pub fn nearest_lane(t: f32x4) -> Option<(f32, usize)> {
    let a = t.to_array();
    let m = a[0].min(a[1]).min(a[2].min(a[3]));
    if m == f32::INFINITY {
        return None;
    }
    a.iter().position(|&x| x == m).map(|lane| (m, lane))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Ray;
    use crate::hash::{hash, unit_f32};

    /// Lane by lane, bit for bit the scalar test's `t`, on random triangles and rays, on
    /// rays through shared vertices and edges (the exact recomputation), and on degenerate
    /// triangles.
    #[test]
    fn every_lane_gives_the_scalar_test_s_t_bit_for_bit() {
        let r = |k: u64, a: u64| unit_f32(hash(9, &[k, a])) * 2.0 - 1.0;
        let v = |k: u64, a: u64| Vec3A::new(r(k, a), r(k, a + 1), r(k, a + 2));
        let mut hits = 0;
        for k in 0..20_000u64 {
            // Triangles sharing corners, sometimes degenerate (repeated or collinear corners).
            let p = [v(k, 0), v(k, 3), v(k, 6), v(k, 9)];
            let mut tris = [
                [p[0], p[1], p[2]],
                [p[0], p[2], p[3]],
                [p[1], p[3], p[2]],
                [p[0], p[0], p[1]],
            ];
            if k % 7 == 0 {
                tris[2] = [p[0], p[1], p[0] * 2.0 - p[1]];
            }
            let origin = v(k, 12) * 3.0;
            // Aim at a corner or an edge midpoint half of the time.
            let target = match k % 4 {
                0 => p[(k / 4 % 4) as usize],
                1 => (p[0] + p[2]) * 0.5,
                _ => v(k, 15) * 0.5,
            };
            let mut ray = Ray::new(origin, target - origin, 0.0);
            ray.t_min = if k % 5 == 0 { 0.9 } else { 0.0 };
            ray.t_max = if k % 3 == 0 { 1.0 } else { f32::INFINITY };
            let w = WatertightRay::new(&ray);
            let t = WatertightRay4::new(&w)
                .intersect(&Triangle4::new(&tris), ray.t_min, ray.t_max)
                .to_array();
            for (lane, tri) in tris.iter().enumerate() {
                let [a, b, c] = *tri;
                let scalar = w.intersect_t(a, b, c, ray.t_min, ray.t_max);
                assert_eq!(
                    scalar.map(f32::to_bits),
                    (t[lane] != f32::INFINITY).then_some(t[lane].to_bits()),
                    "ray {k} lane {lane}"
                );
                hits += usize::from(scalar.is_some());
            }
        }
        assert!(hits > 5_000, "{hits} hits");
        let padded = Triangle4::new(&[[Vec3A::X, Vec3A::Y, Vec3A::Z]]);
        let ray = Ray::new(Vec3A::ZERO, Vec3A::ONE, 0.0);
        let t = WatertightRay4::new(&WatertightRay::new(&ray)).intersect(&padded, 0.0, 10.0);
        assert_eq!(nearest_lane(t), Some((1.0 / 3.0, 0)));
        assert_eq!(nearest_lane(f32x4::splat(f32::INFINITY)), None);
    }

    /// Rays along -z through grid points of a unit square split on its diagonal: edge
    /// functions are exactly zero on the shared edge and at the corners, so lanes take the
    /// exact recomputation; they still agree with the scalar test, and no ray inside the square
    /// slips through.
    #[test]
    fn lanes_on_shared_edges_take_the_exact_path_and_agree() {
        let g = [Vec3A::ZERO, Vec3A::X, Vec3A::new(1.0, 1.0, 0.0), Vec3A::Y];
        let tris = [
            [g[0], g[1], g[2]],
            [g[0], g[2], g[3]],
            [g[2], g[0], g[1]],
            [g[3], g[0], g[2]],
        ];
        let quad = Triangle4::new(&tris);
        let mut on_edge = 0;
        for i in 0..=8 {
            for j in 0..=8 {
                let o = Vec3A::new(i as f32 / 8.0, j as f32 / 8.0, 2.0);
                let ray = Ray::new(o, -Vec3A::Z, 0.0);
                let w = WatertightRay::new(&ray);
                let w4 = WatertightRay4::new(&w);
                let t = w4.intersect(&quad, 0.0, f32::INFINITY).to_array();
                for (lane, &[a, b, c]) in tris.iter().enumerate() {
                    let scalar = w.intersect_t(a, b, c, 0.0, f32::INFINITY);
                    assert_eq!(scalar, (t[lane] != f32::INFINITY).then_some(t[lane]));
                }
                assert!(t.contains(&2.0), "ray at {o} slipped through");
                let [ax, ay, _] = w4.sheared(&quad, 0);
                let [cx, cy, _] = w4.sheared(&quad, 2);
                on_edge += usize::from((ax * cy - ay * cx).simd_eq(f32x4::ZERO).any());
            }
        }
        assert!(on_edge >= 9, "{on_edge} rays on the diagonal");
    }
}
