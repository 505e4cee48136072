//! The subject-facing app: one [`Session`] shown screen by screen. All state lives here and
//! [`SessionApp::show`] draws one repaint from it, so eframe (the real window) and egui_kittest
//! (the tests) drive the very same code. Time comes from egui's input clock only.

mod trial;

use super::prefetch::VideoCache;
use super::screens;
use super::video_painter::Screen;
use crate::log::Display;
use crate::playback::frame_store::FrameStore;
use crate::playback::layout::VideoLayout;
use crate::playback::presentation::Presentation;
use crate::playback::refresh::RefreshMeter;
use crate::session::{Phase, Session, StartInfo};
use egui::{Color32, Key, RichText, ViewportCommand};
use std::sync::{Arc, Mutex};
use std::time::Duration;
use trial::TrialView;

/// How the window paces repaints.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pacing {
    /// Repaint every display refresh while anything moves (vsync on: real displays).
    Vsync,
    /// Sleep until the next frame boundary (no vsync, e.g. Xvfb).
    Timer,
}

/// How long practice feedback stays up, seconds.
const FEEDBACK_SECONDS: f64 = 1.0;

/// The app's state.
pub struct SessionApp {
    session: Session,
    /// The decoded videos and the prefetch of the next trial's.
    cache: VideoCache,
    pacing: Pacing,
    pair1: Vec<Key>,
    pair2: Vec<Key>,
    background: Color32,
    meter: RefreshMeter,
    /// egui time when the session (header or resume line) started: log times count from here.
    origin: Option<f64>,
    view: Option<TrialView>,
    paused_at: Option<f64>,
    feedback: Option<(bool, f64)>,
    fatal: Option<String>,
    /// One line on how the session ended, for the terminal.
    summary: Arc<Mutex<String>>,
    /// Resize the window over the whole monitor if the fullscreen request was not honoured.
    cover_monitor: bool,
    cover_attempts: u32,
    closing: bool,
}

impl SessionApp {
    /// The app over `session`, its videos from `store` (`run`: the stimulus folder,
    /// [`crate::playback::frame_store::FrameDir`]).
    pub fn new(session: Session, store: Arc<dyn FrameStore>, pacing: Pacing) -> Self {
        let keys = |names: &[String]| -> Vec<Key> {
            names
                .iter()
                .filter_map(|n| Key::from_name(crate::design::keys::canonical(n)))
                .collect()
        };
        let d = &session.design().file;
        let [r, g, b] = d.playback.background;
        let summary = Arc::new(Mutex::new(String::new()));
        let app = Self {
            pair1: keys(&d.keys.pair1),
            pair2: keys(&d.keys.pair2),
            background: Color32::from_rgb(r, g, b),
            session,
            cache: VideoCache::new(store),
            pacing,
            meter: RefreshMeter::default(),
            origin: None,
            view: None,
            paused_at: None,
            feedback: None,
            fatal: None,
            summary,
            cover_monitor: false,
            cover_attempts: 0,
            closing: false,
        };
        app.update_summary();
        app
    }

    /// Make sure the window covers the monitor: without a window manager (e.g. bare Xvfb) the
    /// fullscreen request is ignored, so the window is moved to the origin and sized to the
    /// monitor instead.
    pub fn cover_monitor(&mut self, on: bool) {
        self.cover_monitor = on;
    }

    fn enforce_cover(&mut self, ctx: &egui::Context) {
        let (monitor, inner) = ctx.input(|i| (i.viewport().monitor_size, i.viewport().inner_rect));
        let (Some(m), Some(r)) = (monitor, inner) else {
            return;
        };
        // Only the size is compared: under a window manager a fullscreen window on a second
        // monitor sits away from the origin, and must stay there.
        let covered = (r.size() - m).length() < 0.5;
        if !covered && self.cover_attempts < 20 {
            self.cover_attempts += 1;
            ctx.send_viewport_cmd(ViewportCommand::OuterPosition(egui::Pos2::ZERO));
            ctx.send_viewport_cmd(ViewportCommand::InnerSize(m));
            ctx.request_repaint_after(Duration::from_millis(50));
        }
    }

