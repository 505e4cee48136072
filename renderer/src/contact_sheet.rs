//! A contact sheet: display frames (or the same crop of each) side by side at 1:1 pixel scale,
//! each under its label, as one PNG — how noise at each sampling level looks beside the
//! reference.

use crate::convergence::{FONT, register_font};
use anyhow::{Result, anyhow, ensure};
use plotters::prelude::*;
use std::path::Path;

/// A rectangle of a frame, in pixels from the top-left corner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rect {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

impl std::str::FromStr for Rect {
    type Err = String;

    /// `x,y,width,height`.
    fn from_str(s: &str) -> Result<Self, String> {
        let v: Vec<u32> = s
            .split(',')
            .map(|t| t.trim().parse::<u32>())
            .collect::<Result<_, _>>()
            .map_err(|_| format!("`{s}`: expected x,y,width,height in pixels"))?;
        match v[..] {
            [x, y, width, height] if width > 0 && height > 0 => Ok(Rect {
                x,
                y,
                width,
                height,
            }),
            _ => Err(format!(
                "`{s}`: expected x,y,width,height with width and height >= 1"
            )),
        }
    }
}

/// One labelled picture, RGB interleaved.
#[derive(Clone, Debug, PartialEq)]
pub struct Tile {
    pub label: String,
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

impl Tile {
    /// `rect` of a `width` x `height` RGB frame (the whole frame without one).
    pub fn cut(
        label: String,
        rgb: &[u8],
        width: u32,
        height: u32,
        rect: Option<Rect>,
    ) -> Result<Self> {
        let r = rect.unwrap_or(Rect {
            x: 0,
            y: 0,
            width,
            height,
        });
        ensure!(
            r.x + r.width <= width && r.y + r.height <= height,
            "crop {},{},{},{} does not fit in a {width} x {height} frame",
            r.x,
            r.y,
            r.width,
            r.height
        );
        let mut out = Vec::with_capacity((r.width * r.height * 3) as usize);
        for y in r.y..r.y + r.height {
            let start = ((y * width + r.x) * 3) as usize;
            out.extend_from_slice(&rgb[start..start + (r.width * 3) as usize]);
        }
        Ok(Self {
            label,
            width: r.width,
            height: r.height,
            rgb: out,
        })
    }
}

const GAP: u32 = 8;
const LABEL: u32 = 26;
const BACKGROUND: [u8; 3] = [32, 32, 32];

/// Lay `tiles` (all the same size) out in rows of `columns` and write the sheet as PNG.
pub fn write(path: &Path, tiles: &[Tile], columns: usize) -> Result<()> {
    ensure!(!tiles.is_empty(), "a contact sheet needs at least one tile");
    let (tw, th) = (tiles[0].width, tiles[0].height);
    ensure!(
        tiles.iter().all(|t| (t.width, t.height) == (tw, th)),
        "contact sheet tiles differ in size"
    );
    let columns = columns.clamp(1, tiles.len()) as u32;
    let rows = (tiles.len() as u32).div_ceil(columns);
    let (w, h) = (GAP + columns * (tw + GAP), GAP + rows * (LABEL + th + GAP));
    let mut rgb: Vec<u8> = BACKGROUND.repeat((w * h) as usize);
    let origin = |i: usize| {
        let (c, r) = (i as u32 % columns, i as u32 / columns);
        (GAP + c * (tw + GAP), GAP + r * (LABEL + th + GAP))
    };
    for (i, t) in tiles.iter().enumerate() {
        let (x0, y0) = origin(i);
        for y in 0..th {
            let dst = (((y0 + LABEL + y) * w + x0) * 3) as usize;
            let src = (y * tw * 3) as usize;
            rgb[dst..dst + (tw * 3) as usize].copy_from_slice(&t.rgb[src..src + (tw * 3) as usize]);
        }
    }
    register_font()?;
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        let style = (FONT, 18).into_font().color(&WHITE);
        for (i, t) in tiles.iter().enumerate() {
            let (x0, y0) = origin(i);
            root.draw_text(&t.label, &style, (x0 as i32, y0 as i32 + 3))
                .map_err(|e| anyhow!("cannot draw a contact sheet label: {e}"))?;
        }
        root.present()
            .map_err(|e| anyhow!("cannot draw the contact sheet: {e}"))?;
    }
    let png = crate::frame_io::png::png_bytes(&rgb, w, h)?;
    crate::atomic::write_atomic(path, &png)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rectangles_parse_and_cuts_take_the_right_pixels() {
        assert_eq!(
            "1,2,3,4".parse::<Rect>(),
            Ok(Rect {
                x: 1,
                y: 2,
                width: 3,
                height: 4
            })
        );
        assert!("1,2,0,4".parse::<Rect>().is_err());
        assert!("1,2,3".parse::<Rect>().is_err());
        // A 3 x 2 frame whose pixel (x, y) is (x, y, 7).
        let rgb: Vec<u8> = (0..2u8)
            .flat_map(|y| (0..3u8).flat_map(move |x| [x, y, 7]))
            .collect();
        let rect = "1,1,2,1".parse().unwrap();
        let t = Tile::cut("a".into(), &rgb, 3, 2, Some(rect)).unwrap();
        assert_eq!(t.rgb, [1, 1, 7, 2, 1, 7]);
        assert!(Tile::cut("a".into(), &rgb, 3, 2, Some("2,0,2,1".parse().unwrap())).is_err());
    }

    #[test]
    fn the_sheet_holds_every_tile_at_one_to_one_scale() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sheet.png");
        let tile = |v: u8| Tile {
            label: format!("{v}"),
            width: 4,
            height: 3,
            rgb: vec![v; 36],
        };
        write(&path, &[tile(100), tile(200), tile(250)], 2).unwrap();
        let img = image::open(&path).unwrap().to_rgb8();
        assert_eq!(
            img.dimensions(),
            (GAP + 2 * (4 + GAP), GAP + 2 * (LABEL + 3 + GAP))
        );
        // Third tile: second row, first column; its pixels are untouched by the labels.
        let (x, y) = (GAP, GAP + (LABEL + 3 + GAP) + LABEL);
        assert_eq!(img.get_pixel(x + 3, y + 2).0, [250; 3]);
        assert_eq!(img.get_pixel(GAP + 4 + GAP, GAP + LABEL).0, [200; 3]);
    }
}
