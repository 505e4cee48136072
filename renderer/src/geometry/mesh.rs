//! Triangle meshes in object space, with a 4-wide BVH built once per mesh.
//!
//! Motion moves rays, not triangles (see [`crate::accel`]), so the BVH never changes after
//! [`TriangleMesh::new`]. obvhs builds a binary BVH over padded triangle boxes
//! ([`Bounds::padded`]: the slab test is not conservative without it), at most four triangles
//! per leaf; [`Bvh4`] collapses it, and each leaf's triangles are packed into one
//! [`Triangle4`] tested in four SIMD lanes. Triangles are stored in leaf order, so leaf `i`'s
//! lanes are triangles `first_i ..`.

use super::bounds::SLACK_PER_DIAGONAL;
use super::triangle::WatertightRay;
use super::triangle4::{Triangle4, WatertightRay4, nearest_lane};
use super::{Bounds, ObjectHit, Ray, ShapeHit};
use crate::bvh::{BoxRay, Bvh4};
use glam::Vec3A;
use obvhs::BvhBuildParams;
use obvhs::bvh2::builder::build_bvh2;
use std::time::Duration;
use wide::f32x4;

/// Triangles per leaf: one [`Triangle4`].
const LEAF_SIZE: u32 = 4;

/// obvhs's most thorough preset without its pre-splitting (which would put a triangle in
/// several leaves): a mesh is built once per scene load and traced by every ray of every
/// frame, so build time is cheap against trace time. On the trace bench's 200k-triangle torus
/// it traced 8% faster than `medium_build` (median of 10 interleaved runs of
/// `trace_rays --rounds 40`, CPU time: 16.65 against 18.07 ms per 126k rays) for a build of
/// 0.42 s against 0.10 s; `slow_build` without pre-splitting was between (17.3 ms, 0.17 s).
const MESH_BUILD: BvhBuildParams = BvhBuildParams {
    pre_split: false,
    ..BvhBuildParams::very_slow_build()
};

/// Binary BVH nodes whose reinsertion a mesh's build may consider in its first pass:
/// obvhs's reinsertion optimiser (`reinsertion_batch_ratio`) weighs moving each of the first
/// `ratio x nodes` nodes elsewhere in the tree, two thirds of a 200k-triangle build with
/// [`MESH_BUILD`]'s ratio of 1. It works from the top of the tree down, where moves pay most,
/// so bounding the count bounds the build's cost on large meshes and changes nothing on
/// smaller ones (the thesis's airliner, 3,348 triangles, about 6,700 nodes). On the trace
/// bench's 200k-triangle torus a bound of 16,384 nodes built in 0.17-0.23 s of CPU instead of
/// 0.82-0.86 s and traced as fast (CPU per frame 0.96-1.01x; 4,096 nodes built hardly faster
/// and traced up to 7% slower; 65,536 built in 0.23-0.29 s), `trace_rays --rounds 7`, three
/// interleaved rounds at load 8.7 (BENCHMARKS.md, issue 30).
const REINSERTION_NODES: f32 = 16_384.0;

/// [`MESH_BUILD`] with four triangles per leaf, its reinsertion bounded to
/// [`REINSERTION_NODES`] and 64-bit Morton codes above that size (21 bits per axis separate
/// two million cells along each axis: plenty for a mesh that a build must keep cheap).
fn build_params(triangles: usize) -> BvhBuildParams {
    let nodes = (2 * triangles) as f32;
    let base = BvhBuildParams {
        max_prims_per_leaf: LEAF_SIZE,
        ..MESH_BUILD
    };
    if nodes <= REINSERTION_NODES {
        return base;
    }
    BvhBuildParams {
        reinsertion_batch_ratio: REINSERTION_NODES / nodes,
        sort_precision: obvhs::ploc::SortPrecision::U64,
        ..base
    }
}

#[derive(Clone)]
pub struct TriangleMesh {
    /// Vertex positions. Read-only after construction: the BVH was built from them.
    pub positions: Vec<Vec3A>,
    /// Per-vertex normals, same length as `positions`, when the model has them.
    pub normals: Option<Vec<Vec3A>>,
    /// The triangles, in the BVH's leaf order (not the order given to [`TriangleMesh::new`]),
    /// without the ones that were dropped as invalid.
    pub indices: Vec<[u32; 3]>,
    bounds: Bounds,
    /// Corner positions of `indices[i]`.
    corners: Vec<[Vec3A; 3]>,
    /// Leaf `i`'s triangles, one per lane.
    leaves: Vec<Triangle4>,
    bvh: Bvh4,
    dropped: usize,
}

