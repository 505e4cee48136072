//! The session window (feature `gui`): eframe with the glow renderer, full screen without
//! decorations, dithering off (stimulus pixels must reach the screen unchanged).

mod loader;
mod prefetch;
mod screens;
mod session_app;
mod video_painter;

pub use session_app::{Pacing, SessionApp};

use crate::design::Design;
use crate::log::writer::Durability;
use crate::paths::sessions_dir;
use crate::playback::frame_store::FrameDir;
use crate::preflight::{PreflightOptions, preflight};
use crate::session::Session;
use anyhow::{Context, Result};
use renderer::progress::Progress;
use std::path::PathBuf;
use std::sync::Arc;

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

/// A subject's session ready for the window: preflight passed, the log opened (or continued).
pub struct Prepared {
    session: Session,
    manifest: renderer::manifest::Manifest,
    manifest_path: PathBuf,
    log_path: PathBuf,
    subject: String,
    design: String,
    windowed: Option<(u32, u32)>,
    pacing: Pacing,
}

impl Prepared {
    /// What opening the log tolerated (a torn last line, ...), for the caller to show before
    /// the window covers the screen.
    pub fn warnings(&self) -> &[String] {
        self.session.warnings()
    }

    /// Whether the subject has already answered every trial (then there is nothing to show).
    pub fn is_complete(&self) -> bool {
        self.session.is_complete()
    }

    /// The subject's log file.
    pub fn log_path(&self) -> &std::path::Path {
        &self.log_path
    }
}

/// What [`launch`] did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Launched {
    /// The subject had already answered every trial of the design: no window was opened.
    AlreadyComplete {
        subject: String,
        design: String,
        log: PathBuf,
    },
    /// The window ran and closed; the session's summary (trials answered, where the log is).
    Ran { summary: String },
}

impl std::fmt::Display for Launched {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Launched::AlreadyComplete {
                subject,
                design,
                log,
            } => write!(
                f,
                "subject {subject} has already answered every trial of design {design:?} ({}); \
                 nothing to do",
                log.display()
            ),
            Launched::Ran { summary } => f.write_str(summary),
        }
    }
}

/// `run`'s first half: preflight (reporting to `progress`), then open (or continue) the
/// subject's log. The library prints nothing: the caller shows [`Prepared::warnings`].
pub fn prepare(args: &LaunchOptions, progress: &dyn Progress) -> Result<Prepared> {
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
    Ok(Prepared {
        session,
        manifest,
        manifest_path,
        log_path,
        subject: args.subject.clone(),
        design: design.name().to_string(),
        windowed: args.windowed,
        pacing: args.pacing,
    })
}

/// `run`: [`prepare`], then the window unless the session is complete.
pub fn launch(args: &LaunchOptions, progress: &dyn Progress) -> Result<Launched> {
    show(prepare(args, progress)?)
}

/// `run`'s second half: the window over a prepared session (none if it is complete).
pub fn show(prepared: Prepared) -> Result<Launched> {
    let Prepared {
        session,
        manifest,
        manifest_path,
        log_path,
        subject,
        design,
        windowed,
        pacing,
    } = prepared;
    if session.is_complete() {
        return Ok(Launched::AlreadyComplete {
            subject,
            design,
            log: log_path,
        });
    }
    let store = Arc::new(FrameDir::new(manifest, manifest_path));
    let mut app = SessionApp::new(session, store, pacing);
    app.cover_monitor(windowed.is_none());
    let summary = app.summary();
    let mut viewport = egui::ViewportBuilder::default()
        .with_title(format!("blurlab {design} {subject}"))
        .with_decorations(false);
    viewport = match windowed {
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
    let summary = summary.lock().expect("summary lock").clone();
    Ok(Launched::Ran { summary })
}
