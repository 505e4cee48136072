//! Where the videos go, in whole physical pixels: the two videos of a pair side by side,
//! `spacing` apart, centred on the screen; in the grid layout pair 1 is the top row and pair 2
//! the bottom row. Whole pixels plus nearest filtering make every video pixel one screen pixel.

use crate::design::Layout;
use crate::log::Side;
use anyhow::{Result, bail};

/// A rectangle in physical pixels (origin top left).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PxRect {
    pub x: u32,
    pub y: u32,
    pub w: u32,
    pub h: u32,
}

/// The four video places of a trial: `rect(pair, side)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VideoLayout {
    /// `[pair - 1][left, right]`.
    rects: [[PxRect; 2]; 2],
}

impl VideoLayout {
    /// Place `video` (w, h) videos on a `screen` (w, h), all in physical pixels.
    pub fn new(
        layout: Layout,
        screen: (u32, u32),
        video: (u32, u32),
        spacing: u32,
    ) -> Result<Self> {
        let (vw, vh) = video;
        let need_w = 2 * vw + spacing;
        let need_h = match layout {
            Layout::Sequential => vh,
            Layout::Grid => 2 * vh + spacing,
        };
        if need_w > screen.0 || need_h > screen.1 {
            bail!(
                "the {} layout of {vw}x{vh} videos {spacing} px apart needs {need_w}x{need_h} \
                 physical pixels, but the display has {}x{}; use a larger display, the \
                 sequential layout, or smaller stimuli",
                match layout {
                    Layout::Sequential => "sequential",
                    Layout::Grid => "grid",
                },
                screen.0,
                screen.1
            );
        }
        let x0 = (screen.0 - need_w) / 2;
        let y0 = (screen.1 - need_h) / 2;
        let row = |y: u32| {
            [
                PxRect {
                    x: x0,
                    y,
                    w: vw,
                    h: vh,
                },
                PxRect {
                    x: x0 + vw + spacing,
                    y,
                    w: vw,
                    h: vh,
                },
            ]
        };
        let rects = match layout {
            Layout::Sequential => [row(y0), row(y0)],
            Layout::Grid => [row(y0), row(y0 + vh + spacing)],
        };
        Ok(Self { rects })
    }

    pub fn rect(&self, pair: u8, side: Side) -> PxRect {
        let p = usize::from(pair.clamp(1, 2) - 1);
        self.rects[p][match side {
            Side::Left => 0,
            Side::Right => 1,
        }]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thesis_pair_fits_1080p_centred_and_the_grid_does_not() {
        let l = VideoLayout::new(Layout::Sequential, (1920, 1080), (768, 768), 32).unwrap();
        // (1920 - 1568) / 2 = 176; (1080 - 768) / 2 = 156.
        assert_eq!(
            l.rect(1, Side::Left),
            PxRect {
                x: 176,
                y: 156,
                w: 768,
                h: 768
            }
        );
        assert_eq!(l.rect(2, Side::Right).x, 176 + 768 + 32);
        assert_eq!(l.rect(1, Side::Left), l.rect(2, Side::Left));
        let e = VideoLayout::new(Layout::Grid, (1920, 1080), (768, 768), 32).unwrap_err();
        assert!(e.to_string().contains("1568x1568"), "{e}");
    }

    #[test]
    fn grid_rows_are_the_pairs_and_odd_margins_round_down() {
        let l = VideoLayout::new(Layout::Grid, (101, 50), (40, 20), 3).unwrap();
        assert_eq!(
            l.rect(1, Side::Left),
            PxRect {
                x: 9,
                y: 3,
                w: 40,
                h: 20
            }
        );
        assert_eq!(
            l.rect(2, Side::Right),
            PxRect {
                x: 52,
                y: 26,
                w: 40,
                h: 20
            }
        );
        // Exactly fitting is allowed; one pixel less is not.
        assert!(VideoLayout::new(Layout::Sequential, (83, 20), (40, 20), 3).is_ok());
        assert!(VideoLayout::new(Layout::Sequential, (82, 20), (40, 20), 3).is_err());
    }
}
