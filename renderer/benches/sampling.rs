//! Sampling speed: generating every point set at the thesis's eight levels, building a
//! frame's sampler, and the per-sample cost of shift + warps (the renderer's hot path).
//!
//! `cargo bench -p renderer --bench sampling`

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use renderer::sampling::pointset::{self, Poisson};
use renderer::sampling::{FrameSampler, SamplingConfig, SpatialFilter};
use std::hint::black_box;

/// The thesis's sampling levels (Figure 12).
const LEVELS: [usize; 8] = [1, 8, 27, 64, 125, 216, 343, 512];

fn generate_all_levels(c: &mut Criterion) {
    let mut g = c.benchmark_group("generate_8_levels");
    g.sample_size(20);
    for set in pointset::ALL {
        g.bench_function(set.name(), |b| {
            b.iter(|| {
                for n in LEVELS {
                    black_box(pointset::generate(*set, n, 3, black_box(1)).unwrap());
                }
            })
        });
    }
    g.bench_function("every_set", |b| {
        b.iter(|| {
            for set in pointset::ALL {
                for n in LEVELS {
                    black_box(pointset::generate(*set, n, 3, black_box(1)).unwrap());
                }
            }
        })
    });
    g.finish();
}

fn frame_sampler_new(c: &mut Criterion) {
    let mut g = c.benchmark_group("frame_sampler_new");
    g.sample_size(20);
    for (set, spp) in [("poisson", 512), ("poisson", 4096), ("hammersley", 512)] {
        let cfg = SamplingConfig {
            point_set: set.parse().unwrap(),
            spp,
            ..Default::default()
        };
        g.bench_function(format!("{set}_{spp}"), |b| {
            b.iter(|| black_box(FrameSampler::new(&cfg, 1, black_box(3)).unwrap()))
        });
    }
    g.bench_function("poisson_eliminate_512", |b| {
        b.iter(|| black_box(Poisson::eliminate(512, 3, black_box(2))))
    });
    g.finish();
}

fn per_sample(c: &mut Criterion) {
    const PIXELS: u32 = 64;
    const SPP: u32 = 64;
    let mut g = c.benchmark_group("per_sample");
    g.throughput(Throughput::Elements((PIXELS * SPP) as u64));
    let configs = [
        ("gaussian_box", SpatialFilter::Gaussian, "box"),
        ("gaussian_triangle", SpatialFilter::Gaussian, "triangle"),
        ("box_box", SpatialFilter::Box, "box"),
    ];
    for (name, spatial, time) in configs {
        let cfg = SamplingConfig {
            point_set: "hammersley".parse().unwrap(),
            spp: SPP,
            time_filter: time.parse().unwrap(),
            spatial_filter: Some(spatial),
            ..Default::default()
        };
        let s = FrameSampler::new(&cfg, 1, 0).unwrap();
        // The renderer's loop: per pixel, hash the shift once, then every sample.
        g.bench_function(format!("{name}_pixel_then_samples"), |b| {
            b.iter(|| {
                let mut acc = 0.0f32;
                for x in 0..PIXELS {
                    let px = s.pixel(black_box(x), 7);
                    for i in 0..SPP as usize {
                        let p = px.sample(i);
                        acc += p.dx + p.dy + p.t;
                    }
                }
                acc
            })
        });
        // The one-call interface: the shift is re-hashed for every sample.
        g.bench_function(format!("{name}_sample_xy"), |b| {
            b.iter(|| {
                let mut acc = 0.0f32;
                for x in 0..PIXELS {
                    for i in 0..SPP as usize {
                        let p = s.sample(black_box(x), 7, i);
                        acc += p.dx + p.dy + p.t;
                    }
                }
                acc
            })
        });
    }
    g.finish();
}

criterion_group!(benches, generate_all_levels, frame_sampler_new, per_sample);
criterion_main!(benches);
