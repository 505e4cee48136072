//! The stand-in for the thesis's `models/B-727-200.obj` (Figure 13): a procedural trijet with
//! a Boeing 727-200's outline — low swept wing, three engines at the rear (two in pods on the
//! fuselage's sides, one in the tail fed by an intake ahead of the fin) and a T-tail — at the
//! 727-200's published size: 46.69 m long, 32.92 m span, 10.36 m high (the height is the
//! aircraft standing on its gear; the gear is not modelled, so the mesh's height is the fuselage
//! bottom to the tailplane's top).
//!
//! The aircraft is built in metres ([`airliner`]); the committed OBJ ([`b727_obj`]) is in the
//! units Figure 13's `scale 13` needs for a scene measured in feet (one model unit = 13 ft), with
//! the fuselage's axis at model height 350 / 13, so that at `location 0 0 420` it flies at
//! y = 350, the height the camera looks at (`scenes/README.md` explains both choices). Nose
//! towards -x (the direction it flies in), up +y, wings along z.

use glam::Vec3;
use std::f32::consts::TAU;
use std::fmt::Write;

/// The 727-200's overall length, wing span and height, metres.
pub const LENGTH_M: f32 = 46.69;
pub const SPAN_M: f32 = 32.92;
pub const HEIGHT_M: f32 = 10.36;

/// Feet per metre (international foot, 0.3048 m).
pub const FEET_PER_METRE: f32 = 1.0 / 0.3048;
/// Figure 13's `scale` for the model.
pub const FIGURE_13_SCALE: f32 = 13.0;
/// Height of the fuselage's axis in model units: world y = 350 at `scale 13`.
pub const AXIS_HEIGHT_MODEL: f32 = 350.0 / FIGURE_13_SCALE;

