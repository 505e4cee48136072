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
