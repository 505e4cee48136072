//! RMSE at equal spp of every point set under each per-pixel randomization (`shift`, the
//! thesis's toroidal shift, and `scramble`), on a scene frame as it moves and the same frame
//! held still at mid-shutter ([`Scene::frozen_at`]), against a high-spp reference of each.
//! Medians over seeds. Results: `docs/benchmarks/scramble.md`.
//!
//! ```text
//! cargo run --release -p renderer --example scramble_rmse -- \
//!     scenes/thesis/spheres.json --frame 100 --size 128 --seeds 5 --csv spheres.csv
//! ```
//!
//! `--cost` instead times the sampler alone (shift or scramble, then both warps) per sample on
//! one thread, for every set at 64 spp over 256 x 256 pixels (medians of 5 rounds of thread CPU
//! time); the scene argument is then ignored.
//!
//! Error per pixel and channel of the exposed radiance, both as is (HDR: a bright highlight
//! counts in full) and clamped to [0, 1] (the display's range, before the sRGB curve and
//! 8-bit rounding), averaged over the frame.

use anyhow::{Result, ensure};
use clap::Parser;
use renderer::condition::{PointSetKind, TimeFilter};
use renderer::progress::NoProgress;
use renderer::render::render_frame;
use renderer::sampling::{Randomization, SamplingConfig, Scope};
use renderer::scene::Scene;
use std::fmt::Write as _;
use std::path::PathBuf;

#[derive(Parser)]
struct Args {
    /// Scene file.
    scene: PathBuf,
    /// Frame to render (default: the middle one).
    #[arg(long)]
    frame: Option<u32>,
    /// Image width and height in pixels.
    #[arg(long, default_value_t = 128)]
    size: u32,
    /// Samples per pixel compared (cubes, so that stratified has every level).
    #[arg(long, value_delimiter = ',', default_values_t = [8u32, 27, 64, 216])]
    levels: Vec<u32>,
    /// Point sets compared.
    #[arg(long, value_delimiter = ',', default_values_t = PointSetKind::ALL)]
    point_sets: Vec<PointSetKind>,
    /// Seeds per configuration (1, 2, ...); the median RMSE is reported.
    #[arg(long, default_value_t = 5)]
    seeds: u64,
    /// Samples per pixel of the reference (stratified, shifted, its own seed).
    #[arg(long, default_value_t = 4096)]
    reference_spp: u32,
    /// Time filter of every render.
    #[arg(long, default_value = "truncated_box")]
    time_filter: TimeFilter,
    /// Also write every run as CSV.
    #[arg(long)]
    csv: Option<PathBuf>,
    /// Time the sampler per sample instead (see above).
    #[arg(long)]
    cost: bool,
}

#[path = "shared/median.rs"]
mod median;
use median::median;

#[path = "shared/thread_cpu.rs"]
mod thread_cpu;

/// ns of thread CPU time per sample of each set under each randomization.
fn cost(args: &Args) -> Result<()> {
    use renderer::sampling::FrameSampler;
    println!("| point set | shift ns/sample | scramble ns/sample |\n|---|---|---|");
    for &ps in &args.point_sets {
        let mut cells = Vec::new();
        for r in [Randomization::Shift, Randomization::Scramble] {
            let cfg = SamplingConfig {
                point_set: ps,
                spp: 64,
                time_filter: args.time_filter,
                randomization: Some(r),
                ..Default::default()
            };
            let s = FrameSampler::new(&cfg, 1, 0)?;
            let mut runs = Vec::new();
            for _ in 0..5 {
                let t0 = thread_cpu::thread_cpu_ns()?;
                let mut acc = 0.0f32;
                for y in 0..256 {
                    for x in 0..256 {
                        let px = s.pixel(x, y);
                        for i in 0..64 {
                            let p = px.sample(i);
                            acc += p.dx + p.dy + p.t;
                        }
                    }
                }
                std::hint::black_box(acc);
                runs.push((thread_cpu::thread_cpu_ns()? - t0) / (256.0 * 256.0 * 64.0));
            }
            cells.push(median(runs));
        }
        println!("| {ps} | {:.1} | {:.1} |", cells[0], cells[1]);
    }
    Ok(())
}

/// (HDR RMSE, clamped RMSE) of `a` against `r`.
fn rmse(a: &[[f32; 3]], r: &[[f32; 3]]) -> (f64, f64) {
    let (mut hdr, mut clamped) = (0.0f64, 0.0f64);
    for (p, q) in a.iter().zip(r) {
        for c in 0..3 {
            let d = (p[c] - q[c]) as f64;
            hdr += d * d;
            let d = (p[c].clamp(0.0, 1.0) - q[c].clamp(0.0, 1.0)) as f64;
            clamped += d * d;
        }
    }
    let n = (a.len() * 3) as f64;
    ((hdr / n).sqrt(), (clamped / n).sqrt())
}

