//! The text screens between trials (instructions, breaks, pause, end) and small drawing helpers.

use egui::{Align2, Color32, FontId, Painter, Pos2, Rect, RichText, Stroke, Ui, UiBuilder, vec2};

pub const TEXT: Color32 = Color32::from_gray(225);
pub const HINT: Color32 = Color32::from_gray(150);

/// A centred block: title, body text, and a hint line (what key to press).
pub fn message(ui: &mut Ui, title: &str, body: &str, hint: &str) {
    centered(ui, |ui| {
        ui.label(RichText::new(title).size(32.0).color(TEXT));
        ui.add_space(18.0);
        ui.label(RichText::new(body).size(20.0).color(TEXT));
        ui.add_space(28.0);
        ui.label(RichText::new(hint).size(18.0).color(HINT));
    });
}

/// Run `content` in a column centred on the screen.
pub fn centered<R>(ui: &mut Ui, content: impl FnOnce(&mut Ui) -> R) -> R {
    let screen = ui.ctx().content_rect();
    let width = (screen.width() * 0.7).min(900.0);
    let column = Rect::from_center_size(screen.center(), vec2(width, screen.height() * 0.9));
    ui.scope_builder(UiBuilder::new().max_rect(column), |ui| {
        ui.vertical_centered(|ui| {
            ui.add_space(column.height() * 0.25);
            content(ui)
        })
        .inner
    })
    .inner
}

/// A progress bar with a caption, centred.
pub fn progress(ui: &mut Ui, caption: &str, fraction: f32) {
    centered(ui, |ui| {
        ui.label(RichText::new(caption).size(20.0).color(TEXT));
        ui.add_space(12.0);
        ui.add(
            egui::ProgressBar::new(fraction)
                .desired_width(400.0)
                .show_percentage(),
        );
    });
}

/// The fixation cross at the screen centre.
pub fn fixation(ui: &Ui) {
    let c = ui.ctx().content_rect().center();
    let s = 12.0;
    let stroke = Stroke::new(2.0, TEXT);
    let p = ui.painter();
    p.line_segment([c - vec2(s, 0.0), c + vec2(s, 0.0)], stroke);
    p.line_segment([c - vec2(0.0, s), c + vec2(0.0, s)], stroke);
}

/// Small grey text anchored at a point.
pub fn caption(painter: &Painter, at: Pos2, anchor: Align2, text: &str) {
    painter.text(at, anchor, text, FontId::proportional(18.0), HINT);
}
