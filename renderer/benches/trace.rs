//! Primary + shadow rays per second through the tracing core, next to bare obvhs on the same
//! rays (its own triangle test, one BVH in world space, no instancing, no motion).
//!
//! Workload: [`renderer::workload`] (a 200k-triangle torus above a ground; 256x256 jittered
//! pinhole rays, one shadow ray toward a directional light per hit), traced through the
//! 4-wide BVH with SIMD box and triangle tests (`renderer::bvh`). Run:
//! `cargo bench -p renderer --bench trace`
//! (results: `docs/benchmarks/renderer-trace.md`).
//!
//! Two groups: `trace` in wall time (what a user waits), `trace_cpu` in CPU time of all the
//! process's threads (what the work costs; on the shared 2-core machine wall time depends on
//! what everybody else runs). Rays per CPU-second times the thread count is the rate the cores
//! would give if nobody else used them.

use criterion::measurement::{Measurement, ValueFormatter};
use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};
use glam::{Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::bvh2::{Bvh2, builder::build_bvh2_from_tris};
use obvhs::cwbvh::{CwBvh, builder::build_cwbvh_from_tris};
use obvhs::ray::RayHit;
use obvhs::triangle::Triangle;
use rayon::prelude::*;
use renderer::accel::World;
use renderer::geometry::TriangleMesh;
use renderer::workload::{SIZE, TraceWorkload};
use std::hint::black_box;
use std::time::Duration;

struct Setup {
    w: TraceWorkload,
    light: Vec3A,
    /// World-space triangles of the torus and the ground, for bare obvhs.
    triangles: Vec<Triangle>,
}

fn setup() -> Setup {
    let w = TraceWorkload::new();
    let triangles = w
        .world_triangles()
        .into_iter()
        .map(|[v0, v1, v2]| Triangle { v0, v1, v2 })
        .collect();
    Setup {
        light: w.light,
        w,
        triangles,
    }
}

fn world(s: &Setup, velocity: Vec3) -> World {
    s.w.world(velocity, Vec3::ZERO)
}

fn trace_frame(s: &Setup, w: &World) -> (u64, u64) {
    (0..SIZE)
        .into_par_iter()
        .map(|y| s.w.trace_row(w, y))
        .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1))
}

/// The same rays through bare obvhs: one BVH over world-space triangles, Möller-Trumbore,
/// shadow ray from the hit point pushed along the triangle normal by the same rule.
fn bare_row<B: BareBvh>(s: &Setup, bvh: &B, y: u32) -> (u64, u64) {
    let (mut rays, mut lit) = (0, 0);
    for x in 0..SIZE {
        let r = s.w.camera_ray(x, y);
        let ray = obvhs::ray::Ray::new_inf(r.origin, r.dir);
        rays += 1;
        let mut hit = RayHit::none();
        if bvh.closest(ray, &mut hit, &s.triangles) {
            rays += 1;
            let tri = &s.triangles[bvh.original(hit.primitive_id)];
            let p = r.at(hit.t);
            let mut n = tri.compute_normal();
            if n.dot(s.light) < 0.0 {
                n = -n;
            }
            let o = p + n * (1e-5 * (1.0 + p.abs().max_element()));
            lit += u64::from(bvh.miss(obvhs::ray::Ray::new_inf(o, s.light), &s.triangles));
        }
    }
    (rays, lit)
}

trait BareBvh: Sync {
    fn closest(&self, ray: obvhs::ray::Ray, hit: &mut RayHit, tris: &[Triangle]) -> bool;
    fn miss(&self, ray: obvhs::ray::Ray, tris: &[Triangle]) -> bool;
    fn original(&self, id: u32) -> usize;
}

impl BareBvh for Bvh2 {
    fn closest(&self, ray: obvhs::ray::Ray, hit: &mut RayHit, tris: &[Triangle]) -> bool {
        self.ray_traverse(ray, hit, |r, id| {
            tris[self.primitive_indices[id] as usize].intersect(r)
        })
    }
    fn miss(&self, ray: obvhs::ray::Ray, tris: &[Triangle]) -> bool {
        self.ray_traverse_miss(ray, |r, id| {
            tris[self.primitive_indices[id] as usize].intersect(r)
        })
    }
    fn original(&self, id: u32) -> usize {
        self.primitive_indices[id as usize] as usize
    }
}

