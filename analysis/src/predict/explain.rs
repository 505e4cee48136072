//! Where the model sees a difference, and what is there: for each frame of a pair, the place the
//! aperture lands ([`crate::observer::model::pooling::Placement::MostVisible`]), the luminance,
//! clipping and test-minus-reference difference under it, and how the frame's pooled difference
//! (D^beta summed over the frame) splits over local adaptation luminance and clipped pixels. A
//! diagnostic for a prediction that looks wrong (docs/predict.md, "What the model sees in the
//! spheres"): it computes nothing the prediction does not, it only shows where.

use super::stimuli::mean_luminance;
use crate::observer::model::display::Display;
use crate::observer::model::pooling::{FITTED, Pooling, most_visible_at};
use crate::observer::model::shape;
use crate::observer::model::video::{ADAPTATION_FLOOR, Filters, Viewing, frame_sums};
use anyhow::{Context, Result, bail};
use experiment::display::DisplaySpec;
use experiment::playback::frames::{VideoSource, load_frame};
use renderer::manifest::Manifest;
use std::fmt::Write as _;
use std::path::Path;

/// One frame pair as the display shows it.
#[derive(Clone, Debug)]
pub struct FramePair {
    /// Luminance, cd/m^2, row-major.
    pub test: Vec<f32>,
    pub reference: Vec<f32>,
    /// Pixels with a channel at the display's top code (255): the render was clipped there.
    pub test_clipped: Vec<bool>,
    pub reference_clipped: Vec<bool>,
}

/// Statistics of a set of pixels.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Region {
    pub pixels: usize,
    /// Mean reference luminance and mean local adaptation luminance, cd/m^2.
    pub reference_mean: f64,
    pub adaptation_mean: f64,
    /// Fractions of the pixels clipped in the reference and in the test.
    pub reference_clipped: f64,
    pub test_clipped: f64,
    /// Fraction of pixels whose luminance differs at all.
    pub differing: f64,
    /// Mean and RMS of test minus reference, cd/m^2: a mean far from zero against
    /// RMS / sqrt(pixels) is a bias, not noise.
    pub mean_difference: f64,
    pub rms_difference: f64,
    /// RMS of the contrast (T - R) / L_a.
    pub rms_contrast: f64,
}

/// The luminance bins (cd/m^2, of the local adaptation) the pooled difference is split over.
pub const ADAPTATION_BINS: [f32; 6] = [0.0, 3.0, 10.0, 30.0, 100.0, f32::INFINITY];

/// One frame's explanation.
#[derive(Clone, Debug)]
pub struct FrameExplanation {
    pub frame: usize,
    /// Q_t at the pooling's aperture, placed where it is largest (as the prediction pools).
    pub q: f64,
    /// The aperture's centre: column, row.
    pub centre: (usize, usize),
    /// The pixels within one aperture sd of the centre.
    pub window: Region,
    pub whole: Region,
    /// Share of the window's weighted sum of D^beta in the frame's unweighted total.
    pub window_share: f64,
    /// Share of the frame's total D^beta per bin of [`ADAPTATION_BINS`].
    pub by_adaptation: Vec<f64>,
    /// Share of the frame's total D^beta on pixels clipped in the reference or the test, and
    /// within 2 pixels of such a pixel.
    pub on_clipped: f64,
    pub near_clipped: f64,
}

/// Explain stimulus `test` against `reference` of the set at `manifest_path` with the committed
/// model on `display`: the Markdown table.
pub fn pair(
    manifest_path: &Path,
    test: &str,
    reference: &str,
    display: &DisplaySpec,
) -> Result<String> {
    if test == reference {
        // The difference is zero everywhere: every share in the table would be 0 / 0.
        bail!(
            "--test and --reference are both {test:?}; expected two different stimuli (a pair \
             with no difference has nothing to explain)"
        );
    }
    display.validate()?;
    let manifest = Manifest::load(manifest_path)?;
    let video = |id: &str| {
        VideoSource::from_manifest(&manifest, manifest_path, id)
            .with_context(|| format!("stimulus {id} of {}", manifest_path.display()))
    };
    let (t, r) = (video(test)?, video(reference)?);
    if (t.width, t.height, t.frames()) != (r.width, r.height, r.frames()) {
        bail!("{test} and {reference} differ in size or length");
    }
    let d = Display::new(display);
    let frames = (0..t.frames() as usize)
        .map(|i| {
            let (a, b) = (load_frame(&t, i)?.rgb, load_frame(&r, i)?.rgb);
            let clipped = |rgb: &[u8]| rgb.chunks_exact(3).map(|p| p.contains(&255)).collect();
            Ok(FramePair {
                test: d.luminance(&a),
                reference: d.luminance(&b),
                test_clipped: clipped(&a),
                reference_clipped: clipped(&b),
            })
        })
        .collect::<Result<Vec<_>>>()?;
    if frames.iter().all(|f| f.test == f.reference) {
        bail!(
            "{test} and {reference} of {} show the same frames; expected a pair that differs \
             (the shares of a zero difference are 0 / 0)",
            manifest_path.display()
        );
    }
    let viewing = Viewing {
        width: t.width as usize,
        height: t.height as usize,
        frames: frames.len(),
        fps: t.fps,
        pixels_per_degree: d.pixels_per_degree,
        mean_luminance: mean_luminance(&r, &d)?.max(ADAPTATION_FLOOR as f64),
    };
    let mut filters = Filters::new(viewing, FITTED.channels, shape::FITTED)?;
    let e = explain(&mut filters, FITTED, &frames)?;
    Ok(markdown(&format!("{test} against {reference}"), &e))
}

