//! The tracing core against the cases that break ray tracers: rays through shared edges and
//! vertices, large coordinates, degenerate triangles, grazing rays, moving and spinning objects.
//! Random choices come from `renderer::hash` with fixed seeds.

use glam::{Quat, Vec2, Vec3, Vec3A};
use rayon::prelude::*;
use renderer::accel::{Instance, SurfaceHit, World};
use renderer::geometry::tessellate::{cube, icosphere};
use renderer::geometry::{Plane, Ray, Shape, Sphere, TriangleMesh};
use renderer::hash::{hash, unit_f32};
use renderer::motion::{Motion, MotionLayer};
use std::collections::HashSet;
use std::sync::Arc;

#[path = "../../tests/support/test_assets.rs"]
mod test_assets;

const U: f32 = f32::EPSILON / 2.0; // unit roundoff

/// Uniform in [-1, 1) from the hash of `(seed, coords, axis)`.
fn signed(seed: u64, coords: &[u64], axis: u64) -> f32 {
    let mut c = coords.to_vec();
    c.push(axis);
    2.0 * unit_f32(hash(seed, &c)) - 1.0
}

/// A point in the ball of radius `r`, by rejection (deterministic per `coords`).
fn in_ball(seed: u64, coords: &[u64], r: f32) -> Vec3A {
    for attempt in 0.. {
        let mut c = coords.to_vec();
        c.push(attempt);
        let p = Vec3A::new(
            signed(seed, &c, 0),
            signed(seed, &c, 1),
            signed(seed, &c, 2),
        );
        if p.length_squared() <= 1.0 {
            return p * r;
        }
    }
    unreachable!()
}

fn placed(shape: Shape, layers: Vec<MotionLayer>) -> Instance {
    Instance {
        shape,
        motion: Motion { layers },
        material: 0,
    }
}

fn at(location: Vec3, velocity: Vec3) -> MotionLayer {
    MotionLayer {
        location,
        velocity,
        ..MotionLayer::default()
    }
}

/// Every vertex and every edge midpoint of a mesh.
fn vertices_and_edge_midpoints(m: &TriangleMesh) -> Vec<Vec3A> {
    let mut edges = HashSet::new();
    for &[a, b, c] in &m.indices {
        for (p, q) in [(a, b), (b, c), (c, a)] {
            edges.insert((p.min(q), p.max(q)));
        }
    }
    let mids = edges
        .iter()
        .map(|&(p, q)| (m.positions[p as usize] + m.positions[q as usize]) * 0.5);
    m.positions.iter().copied().chain(mids).collect()
}

#[test]
fn a_closed_mesh_seen_from_inside_lets_no_ray_escape() {
    // 10,242 targets x 98 origins = 1,003,716 rays aimed exactly at vertices and edge midpoints.
    let mesh = icosphere(1.0, 4);
    let targets = vertices_and_edge_midpoints(&mesh);
    assert_eq!(targets.len(), 10_242);
    // Per origin batch: (rays, escaped, not occluded); in parallel, the sums do not depend on
    // the order.
    let batch = |k: u64| {
        let (mut escaped, mut unoccluded) = (0usize, 0usize);
        for (i, &target) in targets.iter().enumerate() {
            let origin = in_ball(1, &[k, i as u64], 0.6);
            let ray = Ray::new(origin, target - origin, 0.0);
            match mesh.intersect(&ray) {
                // The polyhedron is convex and the origin inside, so the target (on its
                // surface) is the only exit: t = 1 up to ~10 roundings of O(1) values.
                Some(h) => assert!((h.t - 1.0).abs() < 1e-5, "t = {}", h.t),
                None => escaped += 1,
            }
            if k.is_multiple_of(8) && !mesh.occluded(&ray) {
                unoccluded += 1;
            }
        }
        (targets.len(), escaped, unoccluded)
    };
    let (rays, escaped, unoccluded) = (0..98u64)
        .into_par_iter()
        .map(batch)
        .reduce(|| (0, 0, 0), |a, b| (a.0 + b.0, a.1 + b.1, a.2 + b.2));
    assert!(rays >= 1_000_000);
    assert_eq!((escaped, unoccluded), (0, 0), "of {rays} rays");
}

