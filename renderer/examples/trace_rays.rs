//! The trace bench's workload ([`renderer::workload`]) from the command line, on the calling
//! thread: rays per CPU-second of the tracing core, for profilers and for the peers comparison
//! (`bench/peers/`), which runs it against Embree on the same rays.
//!
//! ```text
//! cargo run --release -p renderer --example trace_rays -- --rounds 5
//! cargo run --release -p renderer --example trace_rays -- --export /tmp/workload
//! ```
//!
//! Each round prints one line `round <i> cpu_s <s> rays <n> lit <n>`; the CPU time is the
//! thread's (`CLOCK_THREAD_CPUTIME_ID`) over the frame only. `--export DIR` writes the
//! workload for other tracers as little-endian f32 arrays: `triangles.f32` (n x 9: the torus in
//! world space and the two ground triangles), `rays.f32` (65,536 x 7: origin, direction,
//! time), `light.f32` (3), and `ours.txt` (hits and lit count of the suite on the same rays).

use anyhow::{Context, Result};
use clap::Parser;
use renderer::workload::{SIZE, TraceWorkload};
use std::path::PathBuf;

#[derive(Parser)]
struct Args {
    /// Frames to trace, each timed on its own.
    #[arg(long, default_value_t = 5)]
    rounds: usize,
    /// Write the workload's triangles and rays to this folder instead.
    #[arg(long)]
    export: Option<PathBuf>,
}

#[path = "shared/thread_cpu.rs"]
mod thread_cpu;
use thread_cpu::thread_cpu_ns;

fn write_f32(path: PathBuf, values: impl Iterator<Item = f32>) -> Result<()> {
    let bytes: Vec<u8> = values.flat_map(f32::to_le_bytes).collect();
    renderer::atomic::write_atomic(&path, &bytes)
        .with_context(|| format!("writing {}", path.display()))
}

fn main() -> Result<()> {
    let args = Args::parse();
    let t = thread_cpu_ns()?;
    let w = TraceWorkload::new();
    println!("build cpu_s {:.4}", (thread_cpu_ns()? - t) * 1e-9);
    let world = w.world(glam::Vec3::ZERO, glam::Vec3::ZERO);
    if let Some(dir) = args.export {
        std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
        let tris = w.world_triangles();
        write_f32(
            dir.join("triangles.f32"),
            tris.iter()
                .flat_map(|t| t.iter().flat_map(|v| v.to_array())),
        )?;
        let rays: Vec<_> = (0..SIZE)
            .flat_map(|y| (0..SIZE).map(move |x| (x, y)))
            .map(|(x, y)| w.camera_ray(x, y))
            .collect();
        write_f32(
            dir.join("rays.f32"),
            rays.iter().flat_map(|r| {
                let (o, d) = (r.origin.to_array(), r.dir.to_array());
                [o[0], o[1], o[2], d[0], d[1], d[2], r.time]
            }),
        )?;
        write_f32(dir.join("light.f32"), w.light.to_array().into_iter())?;
        let hits = rays.iter().filter(|r| world.intersect(r).is_some()).count();
        let (rays, lit) = w.trace_frame(&world);
        let text = format!("hits {hits}\nrays {rays}\nlit {lit}\n");
        renderer::atomic::write_atomic(&dir.join("ours.txt"), text.as_bytes())?;
        println!("exported to {}", dir.display());
        return Ok(());
    }
    for round in 0..args.rounds {
        let t = thread_cpu_ns()?;
        let (rays, lit) = std::hint::black_box(w.trace_frame(&world));
        let s = (thread_cpu_ns()? - t) * 1e-9;
        println!("round {round} cpu_s {s:.5} rays {rays} lit {lit}");
    }
    Ok(())
}
