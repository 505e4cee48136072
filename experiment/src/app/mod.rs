//! The session window (feature `gui`): eframe with the glow renderer, full screen without
//! decorations, dithering off (stimulus pixels must reach the screen unchanged).

mod loader;
mod prefetch;
mod screens;
mod session_app;
mod video_painter;

pub use session_app::{Pacing, SessionApp};

use crate::design::Design;
use crate::log_writer::Durability;
use crate::paths::sessions_dir;
use crate::preflight::{PreflightOptions, preflight};
use crate::session::Session;
use anyhow::{Context, Result};
use renderer::progress::Progress;
use std::path::PathBuf;

/// What [`launch`] needs: a subject's session of a design, and how to show it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LaunchOptions {
    /// The design file (blurlab-design/1).
    pub design: PathBuf,
    /// The subject's id; names the log file `<subject>.jsonl`.
    pub subject: String,
    /// Folder of session logs; `None` (the default): `results/<design name>/sessions`.
    pub out: Option<PathBuf>,
    /// A window of this size in logical pixels instead of full screen; `None` (the default):
    /// full screen.
    pub windowed: Option<(u32, u32)>,
    /// How repaints are paced; default [`Pacing::Vsync`].
    pub pacing: Pacing,
    /// Whether preflight checks the stimuli's content hashes; default `true`.
    pub check_hashes: bool,
}

impl LaunchOptions {
    /// A subject's session of `design` with every default: logs under
    /// `results/<design name>/sessions`, full screen, vsync, content hashes checked.
    pub fn new(design: impl Into<PathBuf>, subject: impl Into<String>) -> Self {
        LaunchOptions {
            design: design.into(),
            subject: subject.into(),
            out: None,
            windowed: None,
            pacing: Pacing::Vsync,
            check_hashes: true,
        }
    }
}

/// `run`: preflight (reporting to `progress`), open (or continue) the subject's log, then the
/// window.
pub fn launch(args: &LaunchOptions, progress: &dyn Progress) -> Result<()> {
    let design = Design::load(&args.design)?;
    let report = preflight(
        &design,
        PreflightOptions {
            check_hashes: args.check_hashes,
        },
        progress,
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
    let pacing = args.pacing;
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
