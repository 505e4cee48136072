//! The cost of motion blur in a scene: CPU time of one frame against the same frame of the scene
//! held still at the frame's mid-shutter time ([`Scene::frozen_at`]: the same picture without
//! the blur), at equal spp, with the scene's own sampling. Runs are interleaved round by round
//! on one rayon thread, and each run's time is that thread's CPU time
//! (`CLOCK_THREAD_CPUTIME_ID`), so load from other processes on a shared machine moves
//! both sides alike and mostly cancels in the ratio.
//!
//! ```text
//! cargo run --release -p renderer --example motion_cost -- scenes/thesis/spheres.json
//! ```
//!
//! `--only moving` (or `frozen`) renders just that side, for profilers (`perf record`,
//! `valgrind --tool=callgrind`). Results: `docs/benchmarks/renderer-scenes.md`.

use anyhow::Result;
use clap::{Parser, ValueEnum};
use renderer::progress::NoProgress;
use renderer::render::render_frame;
use renderer::scene::Scene;
use std::path::PathBuf;

#[derive(Parser)]
struct Args {
    /// Scene file.
    scene: PathBuf,
    /// Image width and height in pixels.
    #[arg(long, default_value_t = 192)]
    size: u32,
    /// Samples per pixel (default: the scene's).
    #[arg(long)]
    spp: Option<u32>,
    /// Frame to render (default: the middle one).
    #[arg(long)]
    frame: Option<u32>,
    /// Rounds of (moving, frozen) pairs; the medians are reported.
    #[arg(long, default_value_t = 7)]
    rounds: usize,
    /// Render only one side (for profiling).
    #[arg(long)]
    only: Option<Side>,
}

#[derive(Clone, Copy, PartialEq, ValueEnum)]
enum Side {
    Moving,
    Frozen,
}

#[path = "shared/median.rs"]
mod median;
use median::median;

#[path = "shared/thread_cpu.rs"]
mod thread_cpu;
use thread_cpu::thread_cpu_ns;

fn main() -> Result<()> {
    let args = Args::parse();
    let mut moving = Scene::load(&args.scene)?;
    moving.settings.width = args.size;
    moving.settings.height = args.size;
    let frame = args.frame.unwrap_or(moving.settings.frames / 2);
    let (t0, t1) = moving.settings.shutter(frame);
    let frozen = moving.frozen_at(0.5 * (t0 + t1));
    let mut sampling = moving.settings.sampling.clone();
    if let Some(spp) = args.spp {
        sampling.spp = spp;
    }
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    // One frame's CPU time in ms and its ray count; on the pool's only thread, so every row
    // runs on the thread whose clock is read.
    let run = |scene: &Scene| -> Result<(f64, u64)> {
        pool.install(|| {
            let start = thread_cpu_ns()?;
            let (_, stats) = render_frame(scene, &sampling, 1, frame, &NoProgress)?;
            Ok(((thread_cpu_ns()? - start) * 1e-6, stats.rays))
        })
    };
    println!(
        "{} frame {frame}, {}x{}, {} spp, {} {}; CPU ms of one thread",
        args.scene.display(),
        args.size,
        args.size,
        sampling.spp,
        sampling.point_set,
        sampling.time_filter,
    );
    let (mut m, mut f, mut ratios) = (vec![], vec![], vec![]);
    for round in 0..args.rounds {
        let a = (args.only != Some(Side::Frozen))
            .then(|| run(&moving))
            .transpose()?;
        let b = (args.only != Some(Side::Moving))
            .then(|| run(&frozen))
            .transpose()?;
        let show = |x: Option<(f64, u64)>| {
            x.map_or("-".into(), |(ms, rays)| format!("{ms:8.1} ({rays} rays)"))
        };
        println!("round {round}: moving {}  frozen {}", show(a), show(b));
        if let Some((ms, _)) = a {
            m.push(ms);
        }
        if let Some((ms, _)) = b {
            f.push(ms);
        }
        if let (Some((x, _)), Some((y, _))) = (a, b) {
            ratios.push(x / y);
        }
    }
    if !m.is_empty() && !f.is_empty() {
        let (mm, mf) = (median(m), median(f));
        println!(
            "median moving {mm:.1} ms, frozen {mf:.1} ms: ratio of medians {:.3}, median of round ratios {:.3}",
            mm / mf,
            median(ratios)
        );
    }
    Ok(())
}
