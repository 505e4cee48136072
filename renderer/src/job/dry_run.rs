//! `render job --dry-run`: a job's work counted and its time estimated from a short
//! calibration render of each scene, without rendering it.

use super::Job;
use super::plan::Plan;
use super::shard::{self, Shard, Unit};
use super::source::FrameSource;
use crate::film::RenderedFrame;
use crate::frame_io::{exr as linear_frame, png::png_bytes};
use crate::metrics::FrameError;
use crate::sampling::SamplingConfig;
use anyhow::Result;
use std::time::Instant;

/// What one scene's frames cost on this machine, wall clock with the job's threads.
#[derive(Clone, Debug)]
pub struct Calibration {
    pub scene: String,
    /// Seconds per camera sample.
    pub per_sample: f64,
    /// Seconds per frame that do not grow with its samples (the world, the frame's sampler,
    /// each pixel's work besides its samples).
    pub per_frame: f64,
    /// Seconds per frame of encoding and metrics, as they add to the job's wall clock (on
    /// the writer thread beside the tracing, with more than one thread).
    pub per_frame_files: f64,
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
    /// Per scene, what its frames cost ([`calibrate`]).
    pub calibration: Vec<Calibration>,
    /// Estimated wall-clock seconds for the whole job / this shard on this machine.
    pub estimated_seconds: f64,
    pub estimated_shard_seconds: f64,
}