#[test]
fn a_closed_moving_instance_far_from_the_origin_lets_no_ray_escape() {
    // The same test through the world: the mesh scaled by 50, turned, placed near (5000, 0,
    // -5000) and moving; rays at random shutter times aimed at where the vertices and edge
    // midpoints are at that time. The ray reaches object space rounded, so it passes near, not
    // through, the vertex: still exactly the rays that leak through a non-watertight test.
    let mesh = Arc::new(icosphere(1.0, 3));
    let targets = vertices_and_edge_midpoints(&mesh);
    let layer = MotionLayer {
        scale: Vec3::splat(50.0),
        rotation: Quat::from_rotation_z(0.3),
        ..at(
            Vec3::new(5000.0, 0.0, -5000.0),
            Vec3::new(-1000.0, 0.0, 50.0),
        )
    };
    let shutter = (-0.06, 0.06);
    let world = World::build(vec![placed(Shape::Mesh(mesh), vec![layer])], shutter);
    let motion = &world.instances()[0].motion;
    let escaped: usize = (0..16u64)
        .into_par_iter()
        .map(|k| {
            let mut escaped = 0;
            for (i, &target) in targets.iter().enumerate() {
                let time = shutter.0 + 0.12 * unit_f32(hash(21, &[k, i as u64]));
                let origin = motion.point_at(in_ball(22, &[k, i as u64], 0.6), time);
                let ray = Ray::new(origin, motion.point_at(target, time) - origin, time);
                escaped += usize::from(world.intersect(&ray).is_none() || !world.occluded(&ray));
            }
            escaped
        })
        .sum();
    assert_eq!(escaped, 0, "of {} rays", 16 * targets.len());
}

/// The test above can fail: obvhs's own Möller-Trumbore test, over the same BVH, lets rays
/// through (the reason the renderer does not use it).
#[test]
fn the_non_watertight_test_does_let_rays_escape() {
    let mesh = icosphere(1.0, 4);
    let targets = vertices_and_edge_midpoints(&mesh);
    let tris: Vec<_> = (0..mesh.triangle_count())
        .map(|i| {
            let [v0, v1, v2] = mesh.corners(i);
            obvhs::triangle::Triangle { v0, v1, v2 }
        })
        .collect();
    let bvh = obvhs::bvh2::builder::build_bvh2_from_tris(
        &tris,
        obvhs::BvhBuildParams::medium_build(),
        &mut std::time::Duration::default(),
    );
    let mut escaped = 0;
    for k in 0..10u64 {
        for (i, &target) in targets.iter().enumerate() {
            let origin = in_ball(1, &[k, i as u64], 0.6);
            let ray = obvhs::ray::Ray::new_inf(origin, target - origin);
            let mut hit = obvhs::ray::RayHit::none();
            let found = bvh.ray_traverse(ray, &mut hit, |r, id| {
                tris[bvh.primitive_indices[id] as usize].intersect(r)
            });
            escaped += usize::from(!found);
        }
    }
    assert!(
        escaped > 0,
        "Möller-Trumbore let no ray through: the watertightness test is too easy"
    );
}

#[test]
fn rays_from_far_away_aimed_at_vertices_hit() {
    // Padding covers origins up to ~40 diagonals away (docs/geometry.md); the diagonal of the
    // unit icosphere's box is 2 sqrt(3) = 3.46: test 3, 17 and 40 diagonals.
    let mesh = icosphere(1.0, 3);
    let n = mesh.normals.clone().expect("normals");
    let mut missed = 0;
    for (dist, seed) in [(10.0f32, 2u64), (60.0, 3), (138.0, 4)] {
        for (i, &v) in mesh.positions.iter().enumerate() {
            for k in 0..8u64 {
                let origin = in_ball(seed, &[i as u64, k], 1.0).normalize() * dist;
                // Only vertices facing the origin, so the ray is not tangent to the sphere.
                if n[i].dot((origin - v).normalize()) < 0.3 {
                    continue;
                }
                let ray = Ray::new(origin, v - origin, 0.0);
                missed += usize::from(mesh.intersect(&ray).is_none());
            }
        }
    }
    assert_eq!(missed, 0);
}