    /// Close the window (every answer is already on disk).
    fn close(&mut self, ctx: &egui::Context) {
        self.closing = true;
        ctx.send_viewport_cmd(ViewportCommand::Close);
    }

    /// Whether the app asked for its window to close.
    pub fn closing(&self) -> bool {
        self.closing
    }

    /// Shared text describing how far the session got (read after the window closed).
    pub fn summary(&self) -> Arc<Mutex<String>> {
        self.summary.clone()
    }

    pub fn session(&self) -> &Session {
        &self.session
    }

    /// Whether a trial's frames are being loaded (before or during its presentation).
    pub fn loading(&self) -> bool {
        self.view.as_ref().is_some_and(|v| v.loader.is_some())
    }

    /// Whether the trial is presented while the rest of its frames load.
    pub fn streaming(&self) -> bool {
        self.view
            .as_ref()
            .is_some_and(|v| v.loader.is_some() && v.presentation.is_some())
    }

    /// Whether the current trial waits for the answer.
    pub fn responding(&self) -> bool {
        self.view
            .as_ref()
            .and_then(|v| v.presentation.as_ref())
            .is_some_and(Presentation::responding)
    }

    /// Whether the next trial's videos are still being loaded in advance.
    pub fn prefetching(&self) -> bool {
        self.cache.prefetching()
    }

    pub fn paused(&self) -> bool {
        self.paused_at.is_some()
    }

    pub fn fatal_error(&self) -> Option<&str> {
        self.fatal.as_deref()
    }

    fn update_summary(&self) {
        let (done, total) = self.session.progress();
        let text = format!(
            "subject {}: {done} of {total} trials answered; log {}{}",
            self.session.subject(),
            self.session.log_path().display(),
            if self.session.is_complete() {
                String::new()
            } else {
                " (run the same command again to continue)".into()
            }
        );
        *self.summary.lock().expect("summary lock") = text;
    }

    /// Draw one repaint.
    pub fn show(&mut self, ui: &mut egui::Ui) {
        let ctx = ui.ctx().clone();
        let now = ctx.input(|i| i.time);
        if self.cover_monitor {
            self.enforce_cover(&ctx);
        }
        if let Some(msg) = self.fatal.clone() {
            screens::message(ui, "The session stopped", &msg, "Press Esc to close.");
            if ctx.input(|i| i.key_pressed(Key::Escape)) {
                self.close(&ctx);
            }
            return;
        }
        if self.paused_at.is_some() {
            self.pause_screen(ui, now);
            return;
        }
        if ctx.input(|i| i.key_pressed(Key::Escape)) && self.session.phase() != Phase::Finished {
            self.paused_at = Some(now);
            ctx.request_repaint();
            return;
        }
        self.pump_prefetch(&ctx);
        if let Some((correct, until)) = self.feedback {
            if now < until {
                let text = if correct { "Correct" } else { "Not correct" };
                screens::message(ui, text, "", "");
                ctx.request_repaint_after(Duration::from_secs_f64(until - now));
                return;
            }
            self.feedback = None;
        }
        match self.session.phase() {
            Phase::Instructions => self.instructions(ui, now),
            Phase::PracticeDone => {
                let body = if self.session.design().file.practice.feedback {
                    "The experiment starts now. It works exactly like the practice, without \
                     being told whether you were right."
                } else {
                    "The experiment starts now. It works exactly like the practice."
                };
                self.screen(ui, "Practice is over", body);
            }
            Phase::Break => self.break_screen(ui),
            Phase::Finished => {
                screens::message(
                    ui,
                    "Thank you!",
                    "All trials are done and your answers are saved.",
                    "Press Space to close.",
                );
                if ctx.input(|i| i.key_pressed(Key::Space)) {
                    self.close(&ctx);
                }
            }
            Phase::Practice(_) | Phase::Trial(_) => self.trial(ui, now),
        }
    }

    /// A screen left with Space.
    fn screen(&mut self, ui: &mut egui::Ui, title: &str, body: &str) {
        screens::message(ui, title, body, "Press Space to continue.");
        if ui.ctx().input(|i| i.key_pressed(Key::Space)) {
            self.session.advance();
        }
    }

