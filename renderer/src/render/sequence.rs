//! Rendering a run of frames to disk: each frame is written (PNG, and EXR on request) as soon
//! as it is done (on a writer thread, overlapping the next frame's tracing), to a temporary name
//! then renamed, reporting progress in samples and the frame under way ([`crate::progress`];
//! `render scene` shows frames done, samples per second and the time left).

use super::{FrameStats, render_frame};
use crate::atomic::write_atomic;
use crate::film::Film;
use crate::frame_io::exr::exr_bytes;
use crate::frame_io::names::{exr_path, png_path};
use crate::frame_io::png::png_bytes;
use crate::progress::Progress;
use crate::sampling::SamplingConfig;
use crate::scene::Scene;
use anyhow::{Context, Result};
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
}

/// What a run did.
#[derive(Clone, Copy, Debug, Default)]
pub struct SequenceReport {
    pub frames: u32,
    pub stats: FrameStats,
    /// Wall-clock seconds spent rendering (not encoding).
    pub render_seconds: f64,
}

/// Render `opts.frames` of `scene` with `sampling`, writing each frame when it is done;
/// `progress` counts samples and names the frame being rendered.
///
/// With more than one rayon thread, developing, encoding and writing frame N runs on a writer
/// thread while frame N + 1 is traced (a channel of one frame between them, so at most three
/// frames are in memory); frames are still written in order, each atomically. With one rayon
/// thread everything stays on the calling thread, so one thread means one core.
pub fn render_sequence(
    scene: &Scene,
    sampling: &SamplingConfig,
    opts: &SequenceOptions,
    progress: &dyn Progress,
) -> Result<SequenceReport> {
    let s = &scene.settings;
    let per_frame = s.width as u64 * s.height as u64 * sampling.spp as u64;
    let count = opts.frames.len() as u32;
    progress.start(per_frame * count as u64);
    let mut report = SequenceReport::default();
    let mut render = |n: usize, frame: u32| -> Result<Film> {
        progress.message(&format!("frame {}/{count} (scene frame {frame})", n + 1));
        let start = Instant::now();
        let (film, stats) = render_frame(scene, sampling, opts.seed, frame, progress)
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
    progress.finish();
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
