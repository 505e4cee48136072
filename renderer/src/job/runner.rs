//! Rendering a job into `<out>/<job>/`: one folder per stimulus holding `frame_NNNN.png`
//! (display), `frame_NNNN.exr` (linear; references always, others on request) and
//! `frame_NNNN.json` (the frame's record, written last), plus `stimulus.json` (what the
//! stimulus is, to refuse mixing frames of a changed job) and, once every frame of the job
//! exists, `manifest.json`.
//!
//! Resume is per frame: a frame counts as done when its record exists and the files it names
//! have the recorded sizes; everything else is rendered again. Every file is written to a
//! temporary name and renamed, so an interrupted run leaves whole files or none.
//! What to render is the job's [`super::plan`]. Finishing a job (late measurements, content
//! checks, the manifest) is [`super::finalize`];
//! counting and estimating without rendering is [`super::dry_run`].

use super::Job;
use super::finalize::{finalize_job, measure};
use super::frame_record::{self as record, FrameRecord};
use super::plan::{Plan, need_exr, stimulus_dir};
use super::shard::{self, Shard};
use super::source::FrameSource;
use crate::assets::AssetRecord;
use crate::film::RenderedFrame;
use crate::frame_io::{exr as linear_frame, names, png::png_bytes};
use crate::manifest::Manifest;
use crate::progress::Progress;
use crate::sampling::SamplingConfig;
use anyhow::{Context, Result, bail};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// When to write the manifest.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Finalize {
    /// After rendering, if every frame of the job exists (whichever shard rendered it).
    Auto,
    /// Render nothing; finalize (fails naming what is missing if the job is incomplete).
    Only,
    /// Never (shards that should leave the manifest to a final step).
    Never,
}

/// How to run a job.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Root of stimulus sets; the job renders into `out_dir/<job name>/`.
    pub out_dir: PathBuf,
    pub shard: Shard,
    pub finalize: Finalize,
}

impl RunOptions {
    /// The whole job into `out_dir`, finalizing at the end.
    pub fn new(out_dir: impl Into<PathBuf>) -> Self {
        Self {
            out_dir: out_dir.into(),
            shard: Shard::WHOLE,
            finalize: Finalize::Auto,
        }
    }
}

/// What a run did.
#[derive(Clone, Debug)]
pub struct RunReport {
    /// `out_dir/<job name>`.
    pub job_dir: PathBuf,
    pub frames_rendered: u64,
    /// Frames of this shard found complete on disk and skipped.
    pub frames_skipped: u64,
    /// Frames of the whole job still missing after this run (other shards' work).
    pub frames_missing: u64,
    /// The manifest, when the job was finalized.
    pub manifest: Option<Manifest>,
    /// Problems that did not stop the run (repaired environment texels), for the caller to
    /// show.
    pub warnings: Vec<String>,
}

/// Format of `<id>/stimulus.json`.
const STIMULUS_FORMAT: &str = "blurlab-stimulus/1";

/// What determines a stimulus's frames; frames on disk are trusted only if this matches.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
struct StimulusStamp {
    format: String,
    id: String,
    scene: String,
    /// SHA-256 of the scene file (models and maps it names are not included).
    scene_sha256: String,
    sampling: SamplingConfig,
    seed: u64,
    width: u32,
    height: u32,
    /// Scene frame shown as frame 0.
    first_frame: u32,
    /// The user's files in place of the scenes' (`--asset`), by name and hash; absent when
    /// none, so stamps written before the field still match.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    assets: Vec<AssetRecord>,
}

