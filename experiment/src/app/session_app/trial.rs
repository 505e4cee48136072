//! The trial flow of [`SessionApp`]: a trial's videos loaded (or taken over from the
//! prefetch), its presentation driven by the clock, the answer screen and the answer logged.

use super::{FEEDBACK_SECONDS, Pacing, SessionApp};
use crate::app::loader::{LoadState, Loader};
use crate::app::prefetch::UPLOAD_BUDGET;
use crate::app::screens;
use crate::app::video_painter::{self, Screen};
use crate::layout::VideoLayout;
use crate::presentation::{Presentation, View};
use crate::session::Stage;
use crate::trials::Trial;
use egui::RichText;
use std::time::{Duration, Instant};

/// The trial being shown: loading, then its presentation.
pub(super) struct TrialView {
    pub(super) stage: Stage,
    pub(super) trial: Trial,
    pub(super) loader: Option<Loader>,
    pub(super) presentation: Option<Presentation>,
    pub(super) preload_ms: f64,
    pub(super) pauses: u32,
    /// When the trial became current (its preload time is the wait from here).
    pub(super) began: Instant,
}

impl SessionApp {
    pub(super) fn trial(&mut self, ui: &mut egui::Ui, now: f64) {
        let ctx = ui.ctx().clone();
        let stage = self.session.stage();
        if self.view.as_ref().is_none_or(|v| v.stage != stage) {
            match self.begin_trial(stage) {
                Ok(v) => self.view = Some(v),
                Err(e) => {
                    self.fatal = Some(format!("{e:#}"));
                    return;
                }
            }
        }
        let Some(view) = self.view.as_mut() else {
            return;
        };
        if let Some(loader) = view.loader.as_mut() {
            match loader.pump(&ctx, UPLOAD_BUDGET) {
                LoadState::Loading { fraction } => {
                    screens::progress(ui, "Loading the next videos...", fraction);
                    ctx.request_repaint();
                    return;
                }
                LoadState::Failed(e) => {
                    self.fatal = Some(format!("cannot load a video: {e}"));
                    return;
                }
                LoadState::Done => {
                    view.preload_ms = view.began.elapsed().as_secs_f64() * 1000.0;
                    let loader = view.loader.take().expect("loader present");
                    self.cache.insert(loader);
                }
            }
        }
        let view = self.view.as_mut().expect("view present");
        if view.presentation.is_none() {
            let r = &self.cache.videos()[&view.trial.reference_stimulus].source;
            view.presentation = Some(Presentation::new(self.session.design(), r.frames(), r.fps));
        }
        let t = now - self.origin.unwrap_or(now);
        let presentation = view.presentation.as_mut().expect("presentation present");
        let shown = presentation.tick(t);
        let next_change = presentation.next_change(t);
        let screen = Screen::of(&ctx);
        match shown {
            View::Fixation => {
                screens::fixation(ui);
                let textures = view
                    .trial
                    .stimuli()
                    .into_iter()
                    .filter_map(|id| self.cache.videos().get(id))
                    .flat_map(|v| v.textures.iter());
                video_painter::warm_up(ui.painter(), screen, textures, self.background);
            }
            View::Play { pairs, frame } => {
                let d = &self.session.design().file;
                let r = &self.cache.videos()[&view.trial.reference_stimulus].source;
                match VideoLayout::new(
                    d.layout,
                    (screen.width, screen.height),
                    (r.width, r.height),
                    d.playback.spacing_px,
                ) {
                    Ok(layout) => video_painter::draw_pairs(
                        ui.painter(),
                        screen,
                        &layout,
                        &view.trial,
                        pairs,
                        frame,
                        self.cache.videos(),
                    ),
                    Err(e) => self.fatal = Some(format!("{e:#}")),
                }
            }
            View::Gap => {}
            View::Respond => {
                self.respond(ui, now);
                return;
            }
        }
        match (self.pacing, next_change) {
            (Pacing::Vsync, _) => ctx.request_repaint(),
            (Pacing::Timer, Some(s)) => ctx.request_repaint_after(Duration::from_secs_f64(s)),
            (Pacing::Timer, None) => {}
        }
    }

