//! Walking a [`Bvh4`]: four slab tests at once per node (`wide::f32x4`: SSE2 on x86_64, NEON
//! on aarch64, plain arrays elsewhere), children visited nearest first for closest hits, and
//! popped subtrees skipped when the hit found meanwhile is nearer than their entry.
//!
//! The slab test is obvhs's, lane by lane: a face's parameter is `(b - o) * (1 / d)`, the entry
//! the largest of the near faces', the exit the smallest of the far faces', and a box is hit when
//! `max(entry, 0) <= min(exit, t_max)`. Which face of an axis is near is decided once per ray
//! from the sign of `1 / d`; `(lo - o) * inv <= (hi - o) * inv` holds after rounding because
//! rounding is monotone, so this picks exactly the values obvhs's `min`/`max` picks. No value is
//! ever NaN (origins are finite, `1 / d` is clamped to ±f32::MAX, empty lanes are ±inf boxes),
//! so the lane minimum and maximum agree on every target: the same nodes are visited everywhere.

use super::wide::{Bvh4, LEAF, Node4};
use glam::Vec3A;
use std::mem::MaybeUninit;
use wide::f32x4;

/// A ray prepared for box tests.
#[derive(Clone, Copy, Debug)]
pub struct BoxRay {
    origin: [f32x4; 3],
    inv_dir: [f32x4; 3],
    /// `bounds` row of the near face per axis (`2 axis` or `2 axis + 1`); the far one is `^ 1`.
    near: [usize; 3],
}

impl BoxRay {
    /// The ray from `origin` along `dir`, or `None` for a ray that can hit nothing (a zero or
    /// non-finite direction, a non-finite origin): no box test has to think about NaN.
    #[inline]
    pub fn new(origin: Vec3A, dir: Vec3A) -> Option<Self> {
        if !(origin.is_finite() && dir.is_finite()) || dir == Vec3A::ZERO {
            return None;
        }
        // Exact reciprocals where finite, ±MAX for zero components (`0 * inv` is then 0, not
        // NaN); see `geometry::Ray::traversal_ray`.
        let inv = dir
            .recip()
            .clamp(Vec3A::splat(-f32::MAX), Vec3A::splat(f32::MAX));
        // Named lanes, not `Vec3A[i]` (a runtime index is a three-way branch in glam): this
        // constructor ran at ~60 instructions before.
        let (o, n) = (origin, |v: f32| usize::from(v.is_sign_negative()));
        Some(Self {
            origin: [f32x4::splat(o.x), f32x4::splat(o.y), f32x4::splat(o.z)],
            inv_dir: [
                f32x4::splat(inv.x),
                f32x4::splat(inv.y),
                f32x4::splat(inv.z),
            ],
            near: [n(inv.x), 2 + n(inv.y), 4 + n(inv.z)],
        })
    }

    /// Entry parameters of the four children and the mask of those hit within `[0, t_max]`.
    #[inline(always)]
    fn test(&self, node: &Node4, t_max: f32) -> (u32, [f32; 4]) {
        let slab = |row: usize, a: usize| {
            (f32x4::new(node.bounds[row]) - self.origin[a]) * self.inv_dir[a]
        };
        let [nx, ny, nz] = self.near;
        let entry = slab(nx, 0)
            .fast_max(slab(ny, 1))
            .fast_max(slab(nz, 2))
            .fast_max(f32x4::ZERO);
        let exit = slab(nx ^ 1, 0)
            .fast_min(slab(ny ^ 1, 1))
            .fast_min(slab(nz ^ 1, 2))
            .fast_min(f32x4::splat(t_max));
        (entry.simd_le(exit).to_bitmask(), entry.to_array())
    }
}

/// The traversal stack: subtrees still to visit and their entry parameters. Sixty-four entries
/// live on the call stack, left uninitialised; a collapsed tree pushes at most three per level,
/// and the trees here are a few tens of levels deep; a deeper tree spills to the heap instead
/// of failing. The entries fill from the top down: with a count starting at zero, LLVM merged
/// the count's zero store with the uninitialised array into one 520-byte memset per traversal
/// (6% of a trace's instructions, callgrind).
struct Stack {
    inline: MaybeUninit<[(u32, f32); 64]>,
    /// Index of the most recent entry in `inline`; 64 when it is empty.
    top: usize,
    spill: Vec<(u32, f32)>,
}