/// Render (this shard of) a job whose scenes are given as frame sources, one per
/// `job.scenes` entry, then finalize if every frame exists (per `opts.finalize`); `progress`
/// counts the samples of the frames left to render and names the frame under way.
pub fn run_with_sources(
    job: &Job,
    sources: &[Box<dyn FrameSource>],
    opts: &RunOptions,
    progress: &dyn Progress,
) -> Result<RunReport> {
    let plan = Plan::new(job, sources)?;
    let job_dir = opts.out_dir.join(&job.name);
    let shard = match opts.finalize {
        Finalize::Only => Shard::WHOLE,
        _ => opts.shard,
    };
    let _lock = super::lock::JobLock::acquire(&job_dir, shard)?;
    stamp_stimuli(job, &plan, &job_dir)?;
    let mut report = RunReport {
        job_dir: job_dir.clone(),
        frames_rendered: 0,
        frames_skipped: 0,
        frames_missing: 0,
        manifest: None,
        warnings: Vec::new(),
    };
    if opts.finalize != Finalize::Only {
        let mine = shard::assign(&plan.units, opts.shard);
        render_units(
            job,
            &plan,
            sources,
            &job_dir,
            &mine,
            opts,
            progress,
            &mut report,
        )?;
    }
    report.frames_missing = missing_frames(job, &plan, &job_dir).len() as u64;
    let finalize = match opts.finalize {
        Finalize::Never => false,
        Finalize::Auto => report.frames_missing == 0,
        Finalize::Only => true,
    };
    if finalize {
        let missing = missing_frames(job, &plan, &job_dir);
        if let Some(&(s, f)) = missing.first() {
            bail!(
                "{}: {} frames are not rendered yet (first: {} frame {f}); run the remaining \
                 shards (or `blurlab render job` without --shard) first",
                job_dir.display(),
                missing.len(),
                plan.specs[s].id
            );
        }
        report.manifest = Some(finalize_job(job, &plan, &job_dir)?);
        super::lock::remove_stale_temporaries(&job_dir);
    }
    Ok(report)
}

/// Write or check every stimulus's stamp; refuse frames of a different job under the same name.
fn stamp_stimuli(job: &Job, plan: &Plan, job_dir: &Path) -> Result<()> {
    let mut scene_hashes = Vec::new();
    for s in &job.scenes {
        let bytes = std::fs::read(&s.path)
            .with_context(|| format!("cannot read scene {}", s.path.display()))?;
        scene_hashes.push(record::sha256_hex(&bytes));
    }
    for (spec, setup) in plan.specs.iter().zip(&plan.setups) {
        let stamp = StimulusStamp {
            format: STIMULUS_FORMAT.into(),
            id: spec.id.clone(),
            scene: spec.scene.clone(),
            scene_sha256: scene_hashes[spec.scene_index].clone(),
            sampling: spec.sampling.clone(),
            seed: spec.seed,
            width: setup.width,
            height: setup.height,
            first_frame: job.overrides.first_frame.unwrap_or(0),
            assets: job.assets.records(),
        };
        let path = stimulus_dir(job_dir, spec).join("stimulus.json");
        if let Ok(text) = std::fs::read(&path) {
            let old: Option<StimulusStamp> = serde_json::from_slice(&text).ok();
            if old.as_ref() != Some(&stamp) {
                bail!(
                    "{} was rendered from a different job or scene (its seed, sampling, size \
                     or scene file changed). Delete {} (or the whole {}) to render it again, \
                     or give the job another name",
                    path.display(),
                    stimulus_dir(job_dir, spec).display(),
                    job_dir.display()
                );
            }
        } else {
            crate::atomic::write_atomic(&path, &serde_json::to_vec_pretty(&stamp)?)?;
        }
    }
    // The job file as given (`job.json`, or `job.job` for the thesis's text).
    let ext = job
        .path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("json");
    let copy = job_dir.join(format!("job.{ext}"));
    let text = std::fs::read(&job.path)
        .with_context(|| format!("cannot read job file {}", job.path.display()))?;
    crate::atomic::write_atomic(&copy, &text)
}

