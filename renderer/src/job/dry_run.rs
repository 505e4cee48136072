//! `render job --dry-run`: a job's work counted and its time estimated from a short
//! calibration render of each scene, without rendering it.

use super::Job;
use super::runner::Plan;
use super::shard::{self, Shard, Unit};
use super::source::FrameSource;
use crate::film::RenderedFrame;
use crate::frame_io::{exr as linear_frame, png::png_bytes};
use crate::metrics::FrameError;
use crate::sampling::SamplingConfig;
use anyhow::Result;
use std::time::Instant;

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
