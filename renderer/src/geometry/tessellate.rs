//! Closed procedural meshes with shared vertices: for tests (watertightness needs every edge
//! shared by exactly two triangles) and benchmarks (any triangle count).

use super::TriangleMesh;
use glam::Vec3A;
use std::collections::HashMap;

/// A sphere of `radius` from an icosahedron whose faces are split in four `subdivisions`
/// times: `20 * 4^subdivisions` triangles, every edge shared, vertex normals radial.
pub fn icosphere(radius: f32, subdivisions: u32) -> TriangleMesh {
    let phi = (1.0 + 5.0f32.sqrt()) / 2.0;
    let mut positions: Vec<Vec3A> = [
        [-1.0, phi, 0.0],
        [1.0, phi, 0.0],
        [-1.0, -phi, 0.0],
        [1.0, -phi, 0.0],
        [0.0, -1.0, phi],
        [0.0, 1.0, phi],
        [0.0, -1.0, -phi],
        [0.0, 1.0, -phi],
        [phi, 0.0, -1.0],
        [phi, 0.0, 1.0],
        [-phi, 0.0, -1.0],
        [-phi, 0.0, 1.0],
    ]
    .iter()
    .map(|&p| Vec3A::from(p).normalize())
    .collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut mid = |a: u32, b: u32, positions: &mut Vec<Vec3A>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let p = (positions[a as usize] + positions[b as usize]).normalize();
                positions.push(p);
                positions.len() as u32 - 1
            })
        };
        faces = faces
            .iter()
            .flat_map(|&[a, b, c]| {
                let ab = mid(a, b, &mut positions);
                let bc = mid(b, c, &mut positions);
                let ca = mid(c, a, &mut positions);
                [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
            })
            .collect();
    }
    let normals = positions.clone();
    let positions = positions.iter().map(|&p| p * radius).collect();
    TriangleMesh::new(positions, Some(normals), faces)
}

/// A torus around the y axis: ring radius `major`, tube radius `minor`, `nu` segments around the
/// ring and `nv` around the tube (`2 nu nv` triangles), every edge shared.
pub fn torus(major: f32, minor: f32, nu: u32, nv: u32) -> TriangleMesh {
    let (nu, nv) = (nu.max(3), nv.max(3));
    let tau = std::f32::consts::TAU;
    let mut positions = Vec::with_capacity((nu * nv) as usize);
    let mut normals = Vec::with_capacity((nu * nv) as usize);
    for i in 0..nu {
        let (su, cu) = (tau * i as f32 / nu as f32).sin_cos();
        for j in 0..nv {
            let (sv, cv) = (tau * j as f32 / nv as f32).sin_cos();
            let n = Vec3A::new(cu * cv, sv, su * cv);
            positions.push(Vec3A::new(cu * major, 0.0, su * major) + n * minor);
            normals.push(n);
        }
    }
    let id = |i: u32, j: u32| (i % nu) * nv + (j % nv);
    let indices = (0..nu)
        .flat_map(|i| (0..nv).map(move |j| (i, j)))
        .flat_map(|(i, j)| {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            [[a, c, b], [a, d, c]]
        })
        .collect();
    TriangleMesh::new(positions, Some(normals), indices)
}

/// The cube `[-h, h]^3`: 8 shared vertices, 12 triangles facing outwards, no vertex normals.
pub fn cube(h: f32) -> TriangleMesh {
    let positions = (0..8)
        .map(|i| {
            let s = |bit: u32| if i & bit == 0 { -h } else { h };
            Vec3A::new(s(1), s(2), s(4))
        })
        .collect();
    let quads = [
        [0, 2, 3, 1], // z = -h
        [4, 5, 7, 6], // z = +h
        [0, 1, 5, 4], // y = -h
        [2, 6, 7, 3], // y = +h
        [0, 4, 6, 2], // x = -h
        [1, 3, 7, 5], // x = +h
    ];
    let indices = quads
        .iter()
        .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
        .collect();
    TriangleMesh::new(positions, None, indices)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    /// Closed and consistently oriented: each directed edge appears once and its reverse once.
    fn assert_closed(m: &TriangleMesh) {
        let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
        for &[a, b, c] in &m.indices {
            for (p, q) in [(a, b), (b, c), (c, a)] {
                *edges.entry((p, q)).or_default() += 1;
            }
        }
        for (&(p, q), &n) in &edges {
            assert_eq!((n, edges.get(&(q, p))), (1, Some(&1)), "edge {p}-{q}");
        }
    }

    fn outward(m: &TriangleMesh) -> bool {
        (0..m.triangle_count()).all(|i| {
            let [a, b, c] = m.corners(i);
            (b - a).cross(c - a).dot(a + b + c) > 0.0
        })
    }

    #[test]
    fn meshes_are_closed_with_outward_faces_and_the_promised_counts() {
        let s = icosphere(2.0, 2);
        assert_eq!((s.triangle_count(), s.positions.len()), (320, 162));
        assert_closed(&s);
        assert!(outward(&s));
        let t = torus(3.0, 1.0, 12, 8);
        assert_eq!(t.triangle_count(), 192);
        assert_closed(&t);
        let n = t.normals.as_ref().expect("normals");
        assert!(t.indices.iter().enumerate().all(|(i, &[a, b, c])| {
            let [pa, pb, pc] = t.corners(i);
            let avg = n[a as usize] + n[b as usize] + n[c as usize];
            (pb - pa).cross(pc - pa).dot(avg) > 0.0
        }));
        let c = cube(1.0);
        assert_eq!(c.triangle_count(), 12);
        assert_closed(&c);
        assert!(outward(&c));
    }
}
