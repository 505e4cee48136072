//! Rendering a run of frames to disk: each frame is written (PNG, and EXR on request) as soon
//! as it is done (on a writer thread, overlapping the next frame's tracing), to a temporary name then renamed, under a progress bar showing frames done,
//! samples per second and the time left.

use super::{FrameStats, render_frame};
use crate::atomic::write_atomic;
use crate::film::Film;
use crate::frame_io::exr::exr_bytes;
use crate::frame_io::names::{exr_path, png_path};
use crate::frame_io::png::png_bytes;
use crate::sampling::SamplingConfig;
use crate::scene::Scene;
use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressState, ProgressStyle};
use std::ops::Range;
use std::path::PathBuf;
use std::time::Instant;

/// What to render and where.
#[derive(Clone, Debug)]
pub struct SequenceOptions {
    /// Frames land in `out_dir/frame_NNNN.png` (NNNN: the scene frame number).
    pub out_dir: PathBuf,
    /// Scene frames to render.
    pub frames: Range<u32>,
    pub seed: u64,
    /// Also write 32-bit float linear `frame_NNNN.exr`.
    pub exr: bool,
    pub progress: bool,
}

/// What a run did.
#[derive(Clone, Copy, Debug, Default)]
pub struct SequenceReport {
    pub frames: u32,
    pub stats: FrameStats,
    /// Wall-clock seconds spent rendering (not encoding).
    pub render_seconds: f64,
}

/// Render `opts.frames` of `scene` with `sampling`, writing each frame when it is done.
///
/// With more than one rayon thread, developing, encoding and writing frame N runs on a writer
/// thread while frame N + 1 is traced (a channel of one frame between them, so at most three
/// frames are in memory); frames are still written in order, each atomically. With one rayon
/// thread everything stays on the calling thread, so one thread means one core.
pub fn render_sequence(
    scene: &Scene,
    sampling: &SamplingConfig,
    opts: &SequenceOptions,
) -> Result<SequenceReport> {
    let s = &scene.settings;
    let per_frame = s.width as u64 * s.height as u64 * sampling.spp as u64;
    let count = opts.frames.len() as u32;
    let bar = progress_bar(opts.progress, per_frame * count as u64);
    let mut report = SequenceReport::default();
    let mut render = |n: usize, frame: u32| -> Result<Film> {
        bar.set_message(format!("frame {}/{count} (scene frame {frame})", n + 1));
        let start = Instant::now();
        let (film, stats) = render_frame(scene, sampling, opts.seed, frame, Some(&bar))
            .with_context(|| format!("rendering frame {frame} of {}", scene.path.display()))?;
        report.render_seconds += start.elapsed().as_secs_f64();
        report.stats += stats;
        report.frames += 1;
        Ok(film)
    };
    super::pipeline::make_and_write(
        opts.frames.clone(),
        |n, frame| Ok((frame, render(n, frame)?)),
        |(frame, film)| write_frame(scene, opts, frame, &film),
    )?;
    bar.finish_and_clear();
    Ok(report)
}

/// Develop `film` and write its PNG (and EXR on request) under `opts.out_dir`.
fn write_frame(scene: &Scene, opts: &SequenceOptions, frame: u32, film: &Film) -> Result<()> {
    let s = &scene.settings;
    let developed = film.develop(s.exposure);
    let png = png_bytes(&developed.display, s.width, s.height)?;
    write_atomic(&png_path(&opts.out_dir, frame), &png)?;
    if opts.exr {
        let exr = exr_bytes(&developed.linear, s.width, s.height)?;
        write_atomic(&exr_path(&opts.out_dir, frame), &exr)?;
    }
    Ok(())
}

fn progress_bar(show: bool, total_samples: u64) -> ProgressBar {
    if !show {
        return ProgressBar::hidden();
    }
    let style = ProgressStyle::with_template(
        "{elapsed_precise} [{bar:30}] {percent:>3}% {msg} | {rate} | eta {eta}",
    )
    .unwrap_or_else(|_| ProgressStyle::default_bar())
    .with_key(
        "rate",
        |state: &ProgressState, w: &mut dyn std::fmt::Write| {
            let _ = write!(w, "{:.2} M samples/s", state.per_sec() / 1e6);
        },
    )
    .progress_chars("=> ");
    ProgressBar::new(total_samples).with_style(style)
}
