//! CPU time per camera sample of one frame of a scene, on one thread: the figure the peers
//! comparison (`bench/peers/`) sets against Mitsuba 3, and the workload to profile the render
//! loop with (`valgrind --tool=callgrind`).
//!
//! ```text
//! cargo run --release -p renderer --example sample_cost -- SCENE.json --spp 16 --rounds 5
//! cargo run --release -p renderer --example sample_cost -- SCENE.json --spp 1024 --rounds 1 --out ref.f32
//! cargo run --release -p renderer --example sample_cost -- SCENE.json --randomization scramble
//! ```
//!
//! Each round renders frame `--frame` (default 0) with `--seed` + round as the stimulus seed
//! (independent noise per round) and prints `round <i> cpu_s <s> samples <n> ns_per_sample <x>`;
//! the CPU time is the rendering thread's (`CLOCK_THREAD_CPUTIME_ID`) over `render_frame`
//! (world and sampler builds included, output not). `--out FILE` writes the last round's linear
//! film (exposure applied) as little-endian f32, row-major RGB.

use anyhow::{Context, Result};
use clap::Parser;
use renderer::progress::NoProgress;
use renderer::render::render_frame;
use renderer::sampling::Randomization;
use renderer::scene::Scene;
use std::path::PathBuf;

#[derive(Parser)]
struct Args {
    /// Scene file.
    scene: PathBuf,
    /// Samples per pixel (default: the scene's).
    #[arg(long)]
    spp: Option<u32>,
    /// Point set (default: the scene's).
    #[arg(long)]
    point_set: Option<renderer::condition::PointSetKind>,
    /// Per-pixel randomization, `shift` or `scramble` (default: the scene's).
    #[arg(long)]
    randomization: Option<String>,
    #[arg(long, default_value_t = 0)]
    frame: u32,
    #[arg(long, default_value_t = 5)]
    rounds: u64,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Write the last round's linear film here.
    #[arg(long)]
    out: Option<PathBuf>,
}

#[path = "shared/thread_cpu.rs"]
mod thread_cpu;
use thread_cpu::thread_cpu_ns;

fn main() -> Result<()> {
    let args = Args::parse();
    // bench/lanes.sh times SSE2 lanes against the widest this CPU has.
    if std::env::var("BLURLAB_LANES").as_deref() == Ok("sse2") {
        renderer::simd::limit_to_sse2();
    }
    let scene = Scene::load(&args.scene)?;
    let mut sampling = scene.settings.sampling.clone();
    sampling.spp = args.spp.unwrap_or(sampling.spp);
    if let Some(p) = args.point_set {
        sampling.point_set = p;
    }
    if let Some(r) = &args.randomization {
        sampling.randomization = Some(match r.as_str() {
            "shift" => Randomization::Shift,
            "scramble" => Randomization::Scramble,
            other => anyhow::bail!("--randomization {other}: expected shift or scramble"),
        });
    }
    // One rayon thread, and the timing taken on it: rows run on the pool's thread.
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let mut last = None;
    for round in 0..args.rounds {
        let (cpu, film, stats) = pool.install(|| -> Result<_> {
            let t = thread_cpu_ns()?;
            let (film, stats) = render_frame(
                &scene,
                &sampling,
                args.seed + round,
                args.frame,
                &NoProgress,
            )?;
            Ok((thread_cpu_ns()? - t, film, stats))
        })?;
        println!(
            "round {round} cpu_s {:.5} samples {} ns_per_sample {:.2} rays {} non_finite {}",
            cpu * 1e-9,
            stats.samples,
            cpu / stats.samples as f64,
            stats.rays,
            stats.non_finite
        );
        last = Some(film);
    }
    if let (Some(path), Some(film)) = (args.out, last) {
        let linear = film.develop(scene.settings.exposure).linear;
        let bytes: Vec<u8> = linear
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        renderer::atomic::write_atomic(&path, &bytes)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}
