//! `blurlab render converge <scene> [--levels ...] [--frames ...]`: whether a scene's stimuli
//! converge in display space (`renderer::display_convergence`): the table, a verdict per point set, and
//! optionally a contact sheet and CSV.

use crate::cli::progress::{Look, Terminal};
use anyhow::{Context, Result, bail};
use clap::Args;
use renderer::condition::{PointSetKind, TimeFilter};
use renderer::contact_sheet::{self, Rect, Tile};
use renderer::display_convergence::{self as dc, Criterion, Plan};
use std::path::PathBuf;

/// Render a scene's levels on a few frames and compare them, as display frames, with a
/// high-density render: does the error fall at every level, by 4x, and leave no speckles?
#[derive(Debug, Args)]
pub struct ConvergeArgs {
    /// The scene file, e.g. scenes/thesis/spheres.json.
    pub scene: PathBuf,
    /// Sampling levels (spp), increasing, separated by commas.
    #[arg(long, value_delimiter = ',', default_value = THESIS_LEVELS,
          value_parser = renderer::limits::parse_spp, allow_hyphen_values = true)]
    pub levels: Vec<u32>,
    /// Point sets to measure, separated by commas.
    #[arg(long, value_delimiter = ',', default_value = THESIS_POINT_SETS)]
    pub point_sets: Vec<PointSetKind>,
    /// Time filter of every render (the thesis's study used the truncated box).
    #[arg(long, default_value = "truncated_box")]
    pub time_filter: TimeFilter,
    /// Samples per pixel of the reference, above the highest level [default: 4 x the highest
    /// level, at most 65536].
    #[arg(long, value_parser = renderer::limits::parse_spp, allow_hyphen_values = true)]
    pub reference_spp: Option<u32>,
    /// Point set of the reference.
    #[arg(long, default_value = "sobol")]
    pub reference_point_set: PointSetKind,
    /// Scene frames to compare, separated by commas [default: four spread over the animation].
    #[arg(long, value_delimiter = ',', value_parser = parse_frame, allow_hyphen_values = true)]
    pub frames: Vec<u32>,
    /// Image width in pixels (default: the scene's).
    #[arg(long, value_parser = renderer::limits::parse_side, allow_hyphen_values = true)]
    pub width: Option<u32>,
    /// Image height in pixels (default: the scene's).
    #[arg(long, value_parser = renderer::limits::parse_side, allow_hyphen_values = true)]
    pub height: Option<u32>,
    /// Master seed of the levels (the reference's is derived from it).
    #[arg(long, default_value_t = 1, value_parser = renderer::limits::parse_seed,
          allow_hyphen_values = true)]
    pub seed: u64,
    /// A pixel differs when a channel is more than this many levels (of 255) off.
    #[arg(long, default_value_t = 32)]
    pub threshold: u8,
    /// Write a contact sheet (PNG): one frame at every level of one point set, then the reference.
    #[arg(long)]
    pub sheet: Option<PathBuf>,
    /// The sheet's frame [default: the first compared].
    #[arg(long)]
    pub sheet_frame: Option<u32>,
    /// The sheet's point set [default: the first measured].
    #[arg(long)]
    pub sheet_point_set: Option<PointSetKind>,
    /// Show only this part of the frame on the sheet: x,y,width,height in pixels.
    #[arg(long)]
    pub sheet_crop: Option<Rect>,
    /// Tiles per row of the sheet.
    #[arg(long, default_value_t = 4)]
    pub sheet_columns: usize,
    /// Also write the rows as CSV.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Exit with an error when a point set does not converge.
    #[arg(long)]
    pub check: bool,
    /// Hide the progress bar.
    #[arg(long)]
    pub no_progress: bool,
    #[command(flatten)]
    pub assets: super::AssetArgs,
}

/// `--levels`' and `--point-sets`' defaults as the flags take them (comma-separated; clap's
/// `default_values_t` would show them space-separated, which does not parse):
/// [`dc::THESIS_LEVELS`] and [`dc::THESIS_POINT_SETS`], checked by a test.
const THESIS_LEVELS: &str = "8,27,64,125,216,343,512";
const THESIS_POINT_SETS: &str = "hammersley,stratified,poisson";

/// A scene frame number of `--frames`.
fn parse_frame(s: &str) -> Result<u32, String> {
    s.trim()
        .parse::<u32>()
        .map_err(|_| format!("`{s}`: expected a frame number from 0"))
}

/// The reference's spp: `--reference-spp`, else 4 x the highest level (within the point sets'
/// largest); it must be above every level, or the levels are judged against a coarser render.
fn reference_spp(args: &ConvergeArgs) -> Result<u32> {
    let top = args.levels.iter().copied().max().unwrap_or(1);
    let spp = args
        .reference_spp
        .unwrap_or_else(|| top.saturating_mul(4).min(renderer::limits::MAX_SPP));
    if spp <= top {
        bail!(
            "--reference-spp is {spp}; expected more samples per pixel than the highest of \
             --levels ({top}): the reference must be finer than every level it judges"
        );
    }
    Ok(spp)
}

