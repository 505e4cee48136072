//! Drawing video frames at exactly one texel per physical pixel: rectangles come from
//! [`VideoLayout`] in whole physical pixels and are divided by the scale factor only at the last
//! moment, so egui's multiplication back to pixels lands on the same whole numbers whatever
//! the display's scale factor. With nearest filtering each pixel centre samples one texel's
//! centre: no resampling, no blur.

use crate::log::Side;
use crate::playback::layout::{PxRect, VideoLayout};
use crate::playback::presentation::Pairs;
use crate::trials::Trial;
use egui::{Align2, Color32, Painter, Rect, TextureHandle, pos2, vec2};

use super::loader::Video;

/// The screen in physical pixels and the scale factor.
#[derive(Clone, Copy, Debug)]
pub struct Screen {
    pub width: u32,
    pub height: u32,
    pub pixels_per_point: f32,
}

impl Screen {
    pub fn of(ctx: &egui::Context) -> Self {
        let ppp = ctx.pixels_per_point();
        let r = ctx.viewport_rect();
        Self {
            width: (r.width() * ppp).round() as u32,
            height: (r.height() * ppp).round() as u32,
            pixels_per_point: ppp,
        }
    }

    /// A physical-pixel rectangle in egui points.
    pub fn to_points(self, r: PxRect) -> Rect {
        let s = self.pixels_per_point;
        Rect::from_min_size(
            pos2(r.x as f32 / s, r.y as f32 / s),
            vec2(r.w as f32 / s, r.h as f32 / s),
        )
    }
}

fn full_uv() -> Rect {
    Rect::from_min_max(pos2(0.0, 0.0), pos2(1.0, 1.0))
}

/// Draw the pair(s) of `trial` at video frame `frame`, videos found by stimulus id (a frame not
/// loaded is not drawn).
pub fn draw_pairs<'a>(
    painter: &Painter,
    screen: Screen,
    layout: &VideoLayout,
    trial: &Trial,
    pairs: Pairs,
    frame: u32,
    videos: impl Fn(&str) -> Option<&'a Video>,
) {
    let shown: &[u8] = match pairs {
        Pairs::One(1) => &[1],
        Pairs::One(_) => &[2],
        Pairs::Both => &[1, 2],
    };
    for &pair in shown {
        for side in [Side::Left, Side::Right] {
            let Some(tex) =
                videos(trial.video(pair, side)).and_then(|v| v.textures.get(frame as usize))
            else {
                continue;
            };
            let rect = screen.to_points(layout.rect(pair, side));
            painter.image(tex.id(), rect, full_uv(), Color32::WHITE);
        }
        // Name the pair above its left video (the keys refer to it).
        let left = screen.to_points(layout.rect(pair, Side::Left));
        let right = screen.to_points(layout.rect(pair, Side::Right));
        let label = match pairs {
            Pairs::Both => format!("{pair}"),
            Pairs::One(_) => format!("Pair {pair}"),
        };
        let at = pos2((left.left() + right.right()) / 2.0, left.top() - 8.0);
        super::screens::caption(painter, at, Align2::CENTER_BOTTOM, &label);
    }
}

/// Touch every texture once, hidden under an opaque background square, so the driver has
/// them resident before playback (a first draw of a fresh texture was seen to stall ~60 ms).
pub fn warm_up<'a>(
    painter: &Painter,
    screen: Screen,
    textures: impl Iterator<Item = &'a TextureHandle>,
    background: Color32,
) {
    let one = screen.to_points(PxRect {
        x: 0,
        y: 0,
        w: 1,
        h: 1,
    });
    for t in textures {
        painter.image(t.id(), one, full_uv(), Color32::WHITE);
    }
    painter.rect_filled(one, 0.0, background);
}