impl BareBvh for CwBvh {
    fn closest(&self, ray: obvhs::ray::Ray, hit: &mut RayHit, tris: &[Triangle]) -> bool {
        self.ray_traverse(ray, hit, |r, id| {
            tris[self.primitive_indices[id] as usize].intersect(r)
        })
    }
    fn miss(&self, ray: obvhs::ray::Ray, tris: &[Triangle]) -> bool {
        self.ray_traverse_miss(ray, |r, id| {
            tris[self.primitive_indices[id] as usize].intersect(r)
        })
    }
    fn original(&self, id: u32) -> usize {
        self.primitive_indices[id as usize] as usize
    }
}

fn bare_frame<B: BareBvh>(s: &Setup, bvh: &B) -> (u64, u64) {
    (0..SIZE)
        .into_par_iter()
        .map(|y| bare_row(s, bvh, y))
        .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1))
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

/// CPU time of every thread of this process, live or finished
/// (`CLOCK_PROCESS_CPUTIME_ID`, `examples/shared/thread_cpu.rs`). Unix only; elsewhere the
/// group measures 0.
struct CpuTime;

#[path = "../examples/shared/thread_cpu.rs"]
mod thread_cpu;

fn process_cpu_ns() -> f64 {
    thread_cpu::process_cpu_ns().unwrap_or(0.0)
}

impl Measurement for CpuTime {
    type Intermediate = f64;
    type Value = f64;
    fn start(&self) -> f64 {
        process_cpu_ns()
    }
    fn end(&self, start: f64) -> f64 {
        process_cpu_ns() - start
    }
    fn add(&self, a: &f64, b: &f64) -> f64 {
        a + b
    }
    fn zero(&self) -> f64 {
        0.0
    }
    fn to_f64(&self, v: &f64) -> f64 {
        *v
    }
    fn formatter(&self) -> &dyn ValueFormatter {
        &CpuFormatter
    }
}

struct CpuFormatter;

impl ValueFormatter for CpuFormatter {
    fn scale_values(&self, _typical: f64, values: &mut [f64]) -> &'static str {
        values.iter_mut().for_each(|v| *v *= 1e-6);
        "ms cpu"
    }
    fn scale_throughputs(&self, _typical: f64, t: &Throughput, values: &mut [f64]) -> &'static str {
        let n = match *t {
            Throughput::Elements(n) => n as f64,
            _ => 1.0,
        };
        values.iter_mut().for_each(|v| *v = n / *v * 1e3); // per ns -> millions per s
        "M rays/cpu-s"
    }
    fn scale_for_machines(&self, _values: &mut [f64]) -> &'static str {
        "ns"
    }
}

struct Fixture {
    s: Setup,
    still: World,
    moving: World,
    spinning: World,
    bvh2: Bvh2,
    cwbvh: CwBvh,
    rays: u64,
    moving_rays: u64,
    bare_rays: u64,
}

fn fixture() -> Fixture {
    let s = setup();
    let still = world(&s, Vec3::ZERO);
    let moving = world(&s, Vec3::new(4.0, 0.0, 1.0));
    // Half a radian per second about the torus's axis (0.06 rad per frame).
    let spinning = s.w.world(Vec3::ZERO, Vec3::new(0.0, 0.5, 0.0));
    assert!(still.is_static() && !moving.is_static() && !spinning.is_static());
    let bvh2 = build_bvh2_from_tris(
        &s.triangles,
        BvhBuildParams::medium_build(),
        &mut Duration::default(),
    );
    let cwbvh = build_cwbvh_from_tris(
        &s.triangles,
        BvhBuildParams::medium_build(),
        &mut Duration::default(),
    );
    let (rays, lit) = trace_frame(&s, &still);
    let (bare_rays, bare_lit) = bare_frame(&s, &bvh2);
    let (moving_rays, _) = trace_frame(&s, &moving);
    eprintln!(
        "rays per frame: ours {rays} ({lit} lit), bare {bare_rays} ({bare_lit} lit), moving {moving_rays}; \
         torus {} triangles",
        s.w.mesh.triangle_count()
    );
    Fixture {
        s,
        still,
        moving,
        spinning,
        bvh2,
        cwbvh,
        rays,
        moving_rays,
        bare_rays,
    }
}

