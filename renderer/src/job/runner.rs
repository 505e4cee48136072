//! Rendering a job into `<out>/<job>/`: one folder per stimulus holding `frame_NNNN.png`
//! (display), `frame_NNNN.exr` (linear; references always, others on request) and
//! `frame_NNNN.json` (the frame's record, written last), plus `stimulus.json` (what the
//! stimulus is, to refuse mixing frames of a changed job) and, once every frame of the job
//! exists, `manifest.json`.
//!
//! Resume is per frame: a frame counts as done when its record exists and the files it names
//! have the recorded sizes; everything else is rendered again. Every file is written to a
//! temporary name and renamed, so an interrupted run leaves whole files or none.

use super::expand::StimulusSpec;
use super::frame_record::{self as record, FrameRecord};
use super::shard::{self, Shard, Unit};
use super::source::{FrameSetup, FrameSource};
use super::{Job, expand};
use crate::film::RenderedFrame;
use crate::frame_io::{exr as linear_frame, names, png::png_bytes};
use crate::manifest::{self, Manifest};
use crate::metrics::{ErrorAccumulator, FrameError};
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
    /// Show an overall progress bar on stderr.
    pub progress: bool,
    pub finalize: Finalize,
}

impl RunOptions {
    /// The whole job into `out_dir`, with progress, finalizing at the end.
    pub fn new(out_dir: impl Into<PathBuf>) -> Self {
        Self {
            out_dir: out_dir.into(),
            shard: Shard::WHOLE,
            progress: true,
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
}

/// The job, expanded and sized.
pub(crate) struct Plan {
    pub specs: Vec<StimulusSpec>,
    /// Per stimulus: its scene's setup (with the job's overrides applied by the source).
    pub setups: Vec<FrameSetup>,
    pub units: Vec<Unit>,
    /// Per stimulus: some stimulus is measured against it (its frames keep EXR copies and are
    /// rendered first within a shard).
    pub serves_as_reference: Vec<bool>,
}

impl Plan {
    pub fn new(job: &Job, sources: &[Box<dyn FrameSource>]) -> Result<Self> {
        if sources.len() != job.scenes.len() {
            bail!(
                "{} scenes but {} frame sources",
                job.scenes.len(),
                sources.len()
            );
        }
        let specs = expand(job);
        let setups: Vec<FrameSetup> = specs
            .iter()
            .map(|s| sources[s.scene_index].setup())
            .collect();
        let serves_as_reference: Vec<bool> = specs
            .iter()
            .map(|s| s.reference || specs.iter().any(|o| o.reference_id.as_ref() == Some(&s.id)))
            .collect();
        let sizes: Vec<(u32, u64, bool)> = specs
            .iter()
            .zip(&setups)
            .zip(&serves_as_reference)
            .map(|((s, u), &r)| {
                let per_frame = u.width as u64 * u.height as u64 * s.sampling.spp as u64;
                (u.frames, per_frame, r)
            })
            .collect();
        let units = shard::units(&sizes, job.frames_per_unit);
        Ok(Self {
            specs,
            setups,
            units,
            serves_as_reference,
        })
    }

    /// The stimulus that stimulus `i` is measured against, unless it has none to be measured
    /// against (an independent reference, or its own reference).
    fn reference_of(&self, i: usize) -> Option<usize> {
        let spec = &self.specs[i];
        if spec.own_reference() {
            return None;
        }
        let id = spec.reference_id.as_ref()?;
        self.specs.iter().position(|s| &s.id == id)
    }

    /// Whether stimulus `i`'s frames get an error against a reference.
    fn measured(&self, i: usize) -> bool {
        self.reference_of(i).is_some()
    }
}

/// Render (this shard of) a job whose scenes are given as frame sources, one per
/// `job.scenes` entry, then finalize if every frame exists (per `opts.finalize`).
pub fn run_with_sources(
    job: &Job,
    sources: &[Box<dyn FrameSource>],
    opts: &RunOptions,
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
    };
    if opts.finalize != Finalize::Only {
        let mine = shard::assign(&plan.units, opts.shard);
        render_units(job, &plan, sources, &job_dir, &mine, opts, &mut report)?;
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
                 shards (or `render job` without --shard) first",
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

fn stimulus_dir(job_dir: &Path, spec: &StimulusSpec) -> PathBuf {
    job_dir.join(&spec.id)
}

/// Whether stimulus `s` keeps EXR frames: references (to measure others against) and, on
/// request, every stimulus.
fn need_exr(job: &Job, plan: &Plan, s: usize) -> bool {
    plan.serves_as_reference[s] || job.keep_exr()
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

fn render_units(
    job: &Job,
    plan: &Plan,
    sources: &[Box<dyn FrameSource>],
    job_dir: &Path,
    mine: &[usize],
    opts: &RunOptions,
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
    let bar = progress_bar(opts.progress, total);
    let mut render = |n: usize, s: usize, f: u32| -> Result<(RenderedFrame, f64)> {
        let spec = &plan.specs[s];
        bar.set_message(format!(
            "frame {}/{} of shard {}: {} #{f}",
            n + 1,
            todo.len(),
            opts.shard,
            spec.id
        ));
        let out = render_frame(plan, sources, s, f)?;
        report.frames_rendered += 1;
        bar.inc(cost(s));
        Ok(out)
    };
    // With more than one rayon thread, frame k's files are encoded, measured and written on a
    // writer thread while frame k + 1 is traced. The writer takes frames in order, so what it
    // finds on disk (a reference frame, say) is what the serial loop would have found.
    if rayon::current_num_threads() <= 1 {
        for (n, &(s, f)) in todo.iter().enumerate() {
            let (rendered, seconds) = render(n, s, f)?;
            write_frame(job, plan, job_dir, s, f, &rendered, seconds)?;
        }
    } else {
        let (send, receive) = std::sync::mpsc::sync_channel::<(usize, u32, RenderedFrame, f64)>(1);
        std::thread::scope(|threads| -> Result<()> {
            let writer = threads.spawn(move || -> Result<()> {
                for (s, f, rendered, seconds) in receive {
                    write_frame(job, plan, job_dir, s, f, &rendered, seconds)?;
                }
                Ok(())
            });
            let rendered = (|| -> Result<()> {
                for (n, &(s, f)) in todo.iter().enumerate() {
                    let (rendered, seconds) = render(n, s, f)?;
                    if send.send((s, f, rendered, seconds)).is_err() {
                        // The writer stopped on an error, which its join below returns.
                        break;
                    }
                }
                Ok(())
            })();
            drop(send);
            let written = writer
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            written.and(rendered)
        })?;
    }
    bar.finish_and_clear();
    Ok(())
}

fn progress_bar(show: bool, total: u64) -> indicatif::ProgressBar {
    if !show {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(total);
    let style = indicatif::ProgressStyle::with_template(
        "{elapsed_precise} [{bar:30}] {percent:>3}% of samples, eta {eta} | {msg}",
    )
    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
    .progress_chars("=> ");
    bar.set_style(style);
    bar
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

/// Error of a frame against the reference frame stored in `ref_dir`.
fn measure(
    test: &RenderedFrame,
    ref_dir: &Path,
    frame: u32,
    setup: FrameSetup,
) -> Result<FrameError> {
    let (ref_linear, w, h) = linear_frame::read_exr(&names::exr_path(ref_dir, frame))?;
    let png_path = names::png_path(ref_dir, frame);
    let ref_display = image::open(&png_path)
        .with_context(|| format!("cannot read reference frame {}", png_path.display()))?
        .to_rgb8();
    if (w, h) != (setup.width, setup.height) || ref_display.dimensions() != (w, h) {
        bail!(
            "reference frame {} is {w}x{h}, the stimulus {}x{}",
            png_path.display(),
            setup.width,
            setup.height
        );
    }
    FrameError::measure(
        &test.linear,
        &ref_linear,
        &test.display,
        ref_display.as_raw(),
        w,
        h,
    )
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

/// Measure what is left to measure, check every frame's content, and write the manifest.
fn finalize_job(job: &Job, plan: &Plan, job_dir: &Path) -> Result<Manifest> {
    let mut m = Manifest::new(&job.name);
    for (s, spec) in plan.specs.iter().enumerate() {
        let setup = plan.setups[s];
        let dir = stimulus_dir(job_dir, spec);
        let mut hasher = manifest::ContentHash::new();
        let mut seconds = 0.0;
        let mut acc = ErrorAccumulator::default();
        let mut frame_paths = Vec::new();
        let mut exr_paths = Vec::new();
        for f in 0..setup.frames {
            let mut rec = record::completed(&dir, f, need_exr(job, plan, s))
                .with_context(|| format!("{} frame {f} disappeared", spec.id))?;
            if plan.measured(s) && rec.error.is_none() {
                rec = measure_late(job, plan, job_dir, s, rec)?;
            }
            let png = std::fs::read(names::png_path(&dir, f))?;
            if record::sha256_hex(&png) != rec.png_sha256 {
                bail!(
                    "{}: content differs from when it was rendered (corrupted?). Delete it \
                     and rerun the job to render it again",
                    names::png_path(&dir, f).display()
                );
            }
            hasher.add_frame(&png);
            seconds += rec.render_seconds;
            if let Some(e) = &rec.error {
                acc.add(e);
            }
            frame_paths.push(format!("{}/{}", spec.id, names::png_name(f)));
            if need_exr(job, plan, s) {
                exr_paths.push(format!("{}/{}", spec.id, names::exr_name(f)));
            }
        }
        super::lock::remove_stale_temporaries(&dir);
        m.stimuli.push(manifest::Stimulus {
            id: spec.id.clone(),
            scene: spec.scene.clone(),
            point_set: spec.sampling.point_set.clone(),
            time_filter: spec.sampling.time_filter.clone(),
            spp: spec.sampling.spp,
            reference: spec.reference,
            reference_id: spec.reference_id.clone(),
            seed: spec.seed,
            width: setup.width,
            height: setup.height,
            frames: setup.frames,
            fps: setup.fps,
            frame_paths,
            exr_paths,
            content_hash: hasher.finish(),
            render_seconds: seconds,
            error: if plan.measured(s) { acc.finish() } else { None },
        });
    }
    m.save(job_dir)?;
    // Hand back what readers will see: serde_json's default float parsing may differ from the
    // written value in the last bit.
    Manifest::load(job_dir)
}

/// Measure a frame rendered before its reference existed, from its scratch EXR.
fn measure_late(
    job: &Job,
    plan: &Plan,
    job_dir: &Path,
    s: usize,
    mut rec: FrameRecord,
) -> Result<FrameRecord> {
    let spec = &plan.specs[s];
    let dir = stimulus_dir(job_dir, spec);
    let f = rec.frame;
    let exr = names::exr_path(&dir, f);
    let linear = match linear_frame::read_exr(&exr) {
        Ok((px, _, _)) => px,
        // Another finalizer may have measured it and removed the scratch file meanwhile.
        Err(e) => match FrameRecord::load(&dir, f).filter(|r| r.error.is_some()) {
            Some(r) => return Ok(r),
            None => return Err(e),
        },
    };
    let display = image::open(names::png_path(&dir, f))?.to_rgb8().into_raw();
    let frame = RenderedFrame { linear, display };
    let r = plan
        .reference_of(s)
        .context("a measured stimulus has a reference")?;
    let ref_dir = stimulus_dir(job_dir, &plan.specs[r]);
    rec.error = Some(measure(&frame, &ref_dir, f, plan.setups[s])?);
    let scratch = !need_exr(job, plan, s);
    if scratch {
        rec.exr_bytes = None;
    }
    rec.save(&dir)?;
    if scratch {
        let _ = std::fs::remove_file(&exr);
    }
    Ok(rec)
}

/// Counts and a time estimate for a job, without rendering it.
#[derive(Clone, Debug)]
pub struct DryRun {
    pub stimuli: usize,
    pub references: usize,
    pub frames: u64,
    /// Camera samples (pixels x spp x frames) over all stimuli.
    pub samples: u64,
    pub units: usize,
    /// Units of the requested shard.
    pub shard_units: usize,
    pub shard_samples: u64,
    /// Per scene: name, measured seconds per camera sample, seconds per frame of overhead
    /// (encoding, metrics).
    pub calibration: Vec<(String, f64, f64)>,
    /// Estimated wall-clock seconds for the whole job / this shard on this machine.
    pub estimated_seconds: f64,
    pub estimated_shard_seconds: f64,
}

/// Count the job's work and estimate its time from a short calibration render of each scene
/// (a 96x96 middle frame at 8 spp, best of two, plus one full-size frame's encoding and
/// metrics).
pub fn dry_run_with_sources(
    job: &Job,
    sources: &[Box<dyn FrameSource>],
    shard: Shard,
) -> Result<DryRun> {
    let plan = Plan::new(job, sources)?;
    let mine = shard::assign(&plan.units, shard);
    let mut calibration = Vec::new();
    for (scene, src) in job.scenes.iter().zip(sources) {
        let (per_sample, per_frame) = calibrate(src.as_ref(), &job.heaviest_sampling())?;
        calibration.push((scene.name.clone(), per_sample, per_frame));
    }
    let unit_seconds = |u: &Unit| {
        let (_, per_sample, per_frame) = &calibration[plan.specs[u.stimulus].scene_index];
        u.cost as f64 * per_sample + u.frames.len() as f64 * per_frame
    };
    Ok(DryRun {
        stimuli: plan.specs.len(),
        references: plan.specs.iter().filter(|s| s.reference).count(),
        frames: plan.setups.iter().map(|s| s.frames as u64).sum(),
        samples: plan.units.iter().map(|u| u.cost).sum(),
        units: plan.units.len(),
        shard_units: mine.len(),
        shard_samples: mine.iter().map(|&u| plan.units[u].cost).sum(),
        estimated_seconds: plan.units.iter().map(unit_seconds).sum(),
        estimated_shard_seconds: mine.iter().map(|&u| unit_seconds(&plan.units[u])).sum(),
        calibration,
    })
}

fn calibrate(src: &dyn FrameSource, reference: &SamplingConfig) -> Result<(f64, f64)> {
    const SIZE: u32 = 96;
    const SPP: u32 = 8;
    let setup = src.setup();
    let small = src.resized(SIZE, SIZE)?;
    // Joint density: a reference's density split need not divide the calibration's 8 spp.
    let cfg = SamplingConfig {
        spp: SPP,
        density: Some(crate::sampling::Density::Joint),
        ..reference.clone()
    };
    let mid = setup.frames / 2;
    let mut best = f64::INFINITY;
    for _ in 0..2 {
        let t = Instant::now();
        small.render(&cfg, 1, mid)?;
        best = best.min(t.elapsed().as_secs_f64());
    }
    let per_sample = best / (SIZE * SIZE * SPP) as f64;
    // Per-frame work besides tracing: PNG and EXR encoding and the metrics, at full size.
    let n = setup.width as usize * setup.height as usize;
    let frame = RenderedFrame {
        linear: (0..n).map(|i| [(i % 7) as f32 * 0.3, 0.5, 2.0]).collect(),
        display: (0..3 * n).map(|i| (i * 31 % 251) as u8).collect(),
    };
    let other: Vec<u8> = frame.display.iter().map(|v| v.wrapping_add(3)).collect();
    let t = Instant::now();
    png_bytes(&frame.display, setup.width, setup.height)?;
    linear_frame::exr_bytes(&frame.linear, setup.width, setup.height)?;
    FrameError::measure(
        &frame.linear,
        &frame.linear,
        &frame.display,
        &other,
        setup.width,
        setup.height,
    )?;
    Ok((per_sample, t.elapsed().as_secs_f64()))
}

impl std::fmt::Display for DryRun {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "{} stimuli ({} references), {} frames, {:.3e} camera samples, {} units of work",
            self.stimuli, self.references, self.frames, self.samples as f64, self.units
        )?;
        for (scene, per_sample, per_frame) in &self.calibration {
            writeln!(
                f,
                "calibration {scene}: {:.0} samples/s, {:.3} s per frame for encoding and metrics",
                1.0 / per_sample.max(1e-12),
                per_frame
            )?;
        }
        writeln!(
            f,
            "estimated time on this machine: {}",
            human_seconds(self.estimated_seconds)
        )?;
        if self.shard_units != self.units {
            writeln!(
                f,
                "this shard: {} units, {:.3e} samples, about {}",
                self.shard_units,
                self.shard_samples as f64,
                human_seconds(self.estimated_shard_seconds)
            )?;
        }
        Ok(())
    }
}

/// `3h 05m`, `4m 10s`, `12.3 s`.
pub fn human_seconds(s: f64) -> String {
    if !s.is_finite() {
        return "unknown".into();
    }
    let whole = s.round() as u64;
    if whole >= 3600 {
        format!("{}h {:02}m ({s:.0} s)", whole / 3600, whole % 3600 / 60)
    } else if whole >= 60 {
        format!("{}m {:02}s", whole / 60, whole % 60)
    } else {
        format!("{s:.1} s")
    }
}
