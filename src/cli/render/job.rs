//! `blurlab render job <job.json | job.job>`: render a stimulus set (or one shard of it), finalize it, estimate
//! it, or write a Slurm job-array script for it.

use crate::cli::progress::{Look, Terminal};
use anyhow::{Context, Result, bail};
use clap::Args;
use renderer::job::slurm::{SlurmOptions, emitted_message, script};
use renderer::job::{Finalize, Job, RunOptions, Shard};
use std::path::{Path, PathBuf};

/// Render every stimulus of a job into <out>/<job name>/ (resumable; rerun to finish).
#[derive(Debug, Args)]
pub struct JobArgs {
    /// The job file: JSON (format blurlab-job/1, e.g. scenes/demo/job.json) or the thesis's
    /// seven-line text (Figure 12, ending in .job).
    pub job: PathBuf,
    /// Render these scenes (JSON or .scene) instead of the job's; repeat for several. (Not
    /// with --emit-slurm: cluster tasks read the job file, so name the scenes there.)
    #[arg(long = "scene", value_name = "SCENE", conflicts_with = "emit_slurm")]
    pub scenes: Vec<PathBuf>,
    /// Root folder of stimulus sets.
    #[arg(long, default_value = "stimuli")]
    pub out: PathBuf,
    /// Render only part K of N (K = 1..N); the union of all parts equals a single run.
    #[arg(long)]
    pub shard: Option<Shard>,
    /// Render nothing; measure what is left and write the manifest (all frames must exist).
    #[arg(long, conflicts_with_all = ["no_finalize", "dry_run"])]
    pub finalize: bool,
    /// Do not write the manifest even if this run completes the job.
    #[arg(long)]
    pub no_finalize: bool,
    /// Print the number of stimuli, frames and samples and an estimated time, render nothing.
    #[arg(long)]
    pub dry_run: bool,
    /// Write a Slurm job-array script to this path instead of rendering.
    #[arg(long, value_name = "SCRIPT")]
    pub emit_slurm: Option<PathBuf>,
    /// Number of array tasks (shards) for --emit-slurm.
    #[arg(long, default_value_t = 16)]
    pub shards: u32,
    /// CPUs per array task for --emit-slurm: a node must have at least this many, or Slurm
    /// keeps the tasks pending (the stimuli do not depend on it).
    #[arg(long, default_value_t = 4, value_parser = renderer::limits::parse_cpus,
          allow_hyphen_values = true)]
    pub cpus_per_task: u32,
    /// Hide the progress bar.
    #[arg(long)]
    pub no_progress: bool,
    #[command(flatten)]
    pub assets: super::AssetArgs,
}

pub fn run(args: JobArgs) -> Result<()> {
    let mut job = Job::load_with_scenes(&args.job, &args.scenes)?;
    job.assets = args.assets.assets()?;
    let shard = args.shard.unwrap_or(Shard::WHOLE);
    if let Some(path) = &args.emit_slurm {
        return emit_slurm(&job, &args, path);
    }
    if args.dry_run {
        let (dry, warnings) = renderer::job::dry_run(&job, shard)?;
        super::print_warnings(&warnings);
        print!("{dry}");
        if let Some(note) = avx2_note(cpu_has_avx2(), cfg!(target_feature = "avx2")) {
            println!("note: {note}");
        }
        return Ok(());
    }
    let opts = RunOptions {
        out_dir: args.out.clone(),
        shard,
        finalize: if args.finalize {
            Finalize::Only
        } else if args.no_finalize {
            Finalize::Never
        } else {
            Finalize::Auto
        },
    };
    let bar = Terminal::new(Look::Job, !args.no_progress);
    let report = renderer::job::run(&job, &opts, &bar)?;
    super::print_warnings(&report.warnings);
    println!(
        "{}: rendered {} frames, {} already done, {} missing in the job",
        report.job_dir.display(),
        report.frames_rendered,
        report.frames_skipped,
        report.frames_missing
    );
    match &report.manifest {
        Some(m) => println!(
            "wrote {} ({} stimuli)",
            renderer::manifest::manifest_file(&report.job_dir).display(),
            m.stimuli.len()
        ),
        None if report.frames_missing > 0 => println!(
            "manifest not written yet: other shards still have frames to render; finish with \
             `blurlab render job {} --out {} --finalize`",
            args.job.display(),
            args.out.display()
        ),
        None => {}
    }
    Ok(())
}

/// A word under the dry run's estimate where the CPU runs AVX2 and this binary is not built for
/// it: its packet code takes AVX2 lanes anyway, but an AVX2 build is 1.1-1.2x faster still
/// (BENCHMARKS.md, "Lanes chosen at run time").
fn avx2_note(cpu_has_avx2: bool, built_for_avx2: bool) -> Option<&'static str> {
    (cpu_has_avx2 && !built_for_avx2).then_some(
        "this CPU has AVX2: this binary traces its packets in AVX2 lanes, and a build for it \
         renders the same bytes 1.1-1.2x faster still (RUSTFLAGS=\"-C target-cpu=x86-64-v3 -C \
         target-feature=-fma\" cargo install --path .; BENCHMARKS.md, \"Lanes chosen at run \
         time\")",
    )
}

#[cfg(target_arch = "x86_64")]
fn cpu_has_avx2() -> bool {
    std::arch::is_x86_feature_detected!("avx2")
}

#[cfg(not(target_arch = "x86_64"))]
fn cpu_has_avx2() -> bool {
    false
}

fn emit_slurm(job: &Job, args: &JobArgs, path: &Path) -> Result<()> {
    if args.shards == 0 {
        bail!("--shards must be at least 1");
    }
    if !job.assets.is_empty() {
        bail!(
            "--asset with --emit-slurm: the array tasks would render the scenes' own files; \
             expected --emit-slurm without --asset (copy the asset where the scene names it on \
             the cluster, outside the project's repository)"
        );
    }
    // A time limit per task from the calibration estimate, with a 2x margin for slower nodes
    // and imbalance.
    let (dry, warnings) = renderer::job::dry_run(
        job,
        Shard {
            index: 1,
            count: args.shards,
        },
    )?;
    super::print_warnings(&warnings);
    let per_task = dry.estimated_shard_seconds;
    let exe = std::env::current_exe().context("cannot locate this program")?;
    let command = vec![exe.display().to_string(), "render".into()];
    let abs = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let options = SlurmOptions {
        command,
        shards: args.shards,
        cpus_per_task: args.cpus_per_task,
        time_limit_seconds: (2.0 * per_task).ceil() as u64 + 600,
    };
    let text = script(&job.name, &abs(&args.job), &abs(&args.out), &options);
    renderer::atomic::write_atomic(path, text.as_bytes())?;
    println!("{}", emitted_message(path, &options));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::avx2_note;

    #[test]
    fn the_avx2_note_is_for_an_avx2_cpu_running_a_build_without_it() {
        assert!(avx2_note(true, false).is_some_and(|n| n.contains("target-feature=-fma")));
        assert_eq!(avx2_note(true, true), None);
        assert_eq!(avx2_note(false, false), None);
        assert_eq!(avx2_note(false, true), None);
    }
}