/// Count the job's work and estimate its time from short calibration renders of each scene
/// ([`calibrate`]).
pub fn dry_run_with_sources(
    job: &Job,
    sources: &[Box<dyn FrameSource>],
    shard: Shard,
) -> Result<DryRun> {
    let plan = Plan::new(job, sources)?;
    let mine = shard::assign(&plan.units, shard);
    let mut calibration = Vec::new();
    for (scene, src) in job.scenes.iter().zip(sources) {
        calibration.push(calibrate(
            &scene.name,
            src.as_ref(),
            &job.heaviest_sampling(),
        )?);
    }
    let unit_seconds = |u: &Unit| {
        let c = &calibration[plan.specs[u.stimulus].scene_index];
        u.cost as f64 * c.per_sample + u.frames.len() as f64 * (c.per_frame + c.per_frame_files)
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

/// Calibration renders have at most this many pixels: a larger frame is calibrated at this
/// area, its aspect kept.
const MAX_CALIBRATION_PIXELS: f64 = 768.0 * 768.0;

/// The cost of one scene's frames, from renders of its middle frame at the job's frame size
/// (at most [`MAX_CALIBRATION_PIXELS`]) at 1 and [`HIGH_SPP`] samples per pixel: a frame costs
/// `per_frame + samples x per_sample`, the line through the two (best of two runs each).
///
/// Why two densities at the job's own size: a frame's time is not proportional to its samples.
/// Building the world and the frame's sampler, and each pixel's work besides its samples, cost
/// the same at 1 spp as at 512, and a small frame's packets of eight neighbouring pixels are
/// less coherent than a full-size frame's (more of them straddle an edge). The earlier
/// calibration (one 96 x 96 frame at 8 spp, all of its time counted per sample) put those into
/// every sample: on a 384 x 384 job of both thesis scenes it estimated 94 s for a run of 32 s
/// (`docs/benchmarks/lanes.md`, "Method").
fn calibrate(name: &str, src: &dyn FrameSource, reference: &SamplingConfig) -> Result<Calibration> {
    const HIGH_SPP: u32 = 8;
    let setup = src.setup();
    let (width, height) = calibration_size(setup.width, setup.height);
    let sized = src.resized(width, height)?;
    let mid = setup.frames / 2;
    let time = |spp: u32| -> Result<f64> {
        // Joint density: a reference's density split need not divide the calibration's spp.
        let cfg = SamplingConfig {
            spp,
            density: Some(crate::sampling::Density::Joint),
            ..reference.clone()
        };
        let mut best = f64::INFINITY;
        for _ in 0..2 {
            let t = Instant::now();
            sized.render(&cfg, 1, mid)?;
            best = best.min(t.elapsed().as_secs_f64());
        }
        Ok(best)
    };
    let (low, high) = (time(1)?, time(HIGH_SPP)?);
    let pixels = f64::from(width) * f64::from(height);
    let (per_frame, per_sample) = frame_line(low, high, pixels, HIGH_SPP);
    // Scaled to the job's frame size where the calibration's is smaller: the fixed part counted
    // as growing with the pixels (an overestimate for the world's build, which does not).
    let per_frame = per_frame * f64::from(setup.width) * f64::from(setup.height) / pixels;
    Ok(Calibration {
        scene: name.to_string(),
        per_sample,
        per_frame,
        per_frame_files: files_seconds(setup.width, setup.height)? / overlap(),
    })
}

/// The frame size calibration renders at: the job's, or its aspect at
/// [`MAX_CALIBRATION_PIXELS`].
fn calibration_size(width: u32, height: u32) -> (u32, u32) {
    let pixels = f64::from(width) * f64::from(height);
    if pixels <= MAX_CALIBRATION_PIXELS {
        return (width, height);
    }
    let scale = (MAX_CALIBRATION_PIXELS / pixels).sqrt();
    let side = |v: u32| ((f64::from(v) * scale).round() as u32).max(1);
    (side(width), side(height))
}

/// `(per_frame, per_sample)` of the line through a frame's times at 1 spp (`low`) and at
/// `high_spp` (`high`), `pixels` pixels each; neither below zero (a noisy pair can cross).
fn frame_line(low: f64, high: f64, pixels: f64, high_spp: u32) -> (f64, f64) {
    let per_sample = (high - low) / (pixels * f64::from(high_spp - 1));
    if per_sample > 0.0 {
        ((low - pixels * per_sample).max(0.0), per_sample)
    } else {
        // The denser frame came out no slower: all of its time per sample, as if no part
        // were fixed (the safe side).
        (0.0, high / (pixels * f64::from(high_spp)))
    }
}

/// How many times the files' work shrinks in the job's wall clock: with more than one thread,
/// the runner encodes and measures frame k on a writer thread while frame k + 1 traces
/// ([`crate::render::pipeline::make_and_write`]), so that work only takes its share of the
/// cores from the tracing; with one, it runs in turn.
fn overlap() -> f64 {
    rayon::current_num_threads().max(1) as f64
}

/// Per-frame work besides tracing: PNG and EXR encoding and the metrics, at full size, one
/// thread.
fn files_seconds(width: u32, height: u32) -> Result<f64> {
    let n = width as usize * height as usize;
    let frame = RenderedFrame {
        linear: (0..n).map(|i| [(i % 7) as f32 * 0.3, 0.5, 2.0]).collect(),
        display: (0..3 * n).map(|i| (i * 31 % 251) as u8).collect(),
    };
    let other: Vec<u8> = frame.display.iter().map(|v| v.wrapping_add(3)).collect();
    let t = Instant::now();
    png_bytes(&frame.display, width, height)?;
    linear_frame::exr_bytes(&frame.linear, width, height)?;
    FrameError::measure(
        &frame.linear,
        &frame.linear,
        &frame.display,
        &other,
        width,
        height,
    )?;
    Ok(t.elapsed().as_secs_f64())
}

impl std::fmt::Display for DryRun {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "{} stimuli ({} references), {} frames, {:.3e} camera samples, {} units of work",
            self.stimuli, self.references, self.frames, self.samples as f64, self.units
        )?;
        for c in &self.calibration {
            writeln!(
                f,
                "calibration {}: {:.0} samples/s, {:.3} s per frame besides its samples, {:.3} s per frame for encoding and metrics",
                c.scene,
                1.0 / c.per_sample.max(1e-12),
                c.per_frame,
                c.per_frame_files
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Frames timed as `a + b samples` give back `a` and `b`; a noisy pair whose high
    /// density came out faster than its low one counts every second per sample, none per
    /// frame, and no part is ever negative.
    #[test]
    fn the_line_through_two_densities_splits_a_frame_into_fixed_and_per_sample_time() {
        let (a, b, pixels) = (0.02, 3e-7, 768.0 * 768.0);
        let at = |spp: f64| a + b * pixels * spp;
        let (fixed, per_sample) = frame_line(at(1.0), at(8.0), pixels, 8);
        assert!((fixed - a).abs() < 1e-12 && (per_sample - b).abs() < 1e-18);
        let (fixed, per_sample) = frame_line(0.5, 0.4, pixels, 8);
        assert_eq!(fixed, 0.0);
        assert!((per_sample - 0.4 / (8.0 * pixels)).abs() < 1e-18);
        let (fixed, per_sample) = frame_line(0.001, 1.0, 10.0, 8);
        assert!(fixed == 0.0 && per_sample > 0.0);
    }

    /// Frames up to 768 x 768 are calibrated at their own size, larger ones at that area with
    /// their aspect.
    #[test]
    fn calibration_renders_the_jobs_size_up_to_a_cap() {
        assert_eq!(calibration_size(768, 768), (768, 768));
        assert_eq!(calibration_size(12, 8), (12, 8));
        let (w, h) = calibration_size(3840, 2160);
        assert!((f64::from(w) / f64::from(h) - 16.0 / 9.0).abs() < 0.01);
        assert!(f64::from(w) * f64::from(h) <= 768.0 * 768.0 * 1.01);
    }
}