#[allow(clippy::too_many_arguments)]
fn render_units(
    job: &Job,
    plan: &Plan,
    sources: &[Box<dyn FrameSource>],
    job_dir: &Path,
    mine: &[usize],
    opts: &RunOptions,
    progress: &dyn Progress,
    report: &mut RunReport,
) -> Result<()> {
    // Work out what is left before starting, so the bar's total is right.
    let mut todo: Vec<(usize, u32)> = Vec::new();
    for &u in mine {
        let unit = &plan.units[u];
        let spec = &plan.specs[unit.stimulus];
        let dir = stimulus_dir(job_dir, spec);
        for f in unit.frames.clone() {
            if record::completed(&dir, f, need_exr(job, plan, unit.stimulus)).is_some() {
                report.frames_skipped += 1;
            } else {
                todo.push((unit.stimulus, f));
            }
        }
    }
    let cost = |s: usize| {
        let u = plan.setups[s];
        u.width as u64 * u.height as u64 * plan.specs[s].sampling.spp as u64
    };
    let total: u64 = todo.iter().map(|&(s, _)| cost(s)).sum();
    progress.start(total);
    let mut render = |n: usize, s: usize, f: u32| -> Result<(RenderedFrame, f64)> {
        let spec = &plan.specs[s];
        progress.message(&format!(
            "frame {}/{} of shard {}: {} #{f}",
            n + 1,
            todo.len(),
            opts.shard,
            spec.id
        ));
        let out = render_frame(plan, sources, s, f)?;
        report.frames_rendered += 1;
        progress.advance(cost(s));
        Ok(out)
    };
    // With more than one rayon thread, frame k's files are encoded, measured and written on a
    // writer thread while frame k + 1 is traced. The writer takes frames in order, so what it
    // finds on disk (a reference frame, say) is what the serial loop would have found.
    crate::render::pipeline::make_and_write(
        todo.iter().copied(),
        |n, (s, f)| Ok((s, f, render(n, s, f)?)),
        |(s, f, (rendered, seconds))| write_frame(job, plan, job_dir, s, f, &rendered, seconds),
    )?;
    progress.finish();
    Ok(())
}

/// Render one frame of stimulus `s`; the seconds it took.
fn render_frame(
    plan: &Plan,
    sources: &[Box<dyn FrameSource>],
    s: usize,
    frame: u32,
) -> Result<(RenderedFrame, f64)> {
    let spec = &plan.specs[s];
    let start = Instant::now();
    let rendered = sources[spec.scene_index]
        .render(&spec.sampling, spec.seed, frame)
        .with_context(|| format!("rendering {} frame {frame}", spec.id))?;
    Ok((rendered, start.elapsed().as_secs_f64()))
}

/// Write the files of frame `frame` of stimulus `s`, record last.
fn write_frame(
    job: &Job,
    plan: &Plan,
    job_dir: &Path,
    s: usize,
    frame: u32,
    rendered: &RenderedFrame,
    render_seconds: f64,
) -> Result<()> {
    let spec = &plan.specs[s];
    let setup = plan.setups[s];
    let dir = stimulus_dir(job_dir, spec);
    let png = png_bytes(&rendered.display, setup.width, setup.height)?;
    // Measure now if the reference frame already exists; otherwise keep this frame's linear
    // values (a scratch EXR) so the error can be measured when the job is finalized.
    let error = match plan.reference_of(s) {
        None => None,
        Some(r) => {
            let ref_dir = stimulus_dir(job_dir, &plan.specs[r]);
            match record::completed(&ref_dir, frame, true) {
                Some(_) => Some(measure(rendered, &ref_dir, frame, setup)?),
                None => None,
            }
        }
    };
    let keep_exr = need_exr(job, plan, s) || (error.is_none() && plan.measured(s));
    let mut exr_bytes = None;
    if keep_exr {
        let exr = linear_frame::exr_bytes(&rendered.linear, setup.width, setup.height)?;
        crate::atomic::write_atomic(&names::exr_path(&dir, frame), &exr)?;
        exr_bytes = Some(exr.len() as u64);
    }
    crate::atomic::write_atomic(&names::png_path(&dir, frame), &png)?;
    FrameRecord {
        format: record::FRAME_RECORD_FORMAT.into(),
        frame,
        png_bytes: png.len() as u64,
        png_sha256: record::sha256_hex(&png),
        exr_bytes,
        render_seconds,
        error,
    }
    .save(&dir)
}

/// Every (stimulus, frame) of the job not complete on disk.
fn missing_frames(job: &Job, plan: &Plan, job_dir: &Path) -> Vec<(usize, u32)> {
    let mut out = Vec::new();
    for (s, spec) in plan.specs.iter().enumerate() {
        let dir = stimulus_dir(job_dir, spec);
        for f in 0..plan.setups[s].frames {
            if record::completed(&dir, f, need_exr(job, plan, s)).is_none() {
                out.push((s, f));
            }
        }
    }
    out
}