impl Stack {
    #[inline(always)]
    fn new() -> Self {
        Self {
            inline: MaybeUninit::uninit(),
            top: 64,
            spill: Vec::new(),
        }
    }

    #[inline(always)]
    fn slot(&mut self, i: usize) -> *mut (u32, f32) {
        debug_assert!(i < 64);
        // SAFETY: `i < 64`, inside the array.
        unsafe { self.inline.as_mut_ptr().cast::<(u32, f32)>().add(i) }
    }

    #[inline(always)]
    fn push(&mut self, e: (u32, f32)) {
        if self.top > 0 {
            self.top -= 1;
            // SAFETY: a slot of the array; writing never reads it.
            unsafe { self.slot(self.top).write(e) };
        } else {
            self.spill.push(e);
        }
    }

    #[inline(always)]
    fn pop(&mut self) -> Option<(u32, f32)> {
        if !self.spill.is_empty() {
            return self.spill.pop();
        }
        if self.top == 64 {
            return None;
        }
        // SAFETY: slots from `top` up were written by `push`.
        let e = unsafe { self.slot(self.top).read() };
        self.top += 1;
        Some(e)
    }
}

impl Bvh4 {
    /// Closest-hit traversal. `leaf(i, t_max)` tests leaf `i`'s primitives for hits nearer
    /// than `t_max` and returns the nearest one's parameter (or anything >= `t_max` for none);
    /// returns the nearest parameter found, or `t_max` if none.
    #[inline(always)]
    pub fn closest(
        &self,
        ray: &BoxRay,
        mut t_max: f32,
        mut leaf: impl FnMut(u32, f32) -> f32,
    ) -> f32 {
        let Some(mut current) = self.root else {
            return t_max;
        };
        let mut stack = Stack::new();
        loop {
            if current & LEAF != 0 {
                t_max = t_max.min(leaf(current & !LEAF, t_max));
            } else {
                let node = &self.nodes[current as usize];
                let (mask, entry) = ray.test(node, t_max);
                if mask != 0 {
                    current = visit_nearest_first(node, mask, entry, &mut stack);
                    continue;
                }
            }
            // Next: the most recently pushed subtree that can still hold a nearer hit.
            loop {
                match stack.pop() {
                    None => return t_max,
                    Some((r, entry)) if entry <= t_max => {
                        current = r;
                        break;
                    }
                    Some(_) => {}
                }
            }
        }
    }

    /// Any-hit traversal (shadow rays): `leaf(i)` says whether leaf `i` blocks the ray; stops
    /// at the first that does.
    #[inline(always)]
    pub fn any(&self, ray: &BoxRay, t_max: f32, mut leaf: impl FnMut(u32) -> bool) -> bool {
        let Some(mut current) = self.root else {
            return false;
        };
        let mut stack = Stack::new();
        loop {
            if current & LEAF != 0 {
                if leaf(current & !LEAF) {
                    return true;
                }
            } else {
                let node = &self.nodes[current as usize];
                let (mut mask, _) = ray.test(node, t_max);
                if mask != 0 {
                    current = node.child[mask.trailing_zeros() as usize];
                    mask &= mask - 1;
                    while mask != 0 {
                        stack.push((node.child[mask.trailing_zeros() as usize], 0.0));
                        mask &= mask - 1;
                    }
                    continue;
                }
            }
            match stack.pop() {
                None => return false,
                Some((r, _)) => current = r,
            }
        }
    }
}

