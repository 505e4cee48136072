//! The session window (feature `gui`): eframe with the glow renderer, full screen without
//! decorations, dithering off (stimulus pixels must reach the screen unchanged).

mod loader;
mod screens;
mod session_app;
mod video_painter;

pub use session_app::{Pacing, SessionApp};

use crate::cli::{RunArgs, sessions_dir};
use crate::design::Design;
use crate::log_writer::Durability;
use crate::preflight::{PreflightOptions, preflight};
use crate::session::Session;
use anyhow::{Context, Result};

/// `run`: preflight, open (or continue) the subject's log, then the window.
pub fn launch(args: &RunArgs) -> Result<()> {
    let design = Design::load(&args.design)?;
    let report = preflight(
        &design,
        PreflightOptions {
            check_hashes: !args.skip_hash_check,
            progress: true,
        },
    );
    let manifest_path = report.manifest_path.clone();
    let manifest = report.into_result()?;
    let dir = sessions_dir(args.out.as_deref(), &design);
    std::fs::create_dir_all(&dir)
        .with_context(|| format!("cannot create folder {}", dir.display()))?;
    let log_path = dir.join(format!("{}.jsonl", args.subject));
    let session = Session::open(&design, &args.subject, &log_path, Durability::Sync)?;
    for w in session.warnings() {
        eprintln!("warning: {w}");
    }
    if session.is_complete() {
        eprintln!(
            "subject {} has already answered every trial of design {:?} ({}); nothing to do",
            args.subject,
            design.name(),
            log_path.display()
        );
        return Ok(());
    }
    let pacing = if args.no_vsync {
        Pacing::Timer
    } else {
        Pacing::Vsync
    };
    let mut app = SessionApp::new(session, manifest, manifest_path, pacing);
    app.cover_monitor(args.windowed.is_none());
    let summary = app.summary();
    let mut viewport = egui::ViewportBuilder::default()
        .with_title(format!("blurlab {} {}", design.name(), args.subject))
        .with_decorations(false);
    viewport = match args.windowed {
        Some((w, h)) => viewport.with_inner_size([w as f32, h as f32]),
        None => viewport.with_fullscreen(true),
    };
    let options = eframe::NativeOptions {
        viewport,
        renderer: eframe::Renderer::Glow,
        dithering: false,
        glow_options: eframe::egui_glow::GlowConfiguration {
            vsync: pacing == Pacing::Vsync,
            ..Default::default()
        },
        ..Default::default()
    };
    eframe::run_native(
        "blurlab-session",
        options,
        Box::new(|_cc| Ok(Box::new(app))),
    )
    .map_err(|e| anyhow::anyhow!("the session window failed: {e}"))?;
    eprintln!("{}", summary.lock().expect("summary lock"));
    Ok(())
}