pub fn run(args: ConvergeArgs) -> Result<()> {
    let mut scene = super::load_scene(&args.scene, &args.assets)?;
    for (flag, v) in [("--width", args.width), ("--height", args.height)] {
        if v == Some(0) {
            bail!("{flag} must be at least 1");
        }
    }
    let s = &mut scene.settings;
    s.width = args.width.unwrap_or(s.width);
    s.height = args.height.unwrap_or(s.height);
    let n = s.frames;
    let frames = if args.frames.is_empty() {
        (0..4).map(|k| n * (2 * k + 1) / 8).collect()
    } else {
        args.frames.clone()
    };
    let reference_spp = reference_spp(&args)?;
    let plan = Plan {
        levels: args.levels.clone(),
        point_sets: args.point_sets.clone(),
        time_filter: args.time_filter,
        reference_point_set: args.reference_point_set,
        reference_spp,
        frames,
        seed: args.seed,
        threshold: args.threshold,
    };
    let sheet_frame = args.sheet_frame.unwrap_or(plan.frames[0]);
    if args.sheet.is_some() && !plan.frames.contains(&sheet_frame) {
        bail!(
            "--sheet-frame {sheet_frame} is not among the compared frames {:?}",
            plan.frames
        );
    }
    let sheet_set = args.sheet_point_set.unwrap_or(plan.point_sets[0]);
    let bar = Terminal::new(Look::Converge, !args.no_progress);
    let mut tiles: Vec<Result<Tile>> = Vec::new();
    let mut reference_tile = None;
    let rows = dc::measure(&scene, &plan, &bar, |r| {
        if args.sheet.is_none() || r.frame != sheet_frame {
            return;
        }
        let label = match r.point_set {
            None => format!("{} spp {} (reference)", r.spp, plan.reference_point_set),
            Some(ps) if ps == sheet_set => format!("{} spp {ps}", r.spp),
            Some(_) => return,
        };
        let tile = Tile::cut(label, r.display, r.width, r.height, args.sheet_crop);
        match r.point_set {
            None => reference_tile = Some(tile),
            Some(_) => tiles.push(tile),
        }
    })?;
    let verdicts = dc::judge(&rows, &Criterion::thesis());
    println!(
        "{}: {} x {}, frames {:?}, time filter {}, against {} spp {}, seed {}\n",
        args.scene.display(),
        scene.settings.width,
        scene.settings.height,
        plan.frames,
        plan.time_filter,
        plan.reference_spp,
        plan.reference_point_set,
        plan.seed
    );
    print!("{}", dc::markdown(&rows, &verdicts, &plan));
    if let Some(path) = &args.csv {
        dc::write_csv(path, &rows)?;
    }
    if let Some(path) = &args.sheet {
        let mut all = tiles.into_iter().collect::<Result<Vec<_>>>()?;
        all.push(reference_tile.context("the reference frame was not rendered")??);
        contact_sheet::write(path, &all, args.sheet_columns)?;
        println!("\ncontact sheet: {}", path.display());
    }
    if args.check && verdicts.iter().any(|v| !v.pass) {
        bail!(
            "{} does not converge (see the table above)",
            args.scene.display()
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(extra: &[&str]) -> Result<ConvergeArgs, clap::Error> {
        let argv = [&["converge", "scene.json"][..], extra].concat();
        crate::cli::try_parse(&argv)
    }

    #[test]
    fn defaults_are_the_thesis_plan_written_as_the_flags_take_them() {
        let a = parse(&[]).unwrap();
        assert_eq!(a.levels, dc::THESIS_LEVELS);
        assert_eq!(a.point_sets, dc::THESIS_POINT_SETS);
        assert_eq!(reference_spp(&a).unwrap(), 4 * 512);
    }

    #[test]
    fn levels_and_reference_are_checked_naming_the_flag() {
        let e = parse(&["--levels", "0,4"]).err().unwrap().to_string();
        assert!(
            e.contains("--levels") && e.contains("from 1 to 65536"),
            "{e}"
        );
        let e = parse(&["--levels", "-8,27"]).err().unwrap().to_string();
        assert!(e.contains("--levels") && e.contains("`-8`"), "{e}");
        let a = parse(&["--levels", "8,27", "--reference-spp", "16"]).unwrap();
        let e = reference_spp(&a).unwrap_err().to_string();
        assert!(
            e.contains("--reference-spp is 16") && e.contains("(27)"),
            "{e}"
        );
        let a = parse(&["--levels", "65536"]).unwrap();
        assert!(reference_spp(&a).is_err());
        let e = parse(&["--frames", "-1"]).err().unwrap().to_string();
        assert!(e.contains("--frames") && e.contains("frame number"), "{e}");
    }
}
