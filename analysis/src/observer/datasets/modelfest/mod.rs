//! The ModelFest data set (Carney et al. 1999; Watson & Ahumada 2005, JOV 5(9):6): 43 foveal
//! detection stimuli with 16 observers' thresholds, loaded from the folder layout of
//! `analysis/tests/data/modelfest/` (its README gives the provenance), and each stimulus run
//! through the model's own pipeline ([`video`]) under ModelFest's viewing conditions.
//!
//! A stimulus is a contrast image c(x) (background 0, peak |c| = 1) shown at peak contrast C
//! with ModelFest's time course: L(x, t) = L0 (1 + C g(t) c(x)), L0 = 30 cd/m^2, 120 pixels
//! per degree, g a Gaussian of sd 0.125 s cut to the central 0.5 s. The model sees it as a
//! 1 s video at 30 fps (the suite's frame rate, so the temporal channels are the suite's; the
//! time course has no energy above 4 Hz, far below the 15 Hz Nyquist limit) holding one
//! presentation, against the uniform field L0. On a uniform reference nothing masks and the
//! local adaptation is L0, so Q grows linearly with C: the model's threshold is the C at which
//! k Q reaches the 2IFC 84% point ([`two_ifc_d_prime_for`]).
//!
//! [`video`]: crate::observer::model::video
//! [`two_ifc_d_prime_for`]: crate::observer::model::proportion_correct::two_ifc_d_prime_for

use crate::observer::model::pooling::{ChannelSums, Grid, Placement, Pooling, video_q};
use crate::observer::model::shape::Shape;
use crate::observer::model::video::linear::Linear;
use crate::observer::model::video::{Filters, Viewing, frame_differences};
use anyhow::{Context, Result, bail};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

pub mod fit;

/// Mean luminance of the ModelFest display, cd/m^2.
pub const MEAN_LUMINANCE: f64 = 30.0;
/// Pixels per degree of the ModelFest display.
pub const PIXELS_PER_DEGREE: f64 = 120.0;
/// Standard deviation of the Gaussian time course, seconds.
pub const TIME_SD: f64 = 0.125;
/// The time course's duration, seconds (the Gaussian is cut outside it).
pub const DURATION: f64 = 0.5;
/// Frame rate and length of the video the model sees.
pub const FPS: f64 = 30.0;
pub const VIDEO_SECONDS: f64 = 1.0;
/// Side of every ModelFest stimulus, pixels (256 px at 120 px/deg: 2.13 deg). The model's
/// viewing assumes it: another size would be another experiment.
pub const SIDE: usize = 256;
/// Leave-one-out needs at least two stimuli.
const MIN_STIMULI: usize = 2;
/// The peak contrast the pipeline is run at (Q is linear in it; any small value gives the same
/// sensitivity).
const PROBE_CONTRAST: f64 = 0.01;

/// One stimulus with its measured threshold.
#[derive(Clone, Debug)]
pub struct Stimulus {
    pub number: u32,
    pub name: String,
    /// The name without its trailing number ("GaborPatch", "Gaussians", ...).
    pub family: String,
    pub width: usize,
    pub height: usize,
    /// c(x), row-major, scaled to peak |c| = 1.
    pub contrast: Vec<f32>,
    /// Mean over observers and repeats of log10(1 / threshold peak contrast).
    pub measured: f64,
    /// Number of (observer, repeat) thresholds averaged.
    pub observations: usize,
}

/// An entry of `stimuli.json`.
#[derive(Deserialize)]
struct Entry {
    number: u32,
    name: String,
    file: PathBuf,
}

/// A row of `thresholds.csv`.
#[derive(Deserialize)]
struct Row {
    stimulus: u32,
    log10_sensitivity: f64,
}

/// Load the data set in `dir` (`stimuli.json`, `thresholds.csv`, `stimuli/*.png`).
pub fn load(dir: &Path) -> Result<Vec<Stimulus>> {
    let index = dir.join("stimuli.json");
    let text = std::fs::read_to_string(&index).with_context(|| {
        format!(
            "cannot read {}: expected the ModelFest folder (stimuli.json, thresholds.csv, stimuli/)",
            index.display()
        )
    })?;
    let entries: Vec<Entry> = serde_json::from_str(&text).with_context(|| {
        format!(
            "{}: expected a list of {{number, name, file}}",
            index.display()
        )
    })?;
    if entries.len() < MIN_STIMULI {
        bail!(
            "{}: {} stimuli; expected at least {MIN_STIMULI} (the fit's leave-one-out error \
             leaves each out in turn)",
            index.display(),
            entries.len()
        );
    }
    let thresholds = read_thresholds(&dir.join("thresholds.csv"))?;
    entries
        .into_iter()
        .map(|e| {
            let Some(list) = thresholds.get(&e.number) else {
                bail!(
                    "{}: stimulus {} has no thresholds",
                    dir.join("thresholds.csv").display(),
                    e.number
                );
            };
            let path = dir.join(&e.file);
            let (width, height, contrast) = read_contrast(&path)?;
            Ok(Stimulus {
                number: e.number,
                family: e
                    .name
                    .trim_end_matches(|c: char| c.is_ascii_digit())
                    .to_string(),
                name: e.name,
                width,
                height,
                contrast,
                measured: list.iter().sum::<f64>() / list.len() as f64,
                observations: list.len(),
            })
        })
        .collect()
}

