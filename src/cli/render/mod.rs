//! `blurlab render`: the renderer's subcommands, one file each, over the `renderer` library.

pub mod assets;
pub mod converge;
pub mod convert;
pub mod export;
pub mod job;
pub mod pointsets;
pub mod report;
pub mod scene;

use anyhow::Result;
use clap::{Args, Subcommand};
use renderer::assets::Assets;
use renderer::scene::Scene;
use std::path::Path;

/// The `--asset` flag of the subcommands that load scenes (`scene`, `job`, `converge`).
#[derive(Debug, Args)]
pub struct AssetArgs {
    /// Read the file NAME that a scene names (e.g. its environment map) from PATH instead of
    /// the scene's folder: `--asset CedarCity.hdr=/data/CedarCity.hdr` renders the thesis's
    /// scenes under your copy of the thesis's sky, which the suite cannot ship. A .hdr must be
    /// a Radiance RGBE lat-long map (twice as wide as high). Repeat for several files; each
    /// is recorded with its SHA-256 (in the manifest of `render job`).
    #[arg(long = "asset", value_name = "NAME=PATH")]
    pub asset: Vec<String>,
}

impl AssetArgs {
    /// The assets named, each checked and hashed; printed with their hashes.
    pub fn assets(&self) -> Result<Assets> {
        let assets = Assets::from_flags(&self.asset, "--asset")?;
        for a in assets.list() {
            println!(
                "asset {}: {} (sha256 {})",
                a.name,
                a.path.display(),
                a.sha256
            );
        }
        Ok(assets)
    }
}

/// Load a scene with the assets of `flags`, printing its loading warnings.
pub fn load_scene(path: &Path, flags: &AssetArgs) -> Result<Scene> {
    let scene = Scene::load_with(path, &flags.assets()?)?;
    print_warnings(&scene.warnings);
    Ok(scene)
}

/// Problems that did not stop the work, one line each on standard error.
pub fn print_warnings(warnings: &[String]) {
    for w in warnings {
        eprintln!("warning: {w}");
    }
}

/// Renderer subcommands.
#[derive(Debug, Subcommand)]
pub enum RenderCommand {
    /// Render a stimulus job (scenes/<study>/job.json, or a thesis .job) into stimuli/<job>/:
    /// resumable, shardable.
    Job(job::JobArgs),
    /// Error against spp and render time of a rendered job: CSV and log-log plots.
    Report(report::ReportArgs),
    /// Stimuli of a rendered job as videos (Y4M; FFV1 or H.264 through ffmpeg).
    Export(export::ExportArgs),
    /// Regenerate the procedural models and environment maps under scenes/.
    Assets(assets::AssetsArgs),
    /// Render a scene's frames (scenes/*.json, or a thesis .scene) into a folder of PNG (and
    /// EXR) files.
    Scene(scene::SceneArgs),
    /// Convert a scene or job between JSON and the thesis's text formats (.scene, .job).
    Convert(convert::ConvertArgs),
    /// Whether a scene's stimuli converge: every level against a 4x render, as display frames.
    Converge(converge::ConvergeArgs),
    /// Measure a point set (discrepancy, spacing) and plot its 2D projections (thesis Figure 4).
    Pointsets(pointsets::PointsetsArgs),
}

/// Run one renderer subcommand.
pub fn run(cmd: RenderCommand) -> Result<()> {
    match cmd {
        RenderCommand::Job(a) => job::run(a),
        RenderCommand::Report(a) => report::run(a),
        RenderCommand::Export(a) => export::run(a),
        RenderCommand::Assets(a) => assets::run(a),
        RenderCommand::Scene(a) => scene::run(a),
        RenderCommand::Pointsets(a) => pointsets::run(a),
        RenderCommand::Convert(a) => convert::run(a),
        RenderCommand::Converge(a) => converge::run(a),
    }
}