/// One convex object per world (so nothing but itself could block its light), lit from the
/// side the camera sees. Returns (rays that hit, shadow rays blocked) for the spawn rule given.
fn self_shadowing(
    inst: Instance,
    aim: Vec3A,
    spread: Vec3A,
    shutter: (f32, f32),
    spawn: impl Fn(&SurfaceHit, Vec3A) -> Vec3A,
    seed: u64,
) -> (usize, usize) {
    let world = World::build(vec![inst], shutter);
    let eye = aim + Vec3A::new(300.0, 200.0, 400.0);
    let (mut hits, mut blocked) = (0, 0);
    for i in 0..4000u64 {
        let time = shutter.0 + (shutter.1 - shutter.0) * unit_f32(hash(seed, &[i, 9]));
        let jitter = Vec3A::new(
            signed(seed, &[i], 0),
            signed(seed, &[i], 1),
            signed(seed, &[i], 2),
        );
        let target = world_aim(&world, aim, time) + jitter * spread;
        let ray = Ray::new(eye, target - eye, time);
        let Some(h) = world.intersect(&ray) else {
            continue;
        };
        assert!(h.point.is_finite() && h.geometric_normal.is_finite());
        hits += 1;
        // The lit side is the camera's side; any direction into that half-space.
        let n = if h.geometric_normal.dot(ray.dir) < 0.0 {
            h.geometric_normal
        } else {
            -h.geometric_normal
        };
        let l = (n + in_ball(seed + 1, &[i], 0.98)).normalize();
        if n.dot(l) <= 1e-3 {
            continue;
        }
        let shadow = Ray::new(spawn(&h, l), l, time);
        if world.occluded(&shadow) || world.intersect(&shadow).is_some() {
            blocked += 1;
        }
    }
    (hits, blocked)
}

/// Where `aim` (the object's location at time 0) has moved by `time`.
fn world_aim(world: &World, aim: Vec3A, time: f32) -> Vec3A {
    let m = &world.instances()[0].motion;
    aim + (m.point_at(Vec3A::ZERO, time) - m.point_at(Vec3A::ZERO, 0.0))
}

fn large_coordinate_cases() -> Vec<(&'static str, Instance, Vec3A, Vec3A)> {
    let mut cases = Vec::new();
    let ico = Arc::new(icosphere(1.0, 3));
    let box_mesh = Arc::new(cube(1.0));
    for base in [Vec3::new(5000.0, 40.0, -5000.0), Vec3::splat(1e4)] {
        for velocity in [Vec3::ZERO, Vec3::new(-1000.0, 0.0, 300.0)] {
            let scaled = |scale: f32| MotionLayer {
                scale: Vec3::splat(scale),
                rotation: Quat::from_rotation_y(0.4),
                ..at(base, velocity)
            };
            let a = Vec3A::from(base);
            cases.push((
                "icosphere",
                placed(Shape::Mesh(ico.clone()), vec![scaled(60.0)]),
                a,
                Vec3A::splat(50.0),
            ));
            cases.push((
                "cube",
                placed(Shape::Mesh(box_mesh.clone()), vec![scaled(40.0)]),
                a,
                Vec3A::splat(39.0),
            ));
            cases.push((
                "sphere",
                placed(
                    Shape::Sphere(Sphere { radius: 70.0 }),
                    vec![at(base, velocity)],
                ),
                a,
                Vec3A::splat(60.0),
            ));
            let rect = Plane {
                half_extent: Some(Vec2::new(500.0, 500.0)),
            };
            cases.push((
                "rectangle",
                placed(Shape::Plane(rect), vec![at(base, velocity)]),
                a,
                Vec3A::new(450.0, 0.0, 450.0),
            ));
            let infinite = Plane { half_extent: None };
            cases.push((
                "infinite plane",
                placed(Shape::Plane(infinite), vec![at(base, velocity)]),
                a,
                Vec3A::new(900.0, 0.0, 900.0),
            ));
        }
    }
    cases
}

#[test]
fn shadow_rays_never_hit_their_own_surface_at_large_coordinates() {
    // The thesis's plane scene flies from x = 12500 at t = -12.5 s; shutter of one frame there.
    let shutter = (-12.5, -12.5 + 0.12);
    for (seed, (name, inst, aim, spread)) in large_coordinate_cases().into_iter().enumerate() {
        let moving = !inst.motion.is_static();
        let (hits, blocked) = self_shadowing(
            inst,
            aim,
            spread,
            shutter,
            |h, l| h.spawn_point(l),
            seed as u64,
        );
        assert!(hits > 2000, "{name} at {aim}: only {hits} hits");
        assert_eq!(
            blocked, 0,
            "{name} at {aim} (moving: {moving}): {blocked} of {hits} shadow rays hit their own surface"
        );
    }
}

