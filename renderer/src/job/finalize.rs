//! Finishing a job: measuring frames rendered before their reference existed, checking every
//! frame's content against its record, and writing the manifest; and measuring one frame
//! against its reference (also done by the runner as frames are written).

use super::Job;
use super::frame_record::{self as record, FrameRecord};
use super::plan::{Plan, need_exr, stimulus_dir};
use super::source::FrameSetup;
use crate::film::RenderedFrame;
use crate::frame_io::{exr as linear_frame, names};
use crate::manifest::{self, Manifest};
use crate::metrics::{ErrorAccumulator, FrameError};
use anyhow::{Context, Result, bail};
use std::path::Path;

/// Error of a frame against the reference frame stored in `ref_dir`.
pub(super) fn measure(
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

/// Measure what is left to measure, check every frame's content, and write the manifest.
pub(super) fn finalize_job(job: &Job, plan: &Plan, job_dir: &Path) -> Result<Manifest> {
    let mut m = Manifest::new(&job.name);
    m.assets = job.assets.records();
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
            point_set: spec.sampling.point_set,
            time_filter: spec.sampling.time_filter,
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