/// Every threshold of each stimulus.
fn read_thresholds(path: &Path) -> Result<BTreeMap<u32, Vec<f64>>> {
    let mut reader =
        csv::Reader::from_path(path).with_context(|| format!("cannot read {}", path.display()))?;
    let mut out: BTreeMap<u32, Vec<f64>> = BTreeMap::new();
    for (i, row) in reader.deserialize::<Row>().enumerate() {
        let row = row.with_context(|| {
            format!(
                "{} line {}: expected stimulus, name, observer, repeat, log10_sensitivity",
                path.display(),
                i + 2
            )
        })?;
        if !row.log10_sensitivity.is_finite() {
            bail!(
                "{} line {}: field `log10_sensitivity` is {}; expected a finite number \
                 (log10 of 1 / the threshold's peak contrast)",
                path.display(),
                i + 2,
                row.log10_sensitivity
            );
        }
        out.entry(row.stimulus)
            .or_default()
            .push(row.log10_sensitivity);
    }
    Ok(out)
}

/// A 16-bit grey PNG of [`SIDE`] x [`SIDE`] as contrast c = 2 v / 65535 - 1, scaled to peak
/// |c| = 1.
fn read_contrast(path: &Path) -> Result<(usize, usize, Vec<f32>)> {
    let img = image::open(path)
        .with_context(|| format!("cannot read the stimulus image {}", path.display()))?;
    let (w, h) = (img.width() as usize, img.height() as usize);
    if (w, h) != (SIDE, SIDE) {
        bail!(
            "{}: the stimulus is {w} x {h} pixels; expected {SIDE} x {SIDE} (ModelFest's \
             images, shown at {PIXELS_PER_DEGREE} pixels per degree)",
            path.display()
        );
    }
    let color = img.color();
    if color != image::ColorType::L16 {
        bail!(
            "{}: the stimulus has {} channel(s) of {} bits; expected a 16-bit grey PNG \
             (ModelFest's contrast images)",
            path.display(),
            color.channel_count(),
            color.bits_per_pixel() / color.channel_count() as u16
        );
    }
    let img = img.into_luma16();
    let c: Vec<f64> = img
        .pixels()
        .map(|p| 2.0 * p.0[0] as f64 / 65535.0 - 1.0)
        .collect();
    let peak = c.iter().fold(0f64, |m, v| m.max(v.abs()));
    // The background, c = 0, lies between the 16-bit codes 32767 and 32768 (|c| = 1/65535
    // either side): a stimulus no pixel of which is further from it is blank.
    if peak <= 1.5 / 65535.0 {
        bail!(
            "{}: the stimulus is blank (every pixel at the background)",
            path.display()
        );
    }
    Ok((w, h, c.iter().map(|v| (v / peak) as f32).collect()))
}

/// The time course g at frame `n` of the video: a Gaussian of sd [`TIME_SD`] centred in the
/// video, zero beyond [`DURATION`] / 2 of the centre.
pub fn time_course(n: usize) -> f64 {
    let t = (n as f64 - frames() as f64 / 2.0) / FPS;
    if t.abs() > DURATION / 2.0 + 1e-9 {
        return 0.0;
    }
    (-0.5 * (t / TIME_SD).powi(2)).exp()
}

/// Frames of the video the model sees.
pub fn frames() -> usize {
    (VIDEO_SECONDS * FPS).round() as usize
}

/// The viewing of a stimulus: ModelFest's display, the video the model sees.
pub fn viewing(s: &Stimulus) -> Viewing {
    Viewing {
        width: s.width,
        height: s.height,
        frames: frames(),
        fps: FPS,
        pixels_per_degree: PIXELS_PER_DEGREE,
        mean_luminance: MEAN_LUMINANCE,
    }
}

