//! A procedural airliner-like mesh (fuselage, swept wings, tailplane, fin, two engines), the
//! stand-in for the thesis's Boeing 727 model. Units are metres: about 40 m long and 36 m
//! across the wings, nose towards -x (the direction it flies in the `plane` scene), up +y,
//! wings along z, origin at the fuselage's centre.

use glam::Vec3;
use std::f32::consts::TAU;
use std::fmt::Write;

/// A triangle mesh with one normal per vertex.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    fn vertex(&mut self, p: Vec3, n: Vec3) -> u32 {
        self.positions.push(p);
        self.normals.push(n.normalize_or(Vec3::Y));
        (self.positions.len() - 1) as u32
    }

    /// A flat-shaded convex polygon (corners in order) whose normal points away from `inside`.
    fn flat_polygon(&mut self, corners: &[Vec3], inside: Vec3) {
        let mut n = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
        let outward = n.dot(corners[0] - inside) >= 0.0;
        if !outward {
            n = -n;
        }
        let ids: Vec<u32> = corners.iter().map(|&c| self.vertex(c, n)).collect();
        for i in 1..ids.len() - 1 {
            let tri = [ids[0], ids[i], ids[i + 1]];
            self.triangles.push(if outward {
                tri
            } else {
                [tri[0], tri[2], tri[1]]
            });
        }
    }

    /// The mesh as Wavefront OBJ text (`v`, `vn`, `f v//vn`), with fixed precision so the
    /// output is byte-stable.
    pub fn to_obj(&self, comment: &str) -> String {
        let mut s = String::new();
        for line in comment.lines() {
            let _ = writeln!(s, "# {line}");
        }
        for p in &self.positions {
            let _ = writeln!(s, "v {:.4} {:.4} {:.4}", p.x, p.y, p.z);
        }
        for n in &self.normals {
            let _ = writeln!(s, "vn {:.4} {:.4} {:.4}", n.x, n.y, n.z);
        }
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| i + 1);
            let _ = writeln!(s, "f {a}//{a} {b}//{b} {c}//{c}");
        }
        s
    }
}

/// Radius and centre height of the fuselage at a fraction `s` in [0, 1] from nose to tail.
fn fuselage_section(s: f32) -> (f32, f32) {
    const R: f32 = 1.9;
    if s < 0.12 {
        // Elliptic nose.
        let a = s / 0.12;
        (R * (1.0 - (1.0 - a) * (1.0 - a)).sqrt(), -0.3 * (1.0 - a))
    } else if s < 0.72 {
        (R, 0.0)
    } else {
        // Tail cone, tapering and rising towards the fin.
        let a = (s - 0.72) / 0.28;
        (R * (1.0 - 0.8 * a), 1.2 * a * a)
    }
}

/// A surface of revolution around the x axis from `x0` to `x1` with a radius/centre profile;
/// the ends close on single apex vertices.
fn lathe(
    mesh: &mut Mesh,
    x0: f32,
    x1: f32,
    rings: usize,
    segments: usize,
    profile: impl Fn(f32) -> (f32, f32),
    z_offset: f32,
) {
    let base = mesh.positions.len() as u32;
    let point = |s: f32, k: usize| -> (Vec3, Vec3) {
        let (r, yc) = profile(s);
        let a = TAU * k as f32 / segments as f32;
        let dir = Vec3::new(0.0, a.cos(), a.sin());
        let x = x0 + (x1 - x0) * s;
        (Vec3::new(x, yc, z_offset) + r * dir, dir)
    };
    // Inner rings only; s = 0 and s = 1 are the apexes.
    for i in 1..rings {
        let s = i as f32 / rings as f32;
        // Slope of the radius gives the normal its axial tilt.
        let h = 0.5 / rings as f32;
        let dr = (profile(s + h).0 - profile(s - h).0) / (2.0 * h * (x1 - x0));
        for k in 0..segments {
            let (p, dir) = point(s, k);
            mesh.vertex(p, dir - Vec3::X * dr);
        }
    }
    let ring = |i: usize, k: usize| base + ((i - 1) * segments + k % segments) as u32;
    for i in 1..rings - 1 {
        for k in 0..segments {
            let (a, b, c, d) = (
                ring(i, k),
                ring(i, k + 1),
                ring(i + 1, k),
                ring(i + 1, k + 1),
            );
            mesh.triangles.push([a, b, c]);
            mesh.triangles.push([b, d, c]);
        }
    }
    let (_, y0) = profile(0.0);
    let (_, y1) = profile(1.0);
    let nose = mesh.vertex(Vec3::new(x0, y0, z_offset), -Vec3::X);
    let tail = mesh.vertex(Vec3::new(x1, y1, z_offset), Vec3::X);
    for k in 0..segments {
        mesh.triangles.push([nose, ring(1, k + 1), ring(1, k)]);
        mesh.triangles
            .push([tail, ring(rings - 1, k), ring(rings - 1, k + 1)]);
    }
}

/// A tapered, swept panel (wing, tailplane, fin): a flat-shaded hexahedron from a root section
/// at `root` (leading edge) with `root_chord` along +x, to a tip at `root + span` moved back by
/// `sweep` with `tip_chord`, thickened by `thickness` along `normal`.
struct Panel {
    root: Vec3,
    span: Vec3,
    sweep: f32,
    root_chord: f32,
    tip_chord: f32,
    thickness: f32,
    normal: Vec3,
}

