//! Triangle meshes in object space.
//!
//! Placeholder: brute force over every triangle. To be replaced by an obvhs BVH built once per
//! mesh (motion moves rays, not triangles), with conservative primitive bounds.

use super::{Bounds, ObjectHit, Ray, triangle};
use glam::Vec3A;

#[derive(Clone, Debug)]
pub struct TriangleMesh {
    pub positions: Vec<Vec3A>,
    /// Per-vertex normals, same length as `positions`, when the model has them.
    pub normals: Option<Vec<Vec3A>>,
    pub indices: Vec<[u32; 3]>,
    bounds: Bounds,
}

impl TriangleMesh {
    /// A mesh from vertex positions, optional per-vertex normals and triangles.
    /// Indices must be in range and `normals` as long as `positions` (checked by the caller
    /// that reads user files; here a debug assertion).
    pub fn new(positions: Vec<Vec3A>, normals: Option<Vec<Vec3A>>, indices: Vec<[u32; 3]>) -> Self {
        debug_assert!(
            indices
                .iter()
                .all(|t| t.iter().all(|&i| (i as usize) < positions.len()))
        );
        debug_assert!(normals.as_ref().is_none_or(|n| n.len() == positions.len()));
        let bounds = positions.iter().fold(Bounds::EMPTY, |b, &p| b.include(p));
        Self {
            positions,
            normals,
            indices,
            bounds,
        }
    }

    pub fn bounds(&self) -> Bounds {
        self.bounds
    }

    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    fn corners(&self, i: usize) -> (Vec3A, Vec3A, Vec3A) {
        let [a, b, c] = self.indices[i];
        (
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        )
    }

    pub fn intersect(&self, ray: &Ray) -> Option<ObjectHit> {
        let mut r = *ray;
        let mut best = None;
        for i in 0..self.indices.len() {
            let (a, b, c) = self.corners(i);
            if let Some(t) = triangle::intersect(&r, a, b, c) {
                r.t_max = t;
                best = Some((i, t));
            }
        }
        best.map(|(i, t)| self.hit(i, t, ray))
    }

    pub fn occluded(&self, ray: &Ray) -> bool {
        (0..self.indices.len()).any(|i| {
            let (a, b, c) = self.corners(i);
            triangle::intersect(ray, a, b, c).is_some()
        })
    }

    fn hit(&self, i: usize, t: f32, ray: &Ray) -> ObjectHit {
        let (a, b, c) = self.corners(i);
        let ng = (b - a).cross(c - a);
        let shading_normal = match &self.normals {
            Some(n) => {
                let [ia, ib, ic] = self.indices[i];
                let (w, u, v) = triangle::barycentric(ray.at(t), a, b, c);
                let s = n[ia as usize] * w + n[ib as usize] * u + n[ic as usize] * v;
                if s.length_squared() > 0.0 && s.is_finite() {
                    s
                } else {
                    ng
                }
            }
            None => ng,
        };
        ObjectHit {
            t,
            geometric_normal: ng,
            shading_normal,
        }
    }
}