fn main() -> Result<()> {
    let args = Args::parse();
    if args.cost {
        return cost(&args);
    }
    ensure!(args.seeds >= 1, "--seeds must be at least 1");
    let mut moving = Scene::load(&args.scene)?;
    moving.settings.width = args.size;
    moving.settings.height = args.size;
    let frame = args.frame.unwrap_or(moving.settings.frames / 2);
    let (t0, t1) = moving.settings.shutter(frame);
    let still = moving.frozen_at(0.5 * (t0 + t1));
    let exposure = moving.settings.exposure;
    // The thesis job's scopes: new points and new per-pixel randomization every frame.
    let config = |point_set: PointSetKind, spp: u32, r: Randomization| SamplingConfig {
        point_set,
        spp,
        time_filter: args.time_filter,
        point_set_scope: Some(Scope::Frame),
        shift_scope: Some(Scope::Frame),
        randomization: Some(r),
        ..moving.settings.sampling.clone()
    };
    let develop = |scene: &Scene, cfg: &SamplingConfig, seed: u64| -> Result<Vec<[f32; 3]>> {
        let (film, _) = render_frame(scene, cfg, seed, frame, &NoProgress)?;
        Ok(film.develop(exposure).linear)
    };
    let mut csv = String::from("scene,point_set,randomization,spp,seed,rmse_hdr,rmse_clamped\n");
    let mut table = String::new();
    for (name, scene) in [("moving", &moving), ("static", &still)] {
        let t = std::time::Instant::now();
        let reference = develop(
            scene,
            &config(
                PointSetKind::Stratified,
                args.reference_spp,
                Randomization::Shift,
            ),
            0x7e7e_7e7e,
        )?;
        eprintln!("{name}: reference in {:.1} s", t.elapsed().as_secs_f64());
        writeln!(
            table,
            "\n{name} ({} frame {frame}, {}x{}, {} seeds, against {} spp stratified)\n",
            args.scene.display(),
            args.size,
            args.size,
            args.seeds,
            args.reference_spp
        )?;
        let levels: Vec<String> = args.levels.iter().map(|l| l.to_string()).collect();
        writeln!(
            table,
            "| point set | randomization | {} spp (HDR / clamped) |",
            levels.join(" | ")
        )?;
        writeln!(table, "|---|---|{}", "---|".repeat(levels.len()))?;
        for ps in &args.point_sets {
            let mut rows = Vec::new();
            for r in [Randomization::Shift, Randomization::Scramble] {
                let mut cells = Vec::new();
                for &spp in &args.levels {
                    let (mut h, mut c, mut mse) = (Vec::new(), Vec::new(), 0.0);
                    for seed in 1..=args.seeds {
                        let img = develop(scene, &config(*ps, spp, r), seed)?;
                        let (a, b) = rmse(&img, &reference);
                        writeln!(csv, "{name},{ps},{},{spp},{seed},{a},{b}", r.name())?;
                        h.push(a);
                        c.push(b);
                        mse += b * b / args.seeds as f64;
                    }
                    cells.push((median(h), median(c), mse.sqrt()));
                }
                rows.push(cells);
            }
            for (k, r) in [Randomization::Shift, Randomization::Scramble]
                .iter()
                .enumerate()
            {
                let cells: Vec<String> = rows[k]
                    .iter()
                    .map(|(h, c, _)| format!("{h:.5} / {c:.5}"))
                    .collect();
                writeln!(table, "| {ps} | {} | {} |", r.name(), cells.join(" | "))?;
            }
            let ratios: Vec<String> = rows[0]
                .iter()
                .zip(&rows[1])
                .map(|(s, c)| format!("{:.2} / {:.2}", s.0 / c.0, s.1 / c.1))
                .collect();
            writeln!(
                table,
                "| {ps} | shift / scramble | {} |",
                ratios.join(" | ")
            )?;
            // The mean of a skewed error over seeds is steadier than its median: the ratio of
            // the clamped RMSE pooled over seeds (root of the mean MSE).
            let pooled: Vec<String> = rows[0]
                .iter()
                .zip(&rows[1])
                .map(|(s, c)| format!("{:.2}", s.2 / c.2))
                .collect();
            writeln!(
                table,
                "| {ps} | shift / scramble, pooled clamped | {} |",
                pooled.join(" | ")
            )?;
            eprintln!("{name}: {ps} done at {:.0} s", t.elapsed().as_secs_f64());
        }
    }
    print!("{table}");
    if let Some(path) = &args.csv {
        std::fs::write(path, csv)?;
    }
    Ok(())
}