/// Q per unit peak contrast of a stimulus for every pooling of `grid` and CSF shape of
/// `shapes`, in the order of [`fit::params`] (channel exponent, shape, space
/// exponent, aperture).
///
/// The stimulus is a static image times a time course on a uniform field, where nothing
/// masks and the local adaptation is L0: every stage before the pooling is linear and
/// separable, d_{b,k}(x, t) = g_k(t) d_{b,k}(x), g_k the time course through channel k. So
/// each band is filtered once rather than at every frame ([`Linear::static_bands`]); the
/// result is the pipeline's ([`frame_differences`]) to float rounding (test below), at a
/// thirtieth of the transforms, which is what lets the fit search a grid of shapes.
pub fn response(s: &Stimulus, grid: &Grid, shapes: &[Shape]) -> Result<Vec<f64>> {
    let mut out = Vec::new();
    for &channels in &grid.channels {
        for &shape in shapes {
            let mut linear = Linear::new(viewing(s), channels, shape)?;
            let bands = linear.static_bands(&s.contrast);
            let [gs, gt] = linear.time_courses(time_course);
            let one = Grid {
                channels: vec![channels],
                ..grid.clone()
            };
            let mut sums = ChannelSums::new(&[channels], s.contrast.len());
            let per_frame: Vec<Vec<f64>> = gs
                .iter()
                .zip(&gt)
                .map(|(&fs, &ft)| {
                    sums.clear();
                    for [a, b] in &bands {
                        sums.add_scaled(a, b, fs, ft);
                    }
                    sums.frame_q(&one, PIXELS_PER_DEGREE, s.width, Placement::Centre)
                })
                .collect();
            for (i, p) in one.space_pairs(channels).iter().enumerate() {
                let q: Vec<f64> = per_frame.iter().map(|f| f[i]).collect();
                out.push(video_q(&q, p.space));
            }
        }
    }
    Ok(out)
}

/// The same through the whole pipeline, frame by frame, at [`PROBE_CONTRAST`] (the suite's
/// code path: adaptation, channels, bands, masking).
pub fn response_by_frames(s: &Stimulus, pooling: Pooling, shape: Shape) -> Result<f64> {
    response_by_frames_in(s, pooling, shape, &|f| f)
}

