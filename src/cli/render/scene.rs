//! `blurlab render scene <scene.json | scene.scene> --spp N --out DIR [--frames a..b] [--exr]`: render a scene's
//! frames with its own settings (or the sampling given here) into a folder.

use crate::cli::progress::{Look, Terminal};
use anyhow::{Result, bail};
use clap::Args;
use renderer::condition::{PointSetKind, TimeFilter};
use renderer::render::sequence::{SequenceOptions, render_sequence};
use std::ops::Range;
use std::path::PathBuf;

/// Render the frames of a scene (JSON blurlab-scene/1, or the thesis's block text ending in
/// .scene) to DIR/frame_NNNN.png.
#[derive(Debug, Args)]
pub struct SceneArgs {
    /// The scene file, e.g. scenes/thesis/plane.json or a thesis .scene.
    pub scene: PathBuf,
    /// Output folder (created if needed).
    #[arg(long)]
    pub out: PathBuf,
    /// Samples per pixel (default: the scene's settings.sampling.spp).
    #[arg(long, value_parser = renderer::limits::parse_spp, allow_hyphen_values = true)]
    pub spp: Option<u32>,
    /// Point set (default: the scene's).
    #[arg(long)]
    pub point_set: Option<PointSetKind>,
    /// Time filter (default: the scene's).
    #[arg(long)]
    pub time_filter: Option<TimeFilter>,
    /// Scene frames to render: `a..b` (b excluded), `a..=b`, or one frame `n`
    /// (default: all of the scene's frames).
    #[arg(long, value_parser = parse_frames, allow_hyphen_values = true)]
    pub frames: Option<Range<u32>>,
    /// Also write 32-bit float linear EXR frames.
    #[arg(long)]
    pub exr: bool,
    /// Master seed of the samplers' random choices.
    #[arg(long, default_value_t = 1, value_parser = renderer::limits::parse_seed,
          allow_hyphen_values = true)]
    pub seed: u64,
    /// Image width in pixels (default: the scene's).
    #[arg(long, value_parser = renderer::limits::parse_side, allow_hyphen_values = true)]
    pub width: Option<u32>,
    /// Image height in pixels (default: the scene's).
    #[arg(long, value_parser = renderer::limits::parse_side, allow_hyphen_values = true)]
    pub height: Option<u32>,
    /// Hide the progress bar.
    #[arg(long)]
    pub no_progress: bool,
    #[command(flatten)]
    pub assets: super::AssetArgs,
}

/// `a..b`, `a..=b` or `n`.
pub fn parse_frames(s: &str) -> Result<Range<u32>, String> {
    let num = |t: &str| {
        t.trim().parse::<u32>().map_err(|_| {
            format!("`{s}`: expected frames as a..b, a..=b or n, with frame numbers from 0")
        })
    };
    let r = if let Some((a, b)) = s.split_once("..=") {
        num(a)?..num(b)?.saturating_add(1)
    } else if let Some((a, b)) = s.split_once("..") {
        num(a)?..num(b)?
    } else {
        let n = num(s)?;
        n..n.saturating_add(1)
    };
    if r.is_empty() {
        return Err(format!("`{s}` holds no frame"));
    }
    Ok(r)
}

pub fn run(args: SceneArgs) -> Result<()> {
    let mut scene = super::load_scene(&args.scene, &args.assets)?;
    let s = &mut scene.settings;
    for (flag, v) in [("--width", args.width), ("--height", args.height)] {
        if v == Some(0) {
            bail!("{flag} must be at least 1");
        }
    }
    s.width = args.width.unwrap_or(s.width);
    s.height = args.height.unwrap_or(s.height);
    let mut sampling = s.sampling.clone();
    if let Some(spp) = args.spp {
        sampling.spp = spp;
    }
    if let Some(p) = args.point_set {
        sampling.point_set = p;
    }
    if let Some(f) = args.time_filter {
        sampling.time_filter = f;
    }
    let frames = args.frames.clone().unwrap_or(0..s.frames);
    if frames.end > s.frames {
        bail!(
            "--frames {}..{}: {} has frames 0..{} (settings.frames = {})",
            frames.start,
            frames.end,
            args.scene.display(),
            s.frames,
            s.frames
        );
    }
    let opts = SequenceOptions {
        out_dir: args.out.clone(),
        frames,
        seed: args.seed,
        exr: args.exr,
    };
    let bar = Terminal::new(Look::Sequence, !args.no_progress);
    let report = render_sequence(&scene, &sampling, &opts, &bar)?;
    let secs = report.render_seconds.max(1e-9);
    println!(
        "{}: {} frames of {}x{} at {} spp in {:.2} s ({:.2} M samples/s, {:.2} M rays/s)",
        args.out.display(),
        report.frames,
        scene.settings.width,
        scene.settings.height,
        sampling.spp,
        report.render_seconds,
        report.stats.samples as f64 / secs / 1e6,
        report.stats.rays as f64 / secs / 1e6,
    );
    if report.stats.non_finite > 0 {
        eprintln!(
            "warning: {} samples were NaN or infinite and counted as black (a renderer bug: \
             please report it with the scene)",
            report.stats.non_finite
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_ranges_parse_in_three_forms() {
        assert_eq!(parse_frames("3..7"), Ok(3..7));
        assert_eq!(parse_frames("3..=7"), Ok(3..8));
        assert_eq!(parse_frames("5"), Ok(5..6));
        assert!(parse_frames("7..3").is_err());
        assert!(parse_frames("a..b").is_err());
    }
}
