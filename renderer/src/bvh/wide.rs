//! The 4-wide BVH: obvhs's binary BVH collapsed so each node holds up to four children's boxes
//! side by side, one SIMD lane per child.
//!
//! Collapsing (as Embree's and pbrt's wide BVHs do): start a node with the two children of a
//! binary node; while it has fewer than four and one of them is an inner node, replace the
//! inner child with the largest surface area by its two children. A binary leaf stays a leaf:
//! its primitives are one leaf of the wide tree. The boxes are obvhs's (unions of the padded
//! primitive boxes, `Bounds::padded`), so the padding argument of `docs/geometry.md` carries
//! over unchanged: the box test computes the same `(b - o) / d` slabs.

use obvhs::bvh2::Bvh2;

/// A child reference: an inner node's index, or [`LEAF`] | a leaf's index.
pub(crate) const LEAF: u32 = 1 << 31;

/// Four children's boxes, one lane each, as `bounds[2 axis + side]` with side 0 the lower and
/// 1 the upper face; empty lanes have min = +inf, max = -inf, which no ray hits. 128 bytes,
/// aligned to a cache line: one node is two line fetches.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(crate) struct Node4 {
    pub bounds: [[f32; 4]; 6],
    pub child: [u32; 4],
}

impl Node4 {
    const EMPTY: Node4 = Node4 {
        bounds: [
            [f32::INFINITY; 4],
            [f32::NEG_INFINITY; 4],
            [f32::INFINITY; 4],
            [f32::NEG_INFINITY; 4],
            [f32::INFINITY; 4],
            [f32::NEG_INFINITY; 4],
        ],
        child: [u32::MAX; 4],
    };
}

/// A 4-wide BVH over primitives `0..n`, whose leaves are ranges of [`Bvh4::order`].
#[derive(Clone, Debug, Default)]
pub struct Bvh4 {
    pub(crate) nodes: Vec<Node4>,
    /// Where traversal starts: a node, a leaf (a tree of one leaf), or `None` when empty.
    pub(crate) root: Option<u32>,
    /// Leaf `i` holds primitives `order[leaves[i].0 .. leaves[i].0 + leaves[i].1]`. Leaves are
    /// numbered in depth-first order, the order traversal tends to meet them.
    leaves: Vec<(u32, u32)>,
    /// Primitive indices (into the caller's list) in leaf order.
    order: Vec<u32>,
    /// Nodes on the longest root-to-leaf path (sizes the traversal stack).
    depth: u32,
}

impl Bvh4 {
    /// Collapse `bvh` (built over the caller's primitives) into a 4-wide tree.
    pub fn from_bvh2(bvh: &Bvh2) -> Self {
        let Some(root) = bvh.nodes.first() else {
            return Self::default();
        };
        let mut out = Bvh4::default();
        let leaf = |out: &mut Bvh4, n: usize| -> u32 {
            let node = &bvh.nodes[n];
            let first = out.order.len() as u32;
            let prims = node.first_index as usize..(node.first_index + node.prim_count) as usize;
            out.order.extend_from_slice(&bvh.primitive_indices[prims]);
            out.leaves.push((first, node.prim_count));
            LEAF | (out.leaves.len() as u32 - 1)
        };
        if root.prim_count > 0 {
            out.root = Some(leaf(&mut out, 0));
            return out;
        }
        out.root = Some(0);
        out.nodes.push(Node4::EMPTY);
        // (binary inner node, wide node to fill, depth of that wide node); a stack, so the
        // wide nodes come out in depth-first order.
        let mut work = vec![(0usize, 0u32, 1u32)];
        while let Some((n, slot, depth)) = work.pop() {
            out.depth = out.depth.max(depth);
            let children = widen(bvh, n);
            let mut node = Node4::EMPTY;
            for (lane, &c) in children.iter().enumerate() {
                let b = &bvh.nodes[c];
                let (lo, hi) = (b.aabb.min, b.aabb.max);
                for axis in 0..3 {
                    node.bounds[2 * axis][lane] = lo[axis];
                    node.bounds[2 * axis + 1][lane] = hi[axis];
                }
                node.child[lane] = if b.prim_count > 0 {
                    leaf(&mut out, c)
                } else {
                    out.nodes.push(Node4::EMPTY);
                    let index = out.nodes.len() as u32 - 1;
                    work.push((c, index, depth + 1));
                    index
                };
            }
            out.nodes[slot as usize] = node;
        }
        out
    }