/// The test above can fail: without an offset, shadow rays do hit their own surface there.
#[test]
fn without_an_offset_shadow_rays_hit_their_own_surface() {
    let (name, inst, aim, spread) = large_coordinate_cases().swap_remove(0);
    let (hits, blocked) = self_shadowing(inst, aim, spread, (0.0, 0.0), |h, _| h.point, 99);
    assert!(
        blocked * 20 > hits,
        "{name}: only {blocked} of {hits} blocked without offset"
    );
}

/// t of the nearer root of |o + t d - c|^2 = r^2, in f64.
fn sphere_t(o: Vec3A, d: Vec3A, c: Vec3A, r: f32) -> Option<f64> {
    let f = |v: Vec3A| [v.x as f64, v.y as f64, v.z as f64];
    let (o, d, c) = (f(o), f(d), f(c));
    let oc: Vec<f64> = (0..3).map(|i| o[i] - c[i]).collect();
    let a: f64 = d.iter().map(|x| x * x).sum();
    let b: f64 = (0..3).map(|i| oc[i] * d[i]).sum();
    let cc: f64 = oc.iter().map(|x| x * x).sum::<f64>() - (r as f64).powi(2);
    let disc = b * b - a * cc;
    (disc >= 0.0).then(|| (-b - disc.sqrt()) / a)
}

/// Checks hits against the closed form for a sphere whose centre is `centre(t)`.
/// Tolerance: the world ray is mapped to object space (~4 roundings of magnitude |o| + |c|),
/// then the roots are taken (~6 more of magnitude ~t|d|); rays aim within 0.6 r of the centre,
/// so the root's sensitivity to the origin is at most 1/sqrt(1 - 0.36) = 1.25. 64 u of the
/// magnitudes bounds that with room to spare.
fn check_sphere_hits(
    world: &World,
    radius: f32,
    centre: impl Fn(f32) -> Vec3A,
    times: &[f32],
    seed: u64,
) {
    let eye = Vec3A::new(3.0, -2.0, 40.0);
    for (k, &time) in times.iter().enumerate() {
        for i in 0..50u64 {
            let c = centre(time);
            let target = c + in_ball(seed, &[k as u64, i], 0.6 * radius);
            let d = (target - eye).normalize();
            let ray = Ray::new(eye, d, time);
            let h = world.intersect(&ray).expect("aimed at the sphere");
            let exact = sphere_t(eye, d, c, radius).expect("closed form hits");
            let tol = 64.0 * U as f64 * (eye.length() + c.length() + radius) as f64;
            assert!(
                (h.t as f64 - exact).abs() <= tol,
                "t = {}, exact {exact}, at time {time}",
                h.t
            );
            let outward = (h.point - c).normalize();
            assert!(h.geometric_normal.dot(outward) > 1.0 - 1e-5);
        }
    }
}

#[test]
fn a_sphere_moving_at_constant_velocity_is_hit_where_its_pose_says() {
    let (c0, v) = (Vec3::new(5.0, 1.0, -3.0), Vec3::new(40.0, 0.0, 10.0));
    let shutter = (0.0, 0.5);
    let world = World::build(
        vec![placed(
            Shape::Sphere(Sphere { radius: 2.0 }),
            vec![at(c0, v)],
        )],
        shutter,
    );
    let centre = |t: f32| Vec3A::from(c0 + v * t);
    check_sphere_hits(&world, 2.0, centre, &[0.0, 0.1, 0.25, 0.4999, 0.5], 11);
    // Aimed where the sphere was at t = 0, a ray at t = 0.5 misses: it moved 20 units.
    let eye = Vec3A::new(3.0, -2.0, 40.0);
    let late = Ray::new(eye, centre(0.0) - eye, 0.5);
    assert!(world.intersect(&late).is_none() && !world.occluded(&late));
    // Times outside the shutter are still traced right (every instance tested).
    check_sphere_hits(&world, 2.0, centre, &[-1.0, 3.0], 12);
}