fn group<M: Measurement>(c: &mut Criterion<M>, name: &str, f: &Fixture) {
    let (two, one) = (pool(2), pool(1));
    let s = &f.s;
    let mut g = c.benchmark_group(name);
    g.sample_size(10)
        .measurement_time(Duration::from_secs(3))
        .warm_up_time(Duration::from_secs(1));
    g.throughput(Throughput::Elements(f.rays));
    g.bench_function("ours_static_2_threads", |b| {
        b.iter(|| two.install(|| black_box(trace_frame(s, &f.still))))
    });
    g.bench_function("ours_static_1_thread", |b| {
        b.iter(|| one.install(|| black_box(trace_frame(s, &f.still))))
    });
    g.throughput(Throughput::Elements(f.moving_rays));
    g.bench_function("ours_moving_2_threads", |b| {
        b.iter(|| two.install(|| black_box(trace_frame(s, &f.moving))))
    });
    g.throughput(Throughput::Elements(f.bare_rays));
    g.bench_function("bare_bvh2_2_threads", |b| {
        b.iter(|| two.install(|| black_box(bare_frame(s, &f.bvh2))))
    });
    g.bench_function("bare_cwbvh_2_threads", |b| {
        b.iter(|| two.install(|| black_box(bare_frame(s, &f.cwbvh))))
    });
    g.finish();
}

fn bench_wall(c: &mut Criterion) {
    let f = fixture();
    group(c, "trace", &f);
    let mut g = c.benchmark_group("build");
    g.sample_size(10);
    g.bench_function("world_build_moving", |b| {
        b.iter_batched(
            || (),
            |_| black_box(world(&f.s, Vec3::new(4.0, 0.0, 1.0))),
            BatchSize::SmallInput,
        )
    });
    g.bench_function("mesh_bvh_200k_triangles", |b| {
        let m = &f.s.w.mesh;
        b.iter(|| {
            black_box(TriangleMesh::new(
                m.positions.clone(),
                m.normals.clone(),
                m.indices.clone(),
            ))
        })
    });
    g.finish();
}

fn ignore<T>(_: T) {}

/// Ratios measured in the same run, interleaved round by round so that the machine's load
/// (shared by several people) hits every variant alike; medians over the rounds.
fn interleaved_ratios(f: &Fixture) {
    let (one, two) = (pool(1), pool(2));
    let cpu = |run: &dyn Fn()| {
        let t = process_cpu_ns();
        run();
        process_cpu_ns() - t
    };
    let wall = |run: &dyn Fn()| {
        let t = std::time::Instant::now();
        run();
        t.elapsed().as_secs_f64()
    };
    let s = &f.s;
    let (mut bare, mut moving, mut spinning, mut threads) = (vec![], vec![], vec![], vec![]);
    for _ in 0..15 {
        let ours = cpu(&|| ignore(one.install(|| black_box(trace_frame(s, &f.still)))));
        let b = cpu(&|| ignore(one.install(|| black_box(bare_frame(s, &f.bvh2)))));
        let m = cpu(&|| ignore(one.install(|| black_box(trace_frame(s, &f.moving)))));
        let sp = cpu(&|| ignore(one.install(|| black_box(trace_frame(s, &f.spinning)))));
        let w1 = wall(&|| ignore(one.install(|| black_box(trace_frame(s, &f.still)))));
        let w2 = wall(&|| ignore(two.install(|| black_box(trace_frame(s, &f.still)))));
        bare.push(ours / b);
        moving.push(m / ours);
        spinning.push(sp / ours);
        threads.push(w1 / w2);
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let rate = f.rays as f64
        / (cpu(&|| ignore(one.install(|| black_box(trace_frame(s, &f.still))))) * 1e-9);
    eprintln!(
        "interleaved medians of 15 rounds: ours/bare CPU time {:.3}, moving/static CPU time {:.3}, \
         spinning/static CPU time {:.3}, \
         wall 1 thread / 2 threads {:.3}; ours {:.2} M rays per CPU-second",
        median(&mut bare),
        median(&mut moving),
        median(&mut spinning),
        median(&mut threads),
        rate * 1e-6
    );
}

fn bench_cpu(c: &mut Criterion<CpuTime>) {
    let f = fixture();
    interleaved_ratios(&f);
    group(c, "trace_cpu", &f);
}

criterion_group!(benches, bench_wall);
criterion_group! {
    name = cpu;
    config = Criterion::default().with_measurement(CpuTime);
    targets = bench_cpu
}
criterion_main!(benches, cpu);