    /// Leaf `i`'s primitives (indices into the list the tree was built over).
    #[inline]
    pub fn leaf(&self, i: u32) -> &[u32] {
        let (first, count) = self.leaves[i as usize];
        &self.order[first as usize..(first + count) as usize]
    }

    /// Leaf `i`'s primitives as a range of [`Bvh4::order`]: `(first, count)`.
    #[inline]
    pub fn leaf_range(&self, i: u32) -> (u32, u32) {
        self.leaves[i as usize]
    }

    /// Primitive indices (into the list the tree was built over) in leaf order: leaf `i` holds
    /// `order()[first..first + count]` with `(first, count)` = [`Bvh4::leaf_range`].
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    pub fn leaf_count(&self) -> usize {
        self.leaves.len()
    }

    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Nodes on the longest path from the root to a leaf.
    pub fn depth(&self) -> u32 {
        self.depth
    }
}

/// The (up to four) binary nodes that become the children of the wide node made from binary
/// inner node `n`, in a fixed order (ties broken by position), so builds are deterministic.
fn widen(bvh: &Bvh2, n: usize) -> Vec<usize> {
    let first = bvh.nodes[n].first_index as usize;
    let mut children = vec![first, first + 1];
    while children.len() < 4 {
        let inner = children
            .iter()
            .enumerate()
            .filter(|&(_, &c)| bvh.nodes[c].prim_count == 0)
            .max_by(|a, b| {
                let area = |c: usize| bvh.nodes[c].aabb.half_area();
                area(*a.1).total_cmp(&area(*b.1)).then(b.0.cmp(&a.0))
            })
            .map(|(i, _)| i);
        let Some(i) = inner else { break };
        let c = bvh.nodes[children[i]].first_index as usize;
        children.splice(i..=i, [c, c + 1]);
    }
    children
}

#[cfg(test)]
mod tests {
    use super::*;
    use obvhs::BvhBuildParams;
    use obvhs::aabb::Aabb;
    use obvhs::bvh2::builder::build_bvh2;
    use std::time::Duration;

    fn boxes(n: usize) -> Vec<Aabb> {
        (0..n)
            .map(|i| {
                let x = (i * 7 % 31) as f32;
                let y = (i * 13 % 17) as f32;
                let p = glam::Vec3A::new(x, y, (i % 5) as f32);
                Aabb::new(p, p + 0.5)
            })
            .collect()
    }

    /// Every primitive lands in exactly one leaf, every child box holds its subtree's boxes,
    /// and no node is left with a single child.
    #[test]
    fn collapsing_keeps_every_primitive_once_inside_its_boxes() {
        for n in [1usize, 2, 3, 5, 64, 1000] {
            let prims = boxes(n);
            for params in [
                BvhBuildParams::fastest_build(),
                BvhBuildParams::medium_build(),
            ] {
                let bvh2 = build_bvh2(&prims, params, &mut Duration::default());
                let wide = Bvh4::from_bvh2(&bvh2);
                let mut seen = vec![0; n];
                // (reference, the box it must lie in)
                let mut work = vec![(wide.root.unwrap(), Aabb::INFINITY)];
                while let Some((r, outer)) = work.pop() {
                    if r & LEAF != 0 {
                        for &p in wide.leaf(r & !LEAF) {
                            seen[p as usize] += 1;
                            let b = prims[p as usize];
                            assert!(outer.contains_point(b.min) && outer.contains_point(b.max));
                        }
                        continue;
                    }
                    let node = &wide.nodes[r as usize];
                    let used = node.child.iter().filter(|&&c| c != u32::MAX).count();
                    assert!(used >= 2, "node {r} has {used} children");
                    for lane in 0..used {
                        let b = |i: usize| node.bounds[i][lane];
                        let lo = glam::Vec3A::new(b(0), b(2), b(4));
                        let hi = glam::Vec3A::new(b(1), b(3), b(5));
                        assert!(outer.contains_point(lo) && outer.contains_point(hi));
                        work.push((node.child[lane], Aabb::new(lo, hi)));
                    }
                }
                assert!(seen.iter().all(|&s| s == 1), "n = {n}");
                assert!(wide.depth() as usize <= n.max(1));
            }
        }
        assert_eq!(Bvh4::from_bvh2(&Bvh2::default()).root, None);
    }
}
