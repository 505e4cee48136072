//! Whole frames of the suite's scenes at a small size: rays per second (primary, shadow and
//! reflection rays together), and the cost of motion (each scene against itself frozen at the
//! frame's mid-shutter time: the same picture without blur, at equal spp).
//!
//! `cargo bench -p renderer --bench render`

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use renderer::progress::NoProgress;
use renderer::render::render_frame;
use renderer::sampling::SamplingConfig;
use renderer::scene::Scene;
use std::hint::black_box;
use std::path::Path;

const SIZE: u32 = 96;
const SPP: u32 = 8;

fn scene(name: &str) -> (Scene, u32) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../scenes/thesis/{name}.json"));
    let mut s = Scene::load(&path).expect("scene loads");
    s.settings.width = SIZE;
    s.settings.height = SIZE;
    // The middle frame: where the plane passes closest and the sky streaks most.
    let frame = s.settings.frames / 2;
    (s, frame)
}

fn frames(c: &mut Criterion) {
    let cfg = SamplingConfig {
        spp: SPP,
        ..SamplingConfig::default()
    };
    let mut group = c.benchmark_group("frame");
    group.sample_size(10);
    for name in ["plane", "spheres"] {
        let (moving, frame) = scene(name);
        let (t0, t1) = moving.settings.shutter(frame);
        let frozen = moving.frozen_at(0.5 * (t0 + t1));
        for (label, s) in [("moving", &moving), ("frozen", &frozen)] {
            let rays = render_frame(s, &cfg, 1, frame, &NoProgress).unwrap().1.rays;
            group.throughput(Throughput::Elements(rays));
            group.bench_function(format!("{name}/{label}"), |b| {
                b.iter(|| black_box(render_frame(s, &cfg, 1, frame, &NoProgress).unwrap()))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, frames);
criterion_main!(benches);