#[test]
fn spinning_objects_are_hit_where_their_pose_says() {
    // A sphere orbiting the y axis: group layer spins, child layer offsets by 6 along x.
    let spin = MotionLayer {
        location: Vec3::new(0.0, 2.0, 0.0),
        angular_velocity: Vec3::new(0.0, 1.5, 0.0),
        ..MotionLayer::default()
    };
    let offset = at(Vec3::new(6.0, 0.0, 0.0), Vec3::ZERO);
    let shutter = (-0.2, 0.6);
    let world = World::build(
        vec![placed(
            Shape::Sphere(Sphere { radius: 1.5 }),
            vec![spin, offset],
        )],
        shutter,
    );
    let centre = |t: f32| {
        Vec3A::new(0.0, 2.0, 0.0) + Quat::from_rotation_y(1.5 * t) * Vec3A::new(6.0, 0.0, 0.0)
    };
    check_sphere_hits(&world, 1.5, centre, &[-0.2, 0.0, 0.3, 0.6], 13);

    // A cube of half-size 1 spinning about y: a ray down -z meets the face turned by theta at
    // z = 1 / cos(theta), with normal (sin theta, 0, cos theta).
    let w = 0.8f32;
    let spinning = MotionLayer {
        angular_velocity: Vec3::new(0.0, w, 0.0),
        ..MotionLayer::default()
    };
    let world = World::build(
        vec![placed(Shape::Mesh(Arc::new(cube(1.0))), vec![spinning])],
        (-0.7, 0.7),
    );
    for time in [-0.7f32, -0.3, 0.0, 0.2, 0.7] {
        let theta = w * time;
        let ray = Ray::new(Vec3A::new(0.05, 0.3, 10.0), -Vec3A::Z, time);
        let h = world.intersect(&ray).expect("hit");
        // The face plane is n.x = 1, so z = (1 - 0.05 sin)/cos; ~8 roundings of magnitude 10.
        let exact = 10.0 - (1.0 - 0.05 * theta.sin() as f64) / theta.cos() as f64;
        assert!(
            (h.t as f64 - exact).abs() < 32.0 * U as f64 * 10.0,
            "t = {}, exact {exact}",
            h.t
        );
        let n = Vec3A::new(theta.sin(), 0.0, theta.cos());
        assert!(h.geometric_normal.dot(n) > 1.0 - 1e-6);
    }
}

fn scene(velocity: Vec3, extra: bool) -> Vec<Instance> {
    let mut v = vec![
        placed(
            Shape::Mesh(Arc::new(icosphere(1.0, 3))),
            vec![MotionLayer {
                scale: Vec3::splat(30.0),
                rotation: Quat::from_rotation_x(0.3),
                ..at(Vec3::new(5000.0, 30.0, -200.0), velocity)
            }],
        ),
        placed(
            Shape::Sphere(Sphere { radius: 20.0 }),
            vec![at(Vec3::new(5060.0, 20.0, -180.0), velocity)],
        ),
        placed(
            Shape::Plane(Plane { half_extent: None }),
            vec![at(Vec3::ZERO, Vec3::ZERO)],
        ),
    ];
    if extra {
        // Far away and moving: the world now has a moving part and another top level.
        v.push(placed(
            Shape::Sphere(Sphere { radius: 1.0 }),
            vec![at(Vec3::splat(-1e4), Vec3::X * 100.0)],
        ));
    }
    v
}

#[test]
fn zero_velocity_gives_bit_identical_hits_to_no_motion() {
    let shutter = (2.0, 2.12);
    let still = World::build(scene(Vec3::ZERO, false), shutter);
    let zero = World::build(scene(Vec3::new(0.0, -0.0, 0.0), true), shutter);
    assert!(still.is_static() && !zero.is_static());
    let eye = Vec3A::new(5030.0, 80.0, 0.0);
    let mut hits = 0;
    for i in 0..20_000u64 {
        let time = 2.0 + 0.12 * unit_f32(hash(5, &[i]));
        let target = Vec3A::new(5030.0, 20.0, -190.0) + in_ball(6, &[i], 60.0);
        let ray = Ray::new(eye, target - eye, time);
        let (a, b) = (still.intersect(&ray), zero.intersect(&ray));
        assert_eq!(a, b);
        hits += usize::from(a.is_some());
        if let Some(h) = a {
            let s = Ray::new(h.spawn_point(Vec3A::Y), Vec3A::Y, time);
            assert_eq!(still.occluded(&s), zero.occluded(&s));
        }
    }
    assert!(hits > 15_000);
}