/// Fuselage radius (the 727's fuselage is 3.76 m across).
const FUSELAGE_R: f32 = 1.88;
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
    const R: f32 = FUSELAGE_R;
    if s < 0.11 {
        // Elliptic nose, its tip a little below the axis.
        let a = s / 0.11;
        (R * (1.0 - (1.0 - a) * (1.0 - a)).sqrt(), -0.3 * (1.0 - a))
    } else if s < 0.74 {
        (R, 0.0)
    } else {
        // Tail cone rising to the centre engine's exhaust under the fin.
        let a = (s - 0.74) / 0.26;
        (R * (1.0 - 0.6 * a), 0.9 * a * a)
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

/// A nacelle's profile: a rounded tube of radius `r` whose axis is at height `y`.
fn nacelle(r: f32, y: f32) -> impl Fn(f32) -> (f32, f32) {
    move |s: f32| {
        (
            r * (1.0 - (2.0 * s - 1.0).powi(6)).max(0.0).sqrt().max(0.05),
            y,
        )
    }
}

/// The airliner in metres, nose at x = -L/2, fuselage axis on y = 0. `segments` sets the
/// roundness of fuselage and engines (24 is smooth at stimulus sizes).
pub fn airliner(segments: usize) -> Mesh {
    let segments = segments.max(3);
    let half = 0.5 * LENGTH_M;
    let mut m = Mesh::default();
    lathe(&mut m, -half, half, 48, segments, fuselage_section, 0.0);
    for side in [-1.0f32, 1.0] {
        // Main wing: low on the fuselage, leading edge swept 35° (32° at quarter chord),
        // 3° dihedral, tip at half the span.
        let reach = 0.5 * SPAN_M - 1.7;
        panel(
            &mut m,
            Panel {
                root: Vec3::new(-6.0, -1.0, side * 1.7),
                span: Vec3::new(0.0, reach * 3f32.to_radians().tan(), side * reach),
                sweep: reach * 35f32.to_radians().tan(),
                root_chord: 8.5,
                tip_chord: 2.0,
                thickness: 0.5,
                normal: Vec3::Y,
            },
        );
        // Side engines in pods on the rear fuselage, each on a short stub.
        lathe(
            &mut m,
            10.5,
            17.0,
            8,
            segments,
            nacelle(0.95, 0.8),
            side * 3.15,
        );
        panel(
            &mut m,
            Panel {
                root: Vec3::new(12.0, 0.8, side * 1.2),
                span: Vec3::new(0.0, 0.0, side * 1.2),
                sweep: 0.6,
                root_chord: 3.4,
                tip_chord: 2.8,
                thickness: 0.35,
                normal: Vec3::Y,
            },
        );
        // Tailplane on top of the fin (the T-tail), 10.9 m across.
        panel(
            &mut m,
            Panel {
                root: Vec3::new(18.6, 7.25, 0.0),
                span: Vec3::new(0.0, 0.0, side * 5.45),
                sweep: 3.0,
                root_chord: 3.3,
                tip_chord: 1.4,
                thickness: 0.3,
                normal: Vec3::Y,
            },
        );
    }
    // Centre engine: its intake on the fuselage's back ahead of the fin (the exhaust is the
    // tail cone's end).
    lathe(
        &mut m,
        10.0,
        14.5,
        8,
        segments,
        nacelle(0.8, FUSELAGE_R + 0.35),
        0.0,
    );
    // Fin, leading edge swept back over 7.5 m, carrying the tailplane at its tip.
    panel(
        &mut m,
        Panel {
            root: Vec3::new(11.5, 1.4, 0.0),
            span: Vec3::new(0.0, 5.85, 0.0),
            sweep: 7.3,
            root_chord: 8.0,
            tip_chord: 3.3,
            thickness: 0.35,
            normal: Vec3::Z,
        },
    );
    m
}

/// The mesh in the units Figure 13 needs: metres to feet, divided by the scale 13, the
/// fuselage's axis raised to [`AXIS_HEIGHT_MODEL`].
pub fn in_figure_13_units(mut m: Mesh) -> Mesh {
    let k = FEET_PER_METRE / FIGURE_13_SCALE;
    for p in &mut m.positions {
        *p = *p * k + Vec3::Y * AXIS_HEIGHT_MODEL;
    }
    m
}

/// The committed `scenes/thesis/models/B-727-200.obj`.
pub fn b727_obj() -> String {
    in_figure_13_units(airliner(24)).to_obj(
        "B-727-200.obj: stand-in for the thesis's Boeing 727-200 model, generated by blurlab \
         (renderer::procedural::airliner); regenerate with `render assets`.\n\
         A trijet with a 727-200's outline and size (46.69 m long, 32.92 m span, 10.36 m high \
         on its gear).\n\
         Units: 13 ft per model unit (Figure 13 scales it by 13 into a scene in feet); \
         fuselage axis at y = 350/13.\n\
         Nose towards -x, up +y, wings along z. Licence: same as blurlab.",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bounds(m: &Mesh) -> (Vec3, Vec3) {
        let lo = m
            .positions
            .iter()
            .fold(Vec3::splat(f32::MAX), |a, &p| a.min(p));
        let hi = m
            .positions
            .iter()
            .fold(Vec3::splat(f32::MIN), |a, &p| a.max(p));
        (lo, hi)
    }

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
    fn size_is_a_727_200s() {
        // Length and span as published; the height as published less the gear (the
        // fuselage's bottom stands about 1.1 m above the ground on a 727).
        let (lo, hi) = bounds(&airliner(24));
        let size = hi - lo;
        assert!(
            (size.x - LENGTH_M).abs() < 0.01 * LENGTH_M,
            "length {}",
            size.x
        );
        assert!((size.z - SPAN_M).abs() < 0.01 * SPAN_M, "span {}", size.z);
        let gear = HEIGHT_M - size.y;
        assert!(gear > 0.8 && gear < 1.4, "height {}", size.y);
        // Symmetric about the fuselage's vertical plane.
        assert!((lo.z + hi.z).abs() < 1e-3);
    }

    #[test]
    fn figure_13_units_give_feet_at_scale_13_with_the_axis_at_350() {
        let m = in_figure_13_units(airliner(24));
        let (lo, hi) = bounds(&m);
        let feet = (hi.x - lo.x) * FIGURE_13_SCALE;
        // 153 ft 2 in.
        assert!((feet - 153.17).abs() < 0.02 * 153.17, "{feet} ft");
        let nose = m
            .positions
            .iter()
            .copied()
            .min_by(|a, b| a.x.total_cmp(&b.x))
            .unwrap();
        // The nose sits just below the axis (the elliptic nose droops 0.3 m).
        let axis_ft = (nose.y * FIGURE_13_SCALE) + 0.3 * FEET_PER_METRE;
        assert!((axis_ft - 350.0).abs() < 0.1, "{axis_ft}");
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
        assert_eq!(b727_obj(), b727_obj());
        assert!(b727_obj().starts_with("# B-727-200.obj"));
    }
}