/// As [`response_by_frames`], with the filters set up by `stage` (a decision stage other than
/// the difference, e.g. the side-by-side stage with orientation channels).
pub fn response_by_frames_in(
    s: &Stimulus,
    pooling: Pooling,
    shape: Shape,
    stage: &dyn Fn(Filters) -> Filters,
) -> Result<f64> {
    let background = vec![MEAN_LUMINANCE as f32; s.contrast.len()];
    let mut filters = stage(Filters::new(viewing(s), pooling.channels, shape)?);
    let per_frame = frame_differences(&mut filters, &Grid::one(pooling), Placement::Centre, |n| {
        let a = (MEAN_LUMINANCE * PROBE_CONTRAST * time_course(n)) as f32;
        let test = s
            .contrast
            .iter()
            .map(|&c| MEAN_LUMINANCE as f32 + a * c)
            .collect();
        Ok((test, background.clone()))
    })?;
    let q: Vec<f64> = per_frame.iter().map(|f| f[0]).collect();
    Ok(video_q(&q, pooling.space) / PROBE_CONTRAST)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_separable_response_is_the_pipelines() {
        // A 64 x 64 Gabor (8 cpd, oblique) and a pixel of noise-like texture: every pooling
        // and shape the fit may pick, against the frame-by-frame pipeline.
        let (w, h) = (64usize, 64usize);
        let contrast: Vec<f32> = (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f32 - 32.0, (i / w) as f32 - 32.0);
                let g = (-(x * x + y * y) / 128.0).exp();
                g * (0.4 * (x + y)).cos() + if i % 97 == 0 { 0.3 } else { 0.0 }
            })
            .collect();
        let s = Stimulus {
            number: 1,
            name: "T1".into(),
            family: "T".into(),
            width: w,
            height: h,
            contrast,
            measured: 1.0,
            observations: 1,
        };
        let grid = Grid {
            channels: vec![1.0, 2.0],
            space: vec![1.6, 2.8],
            apertures: vec![f64::INFINITY, 0.1],
        };
        let shapes = [
            crate::observer::model::shape::NONE,
            Shape {
                narrowing: 0.05,
                centre_cpd: 8.0,
                oblique: 0.3,
                rolloff_cpd: 20.0,
                rolloff_power: 3.0,
                scale: 1.2,
            },
        ];
        let fast = response(&s, &grid, &shapes).unwrap();
        let params = super::fit::params(&grid, &shapes);
        assert_eq!(fast.len(), params.len());
        for (p, q) in params.iter().zip(&fast) {
            let slow = response_by_frames(&s, p.pooling, p.shape).unwrap();
            assert!((q / slow - 1.0).abs() < 1e-3, "{p:?}: {q} vs {slow}");
        }
    }

    /// A data set of `n` copies of stimulus 1's image (or `image`) with one threshold each.
    fn data_set(
        n: usize,
        image: Option<image::DynamicImage>,
        threshold: &str,
    ) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("stimuli")).unwrap();
        let gabor = || {
            image::ImageBuffer::from_fn(SIDE as u32, SIDE as u32, |x, y| {
                let r2 = (x as f64 - 128.0).powi(2) + (y as f64 - 128.0).powi(2);
                let c = (-r2 / 800.0).exp() * (x as f64 * 0.3).cos();
                image::Luma([(32767.5 + 32767.0 * c).round() as u16])
            })
        };
        let img = image.unwrap_or_else(|| image::DynamicImage::ImageLuma16(gabor()));
        let mut entries = Vec::new();
        let mut csv = String::from("stimulus,name,observer,repeat,log10_sensitivity\n");
        for k in 1..=n {
            let file = format!("stimuli/{k:02}_T{k}.png");
            img.save(dir.path().join(&file)).unwrap();
            entries.push(serde_json::json!({"number": k, "name": format!("T{k}"), "file": file}));
            csv += &format!("{k},T{k},abc,1,{threshold}\n");
        }
        let json = serde_json::to_string(&entries).unwrap();
        std::fs::write(dir.path().join("stimuli.json"), json).unwrap();
        std::fs::write(dir.path().join("thresholds.csv"), csv).unwrap();
        dir
    }

    fn load_err(dir: &tempfile::TempDir) -> String {
        format!("{:#}", load(dir.path()).unwrap_err())
    }

    #[test]
    fn a_well_formed_data_set_loads() {
        let dir = data_set(2, None, "1.5");
        let s = load(dir.path()).unwrap();
        assert_eq!((s.len(), s[0].width, s[1].measured), (2, SIDE, 1.5));
    }

    #[test]
    fn a_wrong_size_or_depth_is_refused_naming_the_file() {
        let big = image::DynamicImage::ImageLuma16(image::ImageBuffer::from_pixel(
            512,
            512,
            image::Luma([40000u16]),
        ));
        let e = load_err(&data_set(2, Some(big), "1.5"));
        assert!(
            e.contains("01_T1.png: the stimulus is 512 x 512 pixels; expected 256 x 256"),
            "{e}"
        );
        let tiny = image::DynamicImage::ImageLuma16(image::ImageBuffer::from_pixel(
            1,
            1,
            image::Luma([0u16]),
        ));
        assert!(load_err(&data_set(2, Some(tiny), "1.5")).contains("is 1 x 1 pixels"));
        let eight = image::DynamicImage::ImageLuma8(image::ImageBuffer::from_pixel(
            256,
            256,
            image::Luma([200u8]),
        ));
        let e = load_err(&data_set(2, Some(eight), "1.5"));
        assert!(
            e.contains(
                "01_T1.png: the stimulus has 1 channel(s) of 8 bits; expected a 16-bit grey PNG"
            ),
            "{e}"
        );
    }

    #[test]
    fn a_blank_16_bit_stimulus_is_refused() {
        // Both codes next to the background are blank; one code further is not.
        for v in [32767u16, 32768] {
            let flat = image::DynamicImage::ImageLuma16(image::ImageBuffer::from_pixel(
                256,
                256,
                image::Luma([v]),
            ));
            let e = load_err(&data_set(2, Some(flat), "1.5"));
            assert!(e.contains("01_T1.png: the stimulus is blank"), "{v}: {e}");
        }
        let mut faint = image::ImageBuffer::from_pixel(256, 256, image::Luma([32768u16]));
        faint.put_pixel(5, 5, image::Luma([32770u16]));
        let dir = data_set(2, Some(image::DynamicImage::ImageLuma16(faint)), "1.5");
        assert!(load(dir.path()).is_ok());
    }

    #[test]
    fn a_threshold_not_finite_is_refused_with_its_line() {
        for t in ["NaN", "inf", "-inf"] {
            let e = load_err(&data_set(2, None, t));
            assert!(
                e.contains("thresholds.csv line 2: field `log10_sensitivity` is"),
                "{t}: {e}"
            );
        }
    }

    #[test]
    fn fewer_than_two_stimuli_are_refused_naming_the_index() {
        for n in [0, 1] {
            let e = load_err(&data_set(n, None, "1.5"));
            assert!(
                e.contains(&format!("stimuli.json: {n} stimuli; expected at least 2")),
                "{e}"
            );
        }
    }

    #[test]
    fn the_time_course_is_a_cut_gaussian_centred_in_the_video() {
        assert_eq!(frames(), 30);
        assert_eq!(time_course(15), 1.0);
        // 0.25 s from the centre = 2 sd: exp(-2); one frame further, nothing.
        assert!(
            (time_course(15 + 7) - (-0.5f64 * (7.0 / 30.0 / 0.125f64).powi(2)).exp()).abs() < 1e-12
        );
        assert!((time_course(30 / 2 - 7) - time_course(15 + 7)).abs() < 1e-12);
        assert_eq!(time_course(0), 0.0);
        assert_eq!(time_course(23), 0.0);
    }
}