#[test]
fn degenerate_triangles_and_grazing_rays_give_no_nan_and_no_false_hits() {
    // A unit quad in z = 0, plus zero-area triangles: a point, a sliver on the quad's diagonal,
    // and a repeated vertex.
    let p = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 0.5, 0.0],
    ];
    let positions: Vec<Vec3A> = p.iter().map(|&v| Vec3A::from(v)).collect();
    let indices = vec![[0, 1, 2], [0, 2, 3], [4, 4, 4], [0, 4, 2], [1, 1, 3]];
    let normals = Some(vec![Vec3A::ZERO; 5]); // zero normals: shading falls back to geometric
    let mesh = Arc::new(TriangleMesh::new(positions, normals, indices));
    let world = World::build(
        vec![
            placed(
                Shape::Mesh(mesh),
                vec![at(Vec3::new(1e4, 1e4, 1e4), Vec3::ZERO)],
            ),
            placed(Shape::Plane(Plane { half_extent: None }), vec![]),
        ],
        (0.0, 1.0),
    );
    let base = Vec3A::splat(1e4);
    for i in 0..2000u64 {
        let s = |a| 0.5 + 0.7 * signed(7, &[i], a);
        // In the quad's plane, from outside it, through its interior: no hit.
        let o = base + Vec3A::new(-3.0, s(0), 0.0);
        let mut grazing = Ray::new(o, base + Vec3A::new(s(1), s(2), 0.0) - o, 0.5);
        grazing.t_max = 100.0; // short of the ground plane, 1e4 below
        assert_eq!(world.intersect(&grazing).map(|h| h.instance), None);
        // In the ground plane's own plane: no hit either.
        let flat = Ray::new(Vec3A::new(s(0), 0.0, s(1)), Vec3A::new(1.0, 0.0, s(2)), 0.5);
        assert!(world.intersect(&flat).is_none() && !world.occluded(&flat));
        // Nearly grazing and down onto the quad: finite, unit normals.
        let d = Vec3A::new(1.0, 0.1 * s(3), -(2.0f32).powi(-((i % 20) as i32)));
        let o = base + Vec3A::new(s(0), s(1), 0.0) - d * 0.5;
        if let Some(h) = world.intersect(&Ray::new(o, d, 0.5)) {
            assert!(h.t.is_finite() && h.point.is_finite());
            assert!((h.geometric_normal.length() - 1.0).abs() < 1e-5);
            assert!((h.shading_normal.length() - 1.0).abs() < 1e-5);
        }
    }
    // Degenerate rays.
    for d in [
        Vec3A::ZERO,
        Vec3A::new(f32::NAN, 1.0, 0.0),
        Vec3A::new(0.0, f32::INFINITY, 0.0),
    ] {
        let r = Ray::new(base + Vec3A::Z, d, 0.5);
        assert!(world.intersect(&r).is_none() && !world.occluded(&r));
    }
}

#[test]
fn real_models_give_finite_hits() {
    let Some(dir) = test_assets::folder() else {
        return;
    };
    for name in ["bunny-low.obj", "duck.obj", "teapot.obj"] {
        let mesh = TriangleMesh::from_obj(&dir.join(name)).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            mesh.triangle_count() > 500 && mesh.dropped_triangles() == 0,
            "{name}"
        );
        let b = mesh.bounds();
        let (centre, size) = ((b.min + b.max) * 0.5, b.diagonal());
        let world = World::build(
            vec![placed(Shape::Mesh(Arc::new(mesh)), vec![])],
            (0.0, 0.0),
        );
        let mut hits = 0;
        for i in 0..5000u64 {
            let eye = centre + in_ball(8, &[i], 1.0).normalize_or(Vec3A::X) * size * 2.0;
            let target = centre + in_ball(9, &[i], 0.3 * size);
            let Some(h) = world.intersect(&Ray::new(eye, target - eye, 0.0)) else {
                continue;
            };
            hits += 1;
            assert!(h.t.is_finite() && h.point.is_finite(), "{name}");
            assert!((h.geometric_normal.length() - 1.0).abs() < 1e-5, "{name}");
            assert!((h.shading_normal.length() - 1.0).abs() < 1e-5, "{name}");
        }
        assert!(hits > 1000, "{name}: {hits} hits");
    }
}
