//! The trial flow of [`SessionApp`]: a trial's videos loaded (or taken over from the
//! prefetch), its presentation driven by the clock, the answer screen and the answer logged.

use super::{FEEDBACK_SECONDS, Pacing, SessionApp};
use crate::app::loader::{LoadState, Loader};
use crate::app::prefetch::{PLAYBACK_BUDGET, UPLOAD_BUDGET};
use crate::app::screens;
use crate::app::video_painter::{self, Screen};
use crate::log::Side;
use crate::playback::layout::VideoLayout;
use crate::playback::presentation::{Presentation, View};
use crate::session::Phase;
use crate::trials::Trial;
use egui::RichText;
use std::time::{Duration, Instant};

/// Repaint interval while frames stream in during the fixation and the gap, seconds.
const STREAM_REPAINT_S: f64 = 0.010;

/// The trial being shown: loading, then its presentation.
pub(super) struct TrialView {
    pub(super) phase: Phase,
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
        let phase = self.session.phase();
        if self.view.as_ref().is_none_or(|v| v.phase != phase) {
            match self.begin_trial(phase) {
                Ok(v) => self.view = Some(v),
                Err(e) => {
                    self.fatal = Some(format!("{e:#}"));
                    return;
                }
            }
        }
        if !self.pump_trial(ui) {
            return;
        }
        let view = self.view.as_ref().expect("view present");
        let ready = self.ready(&view.trial, view.loader.as_ref());
        let view = self.view.as_mut().expect("view present");
        let loading = view.loader.as_ref();
        let t = now - self.origin.unwrap_or(now);
        let presentation = view.presentation.as_mut().expect("presentation present");
        let shown = presentation.tick_ready(t, ready);
        let next_change = presentation.next_change(t);
        let screen = Screen::of(&ctx);
        match shown {
            View::Fixation | View::Gap => {
                if shown == View::Fixation {
                    screens::fixation(ui);
                }
                let textures = view
                    .trial
                    .stimuli()
                    .into_iter()
                    .filter_map(|id| self.cache.video(id, loading))
                    .flat_map(|v| v.textures.iter());
                video_painter::warm_up(ui.painter(), screen, textures, self.background);
            }
            View::Play { pairs, frame } => {
                let d = &self.session.design().file;
                let Some(r) = self.cache.video(&view.trial.reference_stimulus, loading) else {
                    return;
                };
                match VideoLayout::new(
                    d.layout,
                    (screen.width, screen.height),
                    (r.source.width, r.source.height),
                    d.playback.spacing_px,
                ) {
                    Ok(layout) => video_painter::draw_pairs(
                        ui.painter(),
                        screen,
                        &layout,
                        &view.trial,
                        pairs,
                        frame,
                        |id| self.cache.video(id, loading),
                    ),
                    Err(e) => self.fatal = Some(format!("{e:#}")),
                }
            }
            View::Respond => {
                self.respond(ui, now);
                return;
            }
        }
        let streaming = loading.is_some();
        match (self.pacing, next_change) {
            (Pacing::Vsync, _) => ctx.request_repaint(),
            // Uploads go on between frames while the trial streams (not during playback: a
            // repaint there redraws the pair).
            (Pacing::Timer, Some(s)) if streaming && !matches!(shown, View::Play { .. }) => {
                ctx.request_repaint_after(Duration::from_secs_f64(s.min(STREAM_REPAINT_S)))
            }
            (Pacing::Timer, Some(s)) => ctx.request_repaint_after(Duration::from_secs_f64(s)),
            (Pacing::Timer, None) => {}
        }
    }

    /// Upload the current trial's frames; `false` while the trial must wait for them (the
    /// progress screen is up) or failed. The presentation starts once every frame is in, or
    /// earlier once the rest will load before it is due ([`crate::playback::stream`]).
    fn pump_trial(&mut self, ui: &mut egui::Ui) -> bool {
        let ctx = ui.ctx().clone();
        let Some(view) = self.view.as_mut() else {
            return false;
        };
        let Some(loader) = view.loader.as_mut() else {
            return true;
        };
        let streaming = view.presentation.is_some();
        let budget = if streaming {
            PLAYBACK_BUDGET
        } else {
            UPLOAD_BUDGET
        };
        let done = match loader.pump(&ctx, budget) {
            LoadState::Failed(e) => {
                self.fatal = Some(format!("cannot load a video: {e}"));
                return false;
            }
            LoadState::Loading { fraction } => {
                if !streaming && !loader.can_start() {
                    screens::progress(ui, "Loading the next videos...", fraction);
                    ctx.request_repaint();
                    return false;
                }
                false
            }
            LoadState::Done => true,
        };
        if view.presentation.is_none() {
            view.preload_ms = view.began.elapsed().as_secs_f64() * 1000.0;
            let r = self
                .cache
                .video(&view.trial.reference_stimulus, view.loader.as_ref());
            let (frames, fps) = r.map_or((1, 30.0), |r| (r.source.frames, r.source.fps));
            view.presentation = Some(Presentation::new(self.session.design(), frames, fps));
        }
        if done {
            let loader = view.loader.take().expect("loader present");
            self.cache.insert(loader);
        }
        true
    }

    /// Frames of both videos of each pair loaded (all of a video not loading).
    fn ready(&self, trial: &Trial, loading: Option<&Loader>) -> [u32; 2] {
        let loaded = |id: &str| loading.and_then(|l| l.loaded(id)).unwrap_or(u32::MAX);
        [1, 2].map(|pair| {
            loaded(trial.video(pair, Side::Left)).min(loaded(trial.video(pair, Side::Right)))
        })
    }

    /// Set up a trial's view, taking over the prefetch of its videos if there is one.
    fn begin_trial(&mut self, phase: Phase) -> anyhow::Result<TrialView> {
        let began = Instant::now();
        let trial = self
            .session
            .trial()
            .ok_or_else(|| anyhow::anyhow!("no trial at phase {phase:?}"))?
            .clone();
        let loader = self.cache.loader_for_trial(self.session.design(), &trial)?;
        Ok(TrialView {
            phase,
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
        let next = self.session.next_trial();
        self.cache
            .start_prefetch(self.session.design(), next.as_ref());
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
                    crate::design::keys::describe(&k.pair1),
                    crate::design::keys::describe(&k.pair2)
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