/// Explain every frame of a pair, pooled as `pooling` (its aperture must be finite).
pub fn explain(
    filters: &mut Filters,
    pooling: Pooling,
    frames: &[FramePair],
) -> Result<Vec<FrameExplanation>> {
    let v = filters.viewing();
    let mut maps = Vec::with_capacity(frames.len());
    frame_sums(
        filters,
        |i| Ok((frames[i].test.clone(), frames[i].reference.clone())),
        |_, sums| maps.push(sums.sums[0].clone()),
    )?;
    let r = (pooling.space / pooling.channels) as f32;
    let sd_px = pooling.aperture_deg * v.pixels_per_degree;
    maps.iter()
        .zip(frames)
        .enumerate()
        .map(|(t, (sum, pair))| {
            let d: Vec<f32> = sum.iter().map(|&s| s.powf(r)).collect();
            let (best, x, y) = most_visible_at(&d, v.width, sd_px / pooling.space.sqrt());
            let la = filters.linear().adaptation(&pair.reference);
            let inside = |i: usize| {
                let (dx, dy) = (
                    (i % v.width) as f64 - x as f64,
                    (i / v.width) as f64 - y as f64,
                );
                dx * dx + dy * dy <= sd_px * sd_px
            };
            let all: Vec<usize> = (0..d.len()).collect();
            let window: Vec<usize> = all.iter().copied().filter(|&i| inside(i)).collect();
            let total: f64 = d.iter().map(|&v| v as f64).sum();
            let share = |keep: &dyn Fn(usize) -> bool| {
                all.iter()
                    .filter(|&&i| keep(i))
                    .map(|&i| d[i] as f64)
                    .sum::<f64>()
                    / total
            };
            let clipped = |i: usize| pair.test_clipped[i] || pair.reference_clipped[i];
            let near = dilate(
                &all.iter().map(|&i| clipped(i)).collect::<Vec<_>>(),
                v.width,
                2,
            );
            Ok(FrameExplanation {
                frame: t,
                q: (best / v.pixels_per_degree.powi(2)).powf(1.0 / pooling.space),
                centre: (x, y),
                window: region(pair, &la, &window),
                whole: region(pair, &la, &all),
                window_share: best / total,
                by_adaptation: ADAPTATION_BINS
                    .windows(2)
                    .map(|b| share(&|i| la[i] >= b[0] && la[i] < b[1]))
                    .collect(),
                on_clipped: share(&clipped),
                near_clipped: share(&|i| near[i]),
            })
        })
        .collect()
}

/// Pixels within `reach` pixels (a square) of a marked one.
fn dilate(marked: &[bool], width: usize, reach: usize) -> Vec<bool> {
    let height = marked.len() / width.max(1);
    let mut out = vec![false; marked.len()];
    for (i, _) in marked.iter().enumerate().filter(|(_, m)| **m) {
        let (x, y) = (i % width, i / width);
        for yy in y.saturating_sub(reach)..=(y + reach).min(height - 1) {
            for xx in x.saturating_sub(reach)..=(x + reach).min(width - 1) {
                out[yy * width + xx] = true;
            }
        }
    }
    out
}

fn region(p: &FramePair, la: &[f32], pixels: &[usize]) -> Region {
    let n = pixels.len().max(1) as f64;
    let mean = |f: &dyn Fn(usize) -> f64| pixels.iter().map(|&i| f(i)).sum::<f64>() / n;
    let diff = |i: usize| (p.test[i] - p.reference[i]) as f64;
    Region {
        pixels: pixels.len(),
        reference_mean: mean(&|i| p.reference[i] as f64),
        adaptation_mean: mean(&|i| la[i] as f64),
        reference_clipped: mean(&|i| f64::from(u8::from(p.reference_clipped[i]))),
        test_clipped: mean(&|i| f64::from(u8::from(p.test_clipped[i]))),
        differing: mean(&|i| f64::from(u8::from(diff(i) != 0.0))),
        mean_difference: mean(&diff),
        rms_difference: mean(&|i| diff(i).powi(2)).sqrt(),
        rms_contrast: mean(&|i| (diff(i) / la[i] as f64).powi(2)).sqrt(),
    }
}