impl std::fmt::Debug for TriangleMesh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TriangleMesh")
            .field("vertices", &self.positions.len())
            .field("triangles", &self.indices.len())
            .field("normals", &self.normals.is_some())
            .field("bounds", &self.bounds)
            .field("bvh_nodes", &self.bvh.node_count())
            .finish()
    }
}

impl TriangleMesh {
    /// A mesh from vertex positions, optional per-vertex normals and triangles, with its BVH.
    ///
    /// Never panics: triangles with an index out of range or a non-finite corner are dropped
    /// (counted by [`TriangleMesh::dropped_triangles`]; file loaders report them as errors
    /// before getting here), and `normals` of the wrong length are ignored. Zero-area
    /// triangles are kept: the intersection test never hits them.
    pub fn new(positions: Vec<Vec3A>, normals: Option<Vec<Vec3A>>, indices: Vec<[u32; 3]>) -> Self {
        debug_assert!(normals.as_ref().is_none_or(|n| n.len() == positions.len()));
        let normals = normals.filter(|n| n.len() == positions.len());
        let corner = |i: u32| positions.get(i as usize).copied().filter(|p| p.is_finite());
        let valid: Vec<([u32; 3], [Vec3A; 3])> = indices
            .iter()
            .filter_map(|&[a, b, c]| Some(([a, b, c], [corner(a)?, corner(b)?, corner(c)?])))
            .collect();
        let dropped = indices.len() - valid.len();
        let bounds = valid
            .iter()
            .flat_map(|(_, c)| c.iter())
            .fold(Bounds::EMPTY, |b, &p| b.include(p));
        let slack = SLACK_PER_DIAGONAL * bounds.diagonal();
        let boxes: Vec<_> = valid
            .iter()
            .map(|(_, c)| {
                let b = Bounds::EMPTY.include(c[0]).include(c[1]).include(c[2]);
                b.padded(slack).to_aabb()
            })
            .collect();
        let bvh = if boxes.is_empty() {
            Bvh4::default()
        } else {
            let params = build_params(boxes.len());
            Bvh4::from_bvh2(&build_bvh2(&boxes, params, &mut Duration::default()))
        };
        // Reorder once so leaf i's lanes are triangles first_i .. first_i + count_i.
        let (indices, corners): (Vec<_>, Vec<_>) =
            bvh.order().iter().map(|&i| valid[i as usize]).unzip();
        let leaves = (0..bvh.leaf_count() as u32)
            .map(|i| {
                let (first, count) = bvh.leaf_range(i);
                debug_assert!(count <= LEAF_SIZE);
                Triangle4::new(&corners[first as usize..(first + count) as usize])
            })
            .collect();
        Self {
            positions,
            normals,
            indices,
            bounds,
            corners,
            leaves,
            bvh,
            dropped,
        }
    }

    /// Bounds of the triangles that were kept (tight, not padded).
    pub fn bounds(&self) -> Bounds {
        self.bounds
    }

    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// How many triangles [`TriangleMesh::new`] dropped (index out of range, corner not finite).
    pub fn dropped_triangles(&self) -> usize {
        self.dropped
    }

    /// The BVH (object space).
    pub fn bvh(&self) -> &Bvh4 {
        &self.bvh
    }

    /// Corner positions of triangle `i` (in [`TriangleMesh::indices`] order).
    pub fn corners(&self, i: usize) -> [Vec3A; 3] {
        self.corners[i]
    }

    /// Closest hit with `ray.t_min < t < ray.t_max`, in object space.
    pub fn intersect(&self, ray: &Ray) -> Option<ObjectHit> {
        self.closest(ray).map(|h| self.surface(ray, h))
    }

    /// Whether any triangle is hit with `ray.t_min < t < ray.t_max` (stops at the first).
    pub fn occluded(&self, ray: &Ray) -> bool {
        let Some(boxes) = BoxRay::new(ray.origin, ray.dir) else {
            return false;
        };
        let mut tris = LazyTriangleRay::new(ray);
        let (t_min, t_max) = (ray.t_min, ray.t_max);
        self.bvh.any(&boxes, t_max, |leaf| {
            let t = tris
                .get()
                .intersect(&self.leaves[leaf as usize], t_min, t_max);
            t.simd_lt(f32x4::splat(f32::INFINITY)).any()
        })
    }