    fn break_screen(&mut self, ui: &mut egui::Ui) {
        let (done, total) = self.session.progress();
        screens::centered(ui, |ui| {
            ui.label(RichText::new("Break").size(32.0).color(screens::TEXT));
            ui.add_space(18.0);
            ui.label(
                RichText::new(format!(
                    "{done} of {total} trials done. Rest your eyes as long as you like."
                ))
                .size(20.0)
                .color(screens::TEXT),
            );
            ui.add_space(12.0);
            ui.add(egui::ProgressBar::new(done as f32 / total.max(1) as f32).desired_width(400.0));
            ui.add_space(28.0);
            ui.label(
                RichText::new("Press Space to continue.")
                    .size(18.0)
                    .color(screens::HINT),
            );
        });
        if ui.ctx().input(|i| i.key_pressed(Key::Space)) {
            self.session.advance();
        }
    }

    fn pause_screen(&mut self, ui: &mut egui::Ui, now: f64) {
        screens::message(
            ui,
            "Paused",
            "Your answers so far are saved.",
            "Press Space to continue, or Q to quit (you can continue later where you stopped).",
        );
        let ctx = ui.ctx().clone();
        if ctx.input(|i| i.key_pressed(Key::Space)) {
            let paused = now - self.paused_at.take().unwrap_or(now);
            if let Some(view) = self.view.as_mut() {
                view.pauses += 1;
                if let Some(p) = view.presentation.as_mut() {
                    p.after_pause(paused);
                }
            }
            ctx.request_repaint();
        } else if ctx.input(|i| i.key_pressed(Key::Q)) {
            self.close(&ctx);
        }
    }

    fn instructions(&mut self, ui: &mut egui::Ui, now: f64) {
        let ctx = ui.ctx().clone();
        self.meter.repaint(now);
        if !self.meter.done() {
            ctx.request_repaint();
        }
        let (done, total) = self.session.progress();
        let mut body = self.session.design().instructions();
        if self.session.resumed() {
            body = format!(
                "Welcome back. {done} of {total} trials are done; the session continues where it \
                 stopped.\n\n{body}"
            );
        }
        let hint = if self.meter.done() {
            "Press Space to start."
        } else {
            "Preparing..."
        };
        screens::message(ui, "Instructions", &body, hint);
        if self.meter.done() && ctx.input(|i| i.key_pressed(Key::Space)) {
            self.start(&ctx, now);
        }
    }

    /// Write the header or resume line, after checking the videos fit this display.
    fn start(&mut self, ctx: &egui::Context, now: f64) {
        let screen = Screen::of(ctx);
        if let Err(e) = self.check_fits(screen) {
            self.fatal = Some(format!("{e:#}"));
            return;
        }
        if self.origin.is_none() {
            let display = Display {
                width: screen.width,
                height: screen.height,
                pixels_per_point: screen.pixels_per_point,
                refresh_interval_ms: self.meter.median_ms().unwrap_or(0.0),
                browser: None,
            };
            let started_unix = std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(0.0, |d| d.as_secs_f64());
            let info = StartInfo {
                mode: "gui".into(),
                display: Some(display),
                observer: None,
                started_unix,
            };
            if let Err(e) = self.session.start(info) {
                self.fatal = Some(format!("cannot start the session log: {e:#}"));
                return;
            }
            self.origin = Some(now);
        }
        self.session.advance();
    }

    /// Every video of the design must fit the display 1:1 in the design's layout.
    fn check_fits(&self, screen: Screen) -> anyhow::Result<()> {
        let d = &self.session.design().file;
        for n in crate::preflight::needed_stimuli(self.session.design()) {
            if let Ok(s) = self.cache.store().video(&n.id) {
                VideoLayout::new(
                    d.layout,
                    (screen.width, screen.height),
                    (s.width, s.height),
                    d.playback.spacing_px,
                )?;
            }
        }
        Ok(())
    }
}

impl eframe::App for SessionApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.show(ui);
    }

    /// The design's background is the clear colour: no full-screen quad to shade every frame
    /// (a software renderer pays for every pixel). Gamma-space values k / 255 are written back
    /// as exactly k.
    fn clear_color(&self, _visuals: &egui::Visuals) -> [f32; 4] {
        self.background.to_normalized_gamma_f32()
    }
}