/// Push the hit children of `node` farthest first and return the nearest, so the stack pops
/// them in order of entry. Equal entries keep lane order (deterministic). One and two hits,
/// the common cases, take no sort.
#[inline(always)]
fn visit_nearest_first(node: &Node4, mask: u32, entry: [f32; 4], stack: &mut Stack) -> u32 {
    let lane = |m: u32| (m.trailing_zeros() & 3) as usize;
    let a = lane(mask);
    let rest = mask & (mask - 1);
    if rest == 0 {
        return node.child[a];
    }
    let b = lane(rest);
    if rest & (rest - 1) == 0 {
        let (near, far) = if entry[b] < entry[a] { (b, a) } else { (a, b) };
        stack.push((node.child[far], entry[far]));
        return node.child[near];
    }
    // Three or four: sort the lanes by entry (insertion sort, stable).
    let mut order = [a, b, 0, 0];
    let mut n = 2;
    if entry[b] < entry[a] {
        order.swap(0, 1);
    }
    let mut m = rest & (rest - 1);
    while m != 0 {
        let l = lane(m);
        let mut i = n;
        while i > 0 && entry[order[i - 1]] > entry[l] {
            order[i] = order[i - 1];
            i -= 1;
        }
        order[i] = l;
        n += 1;
        m &= m - 1;
    }
    for &l in order[1..n].iter().rev() {
        stack.push((node.child[l], entry[l]));
    }
    node.child[order[0]]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Ray;
    use obvhs::BvhBuildParams;
    use obvhs::aabb::Aabb;
    use obvhs::bvh2::builder::build_bvh2;
    use std::time::Duration;

    /// A grid of small boxes; closest and any-hit traversal against testing every box.
    #[test]
    fn traversal_finds_what_testing_every_box_finds() {
        let prims: Vec<Aabb> = (0..400)
            .map(|i| {
                let p = Vec3A::new((i % 20) as f32, (i / 20) as f32, ((i * 7) % 5) as f32);
                Aabb::new(p, p + 0.6)
            })
            .collect();
        let bvh2 = build_bvh2(
            &prims,
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        );
        let wide = Bvh4::from_bvh2(&bvh2);
        let mut hits = 0;
        for k in 0..2000u64 {
            let h = |a: u64| crate::hash::unit_f32(crate::hash::hash(5, &[k, a]));
            let origin = Vec3A::new(h(0) * 30.0 - 5.0, h(1) * 30.0 - 5.0, -10.0 + h(2) * 25.0);
            let target = Vec3A::new(h(3) * 20.0, h(4) * 20.0, h(5) * 5.0);
            let mut ray = Ray::new(origin, target - origin, 0.0);
            if k % 3 == 0 {
                ray.t_max = h(6) * 1.5;
            }
            let br = BoxRay::new(ray.origin, ray.dir).unwrap();
            // Each primitive's own slab test, as the leaf test; the nearest entry wins.
            let entry = |p: u32| {
                let r = ray.traversal_ray();
                let t = prims[p as usize].intersect_ray(&r);
                (t.is_finite() && t <= ray.t_max).then_some(t.max(0.0))
            };
            let brute = (0..prims.len() as u32)
                .filter_map(entry)
                .fold(f32::INFINITY, f32::min);
            let found = wide.closest(&br, ray.t_max, |leaf, t_max| {
                wide.leaf(leaf)
                    .iter()
                    .filter_map(|&p| entry(p))
                    .filter(|&t| t <= t_max)
                    .fold(f32::INFINITY, f32::min)
            });
            let expect = if brute.is_finite() { brute } else { ray.t_max };
            assert_eq!(found, expect, "ray {k}");
            let any = wide.any(&br, ray.t_max, |leaf| {
                wide.leaf(leaf).iter().any(|&p| entry(p).is_some())
            });
            assert_eq!(any, brute.is_finite(), "ray {k}");
            hits += usize::from(brute.is_finite());
        }
        assert!(hits > 200 && hits < 1900, "{hits} of 2000 rays hit");
    }

    #[test]
    fn degenerate_rays_are_refused_and_deep_stacks_spill() {
        assert!(BoxRay::new(Vec3A::ZERO, Vec3A::ZERO).is_none());
        assert!(BoxRay::new(Vec3A::ZERO, Vec3A::new(f32::NAN, 1.0, 0.0)).is_none());
        assert!(BoxRay::new(Vec3A::splat(f32::INFINITY), Vec3A::X).is_none());
        let mut s = Stack::new();
        for i in 0..200u32 {
            s.push((i, i as f32));
        }
        for i in (0..200u32).rev() {
            assert_eq!(s.pop(), Some((i, i as f32)));
        }
        assert_eq!(s.pop(), None);
    }
}