    /// Set up a trial's view, taking over the prefetch of its videos if there is one.
    fn begin_trial(&mut self, stage: Stage) -> anyhow::Result<TrialView> {
        let began = Instant::now();
        let trial = self
            .session
            .trial()
            .ok_or_else(|| anyhow::anyhow!("no trial at stage {stage:?}"))?
            .clone();
        let loader = self.cache.loader_for_trial(&trial)?;
        Ok(TrialView {
            stage,
            trial,
            loader: Some(loader),
            presentation: None,
            preload_ms: 0.0,
            pauses: 0,
            began,
        })
    }

    /// Once a presentation is over, load the next trial's videos while the subject answers
    /// (never during playback, where decoding would compete with frame pacing).
    fn start_prefetch(&mut self) {
        self.cache
            .start_prefetch(self.session.next_trial().as_ref());
    }

    /// Upload prefetched frames a few at a time while nothing moves on screen.
    pub(super) fn pump_prefetch(&mut self, ctx: &egui::Context) {
        let presenting = self
            .view
            .as_ref()
            .and_then(|v| v.presentation.as_ref())
            .is_some_and(|p| !p.responding());
        if presenting {
            return;
        }
        self.cache.pump_prefetch(ctx);
    }

    fn respond(&mut self, ui: &mut egui::Ui, now: f64) {
        let ctx = ui.ctx().clone();
        self.start_prefetch();
        let (first, second) = match self.session.design().file.layout {
            crate::design::Layout::Sequential => ("first", "second"),
            crate::design::Layout::Grid => ("top", "bottom"),
        };
        let mut response = None;
        screens::centered(ui, |ui| {
            ui.label(
                RichText::new(format!(
                    "Which pair was different, the {first} or the {second}?"
                ))
                .size(24.0)
                .color(screens::TEXT),
            );
            ui.add_space(24.0);
            ui.horizontal(|ui| {
                let w = 2.0 * 160.0 + ui.spacing().item_spacing.x;
                ui.add_space(((ui.available_width() - w) / 2.0).max(0.0));
                for (n, label) in [(1u8, "Pair 1"), (2, "Pair 2")] {
                    let b = egui::Button::new(RichText::new(label).size(22.0))
                        .min_size(egui::vec2(160.0, 56.0));
                    if ui.add(b).clicked() {
                        response = Some(n);
                    }
                }
            });
            ui.add_space(18.0);
            let k = &self.session.design().file.keys;
            ui.label(
                RichText::new(format!(
                    "Keys: {} for pair 1, {} for pair 2",
                    crate::keys::describe(&k.pair1),
                    crate::keys::describe(&k.pair2)
                ))
                .size(18.0)
                .color(screens::HINT),
            );
        });
        ctx.input(|i| {
            if self.pair1.iter().any(|&k| i.key_pressed(k)) {
                response = Some(1);
            } else if self.pair2.iter().any(|&k| i.key_pressed(k)) {
                response = Some(2);
            }
        });
        if let Some(r) = response {
            self.answer(&ctx, r, now);
        }
    }

    fn answer(&mut self, ctx: &egui::Context, response: u8, now: f64) {
        let Some(view) = self.view.take() else {
            return;
        };
        let t = now - self.origin.unwrap_or(now);
        let timing = view
            .presentation
            .as_ref()
            .map(|p| p.timing(t, view.pauses, view.preload_ms))
            .unwrap_or_default();
        match self.session.answer(response, timing) {
            Ok(a) => {
                if a.practice && self.session.design().file.practice.feedback {
                    self.feedback = Some((a.correct, now + FEEDBACK_SECONDS));
                }
                self.update_summary();
            }
            Err(e) => {
                self.fatal = Some(format!(
                    "the answer could not be saved: {e:#}. Answers before this trial are in the \
                     log; fix the problem and run the same command to continue."
                ))
            }
        }
        ctx.request_repaint();
    }
}