/// The explanation as Markdown.
pub fn markdown(title: &str, frames: &[FrameExplanation]) -> String {
    let mut s = format!("# Where the model sees the difference: {title}\n\n");
    s.push_str(
        "| frame | Q_t | centre (x, y) | region | pixels | reference cd/m^2 | L_a cd/m^2 | \
         clipped ref / test | differing | mean T-R cd/m^2 | RMS T-R cd/m^2 | RMS contrast |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for f in frames {
        for (name, r) in [("window (1 sd)", &f.window), ("whole frame", &f.whole)] {
            let _ = writeln!(
                s,
                "| {} | {:.3} | {}, {} | {name} | {} | {:.2} | {:.2} | {:.3} / {:.3} | {:.3} | \
                 {:+.4} | {:.4} | {:.4} |",
                f.frame,
                f.q,
                f.centre.0,
                f.centre.1,
                r.pixels,
                r.reference_mean,
                r.adaptation_mean,
                r.reference_clipped,
                r.test_clipped,
                r.differing,
                r.mean_difference,
                r.rms_difference,
                r.rms_contrast
            );
        }
    }
    s.push_str(
        "\nShare of each frame's pooled difference (D^beta summed over the frame):\n\n\
         | frame | in the window | L_a < 3 | 3-10 | 10-30 | 30-100 | >= 100 cd/m^2 | on clipped \
         pixels | within 2 px of them |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for f in frames {
        let bins: Vec<String> = f.by_adaptation.iter().map(|b| format!("{b:.3}")).collect();
        let _ = writeln!(
            s,
            "| {} | {:.3} | {} | {:.3} | {:.3} |",
            f.frame,
            f.window_share,
            bins.join(" | "),
            f.on_clipped,
            f.near_clipped
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::observer::model::pooling::{Grid, Placement};
    use crate::observer::model::video::frame_differences;

    /// A 96 x 96 frame at 32 ppd: a dark left half (5 cd/m^2) and a bright right half (100),
    /// with a +-1% checker of noise in an 11-pixel square at (70, 30) on the test only.
    fn pair() -> (Viewing, FramePair) {
        let side = 96;
        let reference: Vec<f32> = (0..side * side)
            .map(|i| if i % side < side / 2 { 5.0 } else { 100.0 })
            .collect();
        let test = reference
            .iter()
            .enumerate()
            .map(|(i, &r)| {
                let (x, y) = (i % side, i / side);
                let patch = x.abs_diff(70) < 6 && y.abs_diff(30) < 6;
                let sign = if (x + y) % 2 == 0 { 1.0 } else { -1.0 };
                if patch { r * (1.0 + 0.01 * sign) } else { r }
            })
            .collect();
        let viewing = Viewing {
            width: side,
            height: side,
            frames: 1,
            fps: 30.0,
            pixels_per_degree: 32.0,
            mean_luminance: 52.5,
        };
        let none = vec![false; side * side];
        let mut reference_clipped = none.clone();
        reference_clipped[0] = true;
        let pair = FramePair {
            test,
            reference,
            test_clipped: none,
            reference_clipped,
        };
        (viewing, pair)
    }

    #[test]
    fn the_window_lands_on_the_difference_and_its_q_is_the_predictions() {
        let (v, p) = pair();
        let mut filters = Filters::new(v, FITTED.channels, shape::FITTED).unwrap();
        let e = explain(&mut filters, FITTED, std::slice::from_ref(&p)).unwrap();
        let f = &e[0];
        assert!(
            f.centre.0.abs_diff(70) <= 2 && f.centre.1.abs_diff(30) <= 2,
            "{f:?}"
        );
        let mut filters = Filters::new(v, FITTED.channels, shape::FITTED).unwrap();
        let q = frame_differences(
            &mut filters,
            &Grid::one(FITTED),
            Placement::MostVisible,
            |_| Ok((p.test.clone(), p.reference.clone())),
        )
        .unwrap()[0][0];
        assert!((f.q / q - 1.0).abs() < 1e-6, "{} vs {q}", f.q);
        // The window (1 sd = 16 px) holds the whole 11 x 11 patch, on the bright side.
        assert!((f.window.reference_mean - 100.0).abs() < 1e-3, "{f:?}");
        assert_eq!(f.whole.differing, 121.0 / (96.0 * 96.0));
        assert!(f.window.mean_difference.abs() < 0.02 && f.window.rms_difference > 0.3);
        // All the pooled difference is where L_a >= 30 (the bright half, blurred by 0.5 deg
        // = 16 px, is above 30 cd/m^2 more than 5 px from the step: the patch is 16 away).
        let bright: f64 = f.by_adaptation[3..].iter().sum();
        assert!(bright > 0.99, "{:?}", f.by_adaptation);
        assert!((f.by_adaptation.iter().sum::<f64>() - 1.0).abs() < 1e-6);
        assert!(f.on_clipped < 1e-6 && f.near_clipped < 1e-6);
        assert!(f.window_share > 0.0 && f.window_share <= 1.0);
        assert!(markdown("t", &e).contains("| 0 |"));
    }
}