fn panel(mesh: &mut Mesh, p: Panel) {
    let Panel {
        root,
        span,
        sweep,
        root_chord,
        tip_chord,
        thickness,
        normal,
    } = p;
    let h = 0.5 * thickness * normal;
    let tip = root + span + Vec3::X * sweep;
    let corners = [
        root + h,
        root + Vec3::X * root_chord + h,
        tip + Vec3::X * tip_chord + h,
        tip + h,
        root - h,
        root + Vec3::X * root_chord - h,
        tip + Vec3::X * tip_chord - h,
        tip - h,
    ];
    let centre = corners.iter().copied().sum::<Vec3>() / 8.0;
    let c = |i: usize| corners[i];
    for quad in [
        [0, 1, 2, 3],
        [4, 7, 6, 5],
        [0, 4, 5, 1],
        [1, 5, 6, 2],
        [2, 6, 7, 3],
        [3, 7, 4, 0],
    ] {
        mesh.flat_polygon(&quad.map(c), centre);
    }
}

/// The airliner. `segments` sets the roundness of fuselage and engines (24 is smooth at
/// stimulus sizes).
pub fn airliner(segments: usize) -> Mesh {
    let segments = segments.max(3);
    let mut m = Mesh::default();
    lathe(&mut m, -20.0, 20.0, 48, segments, fuselage_section, 0.0);
    for side in [-1.0f32, 1.0] {
        // Main wing: low on the fuselage, swept back, slight dihedral.
        panel(
            &mut m,
            Panel {
                root: Vec3::new(-4.0, -0.9, side * 1.6),
                span: Vec3::new(0.0, 1.0, side * 16.5),
                sweep: 9.0,
                root_chord: 7.5,
                tip_chord: 2.2,
                thickness: 0.45,
                normal: Vec3::new(0.0, 1.0, -side * 0.06).normalize(),
            },
        );
        // Tailplane.
        panel(
            &mut m,
            Panel {
                root: Vec3::new(14.5, 0.9, side * 0.5),
                span: Vec3::new(0.0, 0.4, side * 6.0),
                sweep: 3.5,
                root_chord: 3.5,
                tip_chord: 1.3,
                thickness: 0.25,
                normal: Vec3::Y,
            },
        );
        // Engine nacelle under the wing.
        let nacelle = |s: f32| {
            let r = 1.05 * (1.0 - (2.0 * s - 1.0).powi(6)).max(0.0).sqrt().max(0.05);
            (r, -2.0)
        };
        lathe(&mut m, -5.5, -0.5, 8, segments, nacelle, side * 6.5);
    }
    // Fin.
    panel(
        &mut m,
        Panel {
            root: Vec3::new(13.0, 1.3, 0.0),
            span: Vec3::new(0.0, 7.0, 0.0),
            sweep: 4.5,
            root_chord: 5.5,
            tip_chord: 2.0,
            thickness: 0.3,
            normal: Vec3::Z,
        },
    );
    m
}

/// The committed `scenes/models/airliner.obj`.
pub fn airliner_obj() -> String {
    airliner(24).to_obj(
        "airliner.obj: procedural airliner-like model generated by blurlab \
         (renderer::procedural::airliner); regenerate with `render assets`.\n\
         Units: metres. Nose towards -x, up +y, wings along z. Licence: same as blurlab.",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mesh_is_finite_and_indices_are_valid() {
        let m = airliner(12);
        assert!(m.triangles.len() > 500);
        assert!(m.positions.iter().all(|p| p.is_finite()));
        assert!(m.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-4));
        let n = m.positions.len() as u32;
        assert!(m.triangles.iter().flatten().all(|&i| i < n));
    }

    #[test]
    fn proportions_are_an_airliners() {
        let m = airliner(12);
        let lo = m
            .positions
            .iter()
            .fold(Vec3::splat(f32::MAX), |a, &p| a.min(p));
        let hi = m
            .positions
            .iter()
            .fold(Vec3::splat(f32::MIN), |a, &p| a.max(p));
        let size = hi - lo;
        assert!((size.x - 40.0).abs() < 0.5, "length {}", size.x);
        assert!(size.z > 30.0 && size.z < 40.0, "span {}", size.z);
        assert!(size.y > 8.0 && size.y < 12.0, "height {}", size.y);
    }

    #[test]
    fn closed_surfaces_have_outward_normals() {
        // Every triangle's winding agrees with its vertex normals, so the renderer's
        // geometric normal and shading normal never point to opposite sides.
        let m = airliner(12);
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            let g = (b - a).cross(c - a);
            if g.length() < 1e-6 {
                continue;
            }
            let n: Vec3 = t.iter().map(|&i| m.normals[i as usize]).sum();
            assert!(g.dot(n) > 0.0, "triangle {t:?} winds against its normals");
        }
    }

    #[test]
    fn obj_text_is_stable() {
        assert_eq!(airliner_obj(), airliner_obj());
        assert!(airliner_obj().starts_with("# airliner.obj"));
    }
}