    /// The closest hit's parameter and triangle, without normals.
    pub fn closest(&self, ray: &Ray) -> Option<ShapeHit> {
        let boxes = BoxRay::new(ray.origin, ray.dir)?;
        let mut tris = LazyTriangleRay::new(ray);
        let t_min = ray.t_min;
        let mut found = None;
        self.bvh.closest(&boxes, ray.t_max, |leaf, t_max| {
            let t = tris
                .get()
                .intersect(&self.leaves[leaf as usize], t_min, t_max);
            match nearest_lane(t) {
                Some((t, lane)) => {
                    // Padding lanes copy the leaf's last triangle at a later lane, so the
                    // nearest lane is always a real one.
                    let (first, count) = self.bvh.leaf_range(leaf);
                    found = Some(ShapeHit {
                        t,
                        primitive: first + (lane as u32).min(count - 1),
                    });
                    t
                }
                None => f32::INFINITY,
            }
        });
        found
    }

    /// Normals at a hit found by [`TriangleMesh::closest`] for the same ray.
    pub fn surface(&self, ray: &Ray, hit: ShapeHit) -> ObjectHit {
        let i = hit.primitive as usize;
        let [a, b, c] = self.corners[i];
        let ng = (b - a).cross(c - a);
        // The same test again, for this one triangle, gives the same t and its weights.
        let weights = WatertightRay::new(ray)
            .intersect(a, b, c, f32::NEG_INFINITY, f32::INFINITY)
            .map_or([1.0 / 3.0; 3], |h| h.barycentric);
        let shading_normal = match &self.normals {
            Some(n) => {
                let [ia, ib, ic] = self.indices[i];
                let s = n[ia as usize] * weights[0]
                    + n[ib as usize] * weights[1]
                    + n[ic as usize] * weights[2];
                if s.length_squared() > 0.0 && s.is_finite() {
                    s
                } else {
                    ng
                }
            }
            None => ng,
        };
        ObjectHit {
            t: hit.t,
            geometric_normal: ng,
            shading_normal,
        }
    }
}

/// The ray prepared for four-lane triangle tests, when the traversal first reaches a leaf: a
/// ray that enters the instance's swept box but misses the mesh's boxes (most rays near a
/// moving mesh) never pays the shear's three divisions. [`BoxRay::new`] refuses exactly the
/// rays [`WatertightRay::is_valid`] does (a non-finite origin, a non-finite or zero
/// direction), so only valid rays are prepared.
struct LazyTriangleRay<'a> {
    ray: &'a Ray,
    prepared: Option<WatertightRay4>,
}

impl<'a> LazyTriangleRay<'a> {
    #[inline(always)]
    fn new(ray: &'a Ray) -> Self {
        Self {
            ray,
            prepared: None,
        }
    }

    #[inline(always)]
    fn get(&mut self) -> &WatertightRay4 {
        let ray = self.ray;
        self.prepared.get_or_insert_with(|| {
            let w = WatertightRay::new(ray);
            debug_assert!(w.is_valid());
            WatertightRay4::new(&w)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad() -> TriangleMesh {
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let n = vec![Vec3A::Z; 4];
        TriangleMesh::new(
            p.map(Vec3A::from).to_vec(),
            Some(n),
            vec![[0, 1, 2], [0, 2, 3]],
        )
    }

    #[test]
    fn finds_the_closest_hit_and_its_normals() {
        let m = quad();
        let r = Ray::new(Vec3A::new(0.25, 0.75, 3.0), Vec3A::new(0.0, 0.0, -2.0), 0.0);
        let h = m.intersect(&r).expect("hit");
        assert_eq!(h.t, 1.5);
        assert_eq!(h.geometric_normal.normalize(), Vec3A::Z);
        assert_eq!(h.shading_normal, Vec3A::Z);
        assert!(m.occluded(&r));
        let mut short = r;
        short.t_max = 1.5;
        assert!(m.intersect(&short).is_none() && !m.occluded(&short));
    }

    #[test]
    fn drops_invalid_triangles_and_survives_empty_meshes() {
        let p = vec![Vec3A::ZERO, Vec3A::X, Vec3A::Y, Vec3A::splat(f32::NAN)];
        let m = TriangleMesh::new(p, None, vec![[0, 1, 2], [0, 1, 3], [0, 1, 9]]);
        assert_eq!((m.triangle_count(), m.dropped_triangles()), (1, 2));
        assert!(m.bounds().is_finite());
        let empty = TriangleMesh::new(vec![], None, vec![]);
        let r = Ray::new(Vec3A::Z, -Vec3A::Z, 0.0);
        assert!(empty.intersect(&r).is_none() && !empty.occluded(&r));
        assert!(
            m.intersect(&Ray::new(Vec3A::new(0.2, 0.2, 1.0), -Vec3A::Z, 0.0))
                .is_some()
        );
    }
}
