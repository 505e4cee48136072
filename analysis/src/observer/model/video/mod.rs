//! The visible difference between a test video and its reference, frame by frame:
//!
//! 1. luminance frames (cd/m^2, [`super::display`]);
//! 2. local adaptation: the reference frame blurred by a Gaussian of 0.5 deg (the local
//!    adaptation of FovVideoVDP's simple mode, Mantiuk et al. 2021), floored at 1 cd/m^2;
//!    contrasts relative to it: the difference e = (T - R) / L_a and the reference's own
//!    c = R / L_a - 1 (its structure, the masker) ([`linear`]);
//! 3. temporal channels: sustained and transient filters over the looped frames
//!    ([`super::temporal`]);
//! 4. spatial bands, each weighted per frequency by its channel's CSF at the reference's mean
//!    luminance and a fixed area ([`CSF_AREA_DEG2`]) ([`super::bands`], [`super::csf`]):
//!    d_{b,k} and m_{b,k};
//! 5. the decision stage ([`super::decision_stage`]): the difference stage's masking,
//!    d_{b,k} / T_e(m_{b,k}) ([`super::masking`]), or the side-by-side stage's comparison of
//!    the two videos' local amplitudes ([`side_by_side`]);
//! 6. pooling over bands and channels, then a Minkowski sum over space, per frame
//!    ([`super::pooling`]).
//!
//! Each signal's two channels travel packed as one complex image (e_S + i e_T, c_S + i c_T):
//! every filter is real and even in frequency, so one transform serves both channels (half the
//! transforms), and e is never packed with c, so identical videos give e = 0 exactly, hence
//! Q = 0 exactly.
//!
//! Files: [`viewing`] (size, timing, the constants), [`linear`] (steps 2-4), [`side_by_side`]
//! (that stage on a frame); here, [`Filters`], the pipeline ([`frame_sums`],
//! [`frame_differences`]) and the difference stage.

pub mod linear;
pub mod side_by_side;
pub mod viewing;

pub use viewing::{ADAPTATION_FLOOR, ADAPTATION_SIGMA_DEG, CSF_AREA_DEG2, Viewing};

use super::decision_stage::{DecisionStage, SideBySide};
use super::masking::threshold_elevation;
use super::pooling::{ChannelSums, Grid, Placement};
use super::shape::Shape;
use anyhow::{Result, bail};
use linear::Linear;
use rustfft::num_complex::Complex32;
use side_by_side::{SideBySideFilters, read_at_aperture};
use std::collections::BTreeMap;

/// Everything that depends only on the viewing and the decision stage: the linear stages'
/// transforms, weights and kernels, and the side-by-side stage's if it runs.
pub struct Filters {
    linear: Linear,
    /// `None`: the difference stage.
    side_by_side: Option<SideBySideFilters>,
}

impl Filters {
    /// The filters of a viewing with the difference stage, for pooling over bands and
    /// channels with exponent `channel_exponent` (beta_c; [`Linear::new`]); `shape` corrects
    /// the CSF's weights ([`super::shape`]).
    pub fn new(v: Viewing, channel_exponent: f64, shape: Shape) -> Result<Self> {
        Ok(Self {
            linear: Linear::new(v, channel_exponent, shape)?,
            side_by_side: None,
        })
    }

    /// These filters deciding with `stage`, the side-by-side stage as committed
    /// ([`SideBySide::committed`]) at space exponent `space` (beta).
    pub fn with_stage(self, stage: DecisionStage, space: f64) -> Self {
        match stage {
            DecisionStage::Difference => Self {
                side_by_side: None,
                ..self
            },
            DecisionStage::SideBySide => self.side_by_side(SideBySide::committed(space)),
        }
    }

    /// These filters deciding with the side-by-side stage set as `s`.
    pub fn side_by_side(mut self, s: SideBySide) -> Self {
        self.side_by_side = Some(SideBySideFilters::new(&self.linear, s));
        self
    }

    /// The linear stages: adaptation, channels, bands.
    pub fn linear(&mut self) -> &mut Linear {
        &mut self.linear
    }

    pub fn viewing(&self) -> Viewing {
        self.linear.viewing()
    }
}

/// Per-frame visible difference Q_t of a video pair, for each space exponent and aperture of
/// `pooling` (`out[t][i]` in the order of [`Grid::space_pairs`]; its channel exponents are
/// ignored: the filters hold theirs), an aperture placed by `placement`; `load(t)` gives frame
/// t's luminance (test, reference). Frames are loaded as the temporal window reaches them and
/// dropped after.
pub fn frame_differences(
    filters: &mut Filters,
    pooling: &Grid,
    placement: Placement,
    load: impl FnMut(usize) -> Result<(Vec<f32>, Vec<f32>)>,
) -> Result<Vec<Vec<f64>>> {
    let v = filters.viewing();
    let grid = Grid {
        channels: vec![filters.linear.channel_exponent()],
        ..pooling.clone()
    };
    let mut out = Vec::with_capacity(v.frames);
    let read = filters
        .side_by_side
        .as_ref()
        .is_some_and(SideBySideFilters::reads_at_aperture);
    frame_sums(filters, load, |_, sums| {
        out.push(if read {
            read_at_aperture(sums, &grid, v, placement)
        } else {
            sums.frame_q(&grid, v.pixels_per_degree, v.width, placement)
        })
    })?;
    Ok(out)
}

/// The pipeline up to the pooling over space: `each(t, sums)` receives frame t's per-pixel
/// sums over bands and channels, sum_b (|d_S| + |d_T|)^beta_c, with beta_c the filters'
/// ([`frame_differences`] pools them; `predict::explain` maps them).
pub fn frame_sums(
    filters: &mut Filters,
    mut load: impl FnMut(usize) -> Result<(Vec<f32>, Vec<f32>)>,
    mut each: impl FnMut(usize, &ChannelSums),
) -> Result<()> {
    let Filters {
        linear,
        side_by_side,
    } = filters;
    let v = linear.viewing();
    let f = v.frames as i64;
    let pixels = v.width * v.height;
    let offsets = linear.offsets();
    let mut cache: BTreeMap<usize, Vec<Complex32>> = BTreeMap::new();
    let mut e_pack = vec![Complex32::default(); pixels];
    let mut c_pack = vec![Complex32::default(); pixels];
    let mut difference = Difference::new(pixels);
    let mut sums = ChannelSums::new(&[linear.channel_exponent()], pixels);
    for t in 0..f {
        let needed: Vec<usize> = offsets
            .iter()
            .map(|o| (t + o).rem_euclid(f) as usize)
            .collect();
        cache.retain(|i, _| needed.contains(i));
        for &i in &needed {
            if let std::collections::btree_map::Entry::Vacant(slot) = cache.entry(i) {
                let (test, reference) = load(i)?;
                if test.len() != pixels || reference.len() != pixels {
                    bail!(
                        "frame {i} has {} and {} pixels; expected {pixels}",
                        test.len(),
                        reference.len()
                    );
                }
                slot.insert(linear.contrast(&test, &reference));
            }
        }
        sums.clear();
        linear.channels(t, &cache, &mut e_pack, &mut c_pack);
        match side_by_side {
            Some(s) => s.add_frame(linear, (&e_pack, &c_pack), &mut sums),
            None => difference.add_frame(linear, (&e_pack, &c_pack), &mut sums),
        }
        each(t as usize, &sums);
    }
    Ok(())
}

/// The difference stage's scratch: each band's images and their masked channels.
struct Difference {
    e_band: Vec<Complex32>,
    c_band: Vec<Complex32>,
    sustained: Vec<f32>,
    transient: Vec<f32>,
}

impl Difference {
    fn new(pixels: usize) -> Self {
        Self {
            e_band: vec![Complex32::default(); pixels],
            c_band: vec![Complex32::default(); pixels],
            sustained: vec![0.0; pixels],
            transient: vec![0.0; pixels],
        }
    }

    /// Every band of the difference, d_{b,k} / T_e(m_{b,k}) (masked by the reference's band
    /// contrast at the same place), into `sums`.
    fn add_frame(
        &mut self,
        linear: &mut Linear,
        (e_pack, c_pack): (&[Complex32], &[Complex32]),
        sums: &mut ChannelSums,
    ) {
        for b in 0..linear.bands() {
            linear.band(e_pack, b, None, &mut self.e_band);
            linear.band(c_pack, b, None, &mut self.c_band);
            for (((s, t), e), c) in self
                .sustained
                .iter_mut()
                .zip(self.transient.iter_mut())
                .zip(&self.e_band)
                .zip(&self.c_band)
            {
                *s = e.re / threshold_elevation(c.re);
                *t = e.im / threshold_elevation(c.im);
            }
            sums.add(&self.sustained, &self.transient);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::csf::sensitivity;
    use super::super::masking::EPSILON;
    use super::super::pooling::{FITTED, Pooling};
    use super::super::shape::{self, NONE};
    use super::*;
    use renderer::hash::{hash, unit_f64};
    use std::f64::consts::PI;

    fn viewing(frames: usize) -> Viewing {
        Viewing {
            width: 64,
            height: 64,
            frames,
            fps: 30.0,
            pixels_per_degree: 32.0,
            mean_luminance: 100.0,
        }
    }

    /// Q (exponents `e`) of a drifting grating of contrast `c`, `cycles` per video width,
    /// `j` cycles per loop of `frames` frames, on a uniform reference of 100 cd/m^2.
    fn grating_q(v: Viewing, c: f64, cycles: f64, j: f64, e: Pooling) -> f64 {
        let mut filters = Filters::new(v, e.channels, NONE).unwrap();
        let q = frame_differences(&mut filters, &Grid::one(e), Placement::Centre, |t| {
            let reference = vec![100f32; v.width * v.height];
            let test = (0..v.width * v.height)
                .map(|i| {
                    let x = (i % v.width) as f64 / v.width as f64;
                    let phase = 2.0 * PI * (cycles * x - j * t as f64 / v.frames as f64);
                    (100.0 * (1.0 + c * phase.cos())) as f32
                })
                .collect();
            Ok((test, reference))
        })
        .unwrap();
        let q: Vec<f64> = q.iter().map(|f| f[0]).collect();
        super::super::pooling::video_q(&q, e.space)
    }

    #[test]
    fn a_drifting_grating_gives_the_csf_weighted_contrast() {
        // 8 frames at 30 fps: temporal frequencies are multiples of 3.75 Hz. With space
        // exponent 2 the pooled D = S c |cos| integrates to (S c)^2 A / 2 over the video's
        // A deg^2, at any channel exponent: 6 and 12 cycles (3 and 6 cpd) fall between band
        // centres (2, 4, 8 cpd), where a window not matched to the exponent would ripple.
        let v = viewing(8);
        let area = (v.width * v.height) as f64 / v.pixels_per_degree.powi(2);
        for channels in [1.0, 2.0, 3.0] {
            let e = Pooling {
                channels,
                space: 2.0,
                aperture_deg: f64::INFINITY,
            };
            for (cycles, j) in [
                (2.0, 0.0),
                (4.0, 1.0),
                (6.0, 0.0),
                (8.0, 2.0),
                (12.0, 1.0),
                (16.0, 1.0),
                (4.0, 4.0),
            ] {
                let rho = cycles * v.pixels_per_degree / v.width as f64;
                let omega = j * v.fps / v.frames as f64;
                let s = sensitivity(rho, omega, 100.0, CSF_AREA_DEG2);
                let q = grating_q(v, 0.5 / s, cycles, j, e);
                let want = 0.5 * (area / 2.0).sqrt();
                assert!(
                    (q - want).abs() < want * 2e-3,
                    "{e:?} {rho} cpd {omega} Hz: {q}"
                );
            }
        }
    }

    /// Q of a static Gabor patch (4 cycles per 64 pixels, sd 8 pixels) in the middle of a
    /// `side`-pixel uniform field.
    fn gabor_q(side: usize, e: Pooling) -> f64 {
        let v = Viewing {
            width: side,
            height: side,
            ..viewing(2)
        };
        let mut filters = Filters::new(v, e.channels, NONE).unwrap();
        let mid = side as f64 / 2.0;
        let q = frame_differences(&mut filters, &Grid::one(e), Placement::Centre, |_| {
            let test = (0..side * side)
                .map(|i| {
                    let (x, y) = ((i % side) as f64 - mid, (i / side) as f64 - mid);
                    let g = (-(x * x + y * y) / (2.0 * 64.0)).exp();
                    (100.0 * (1.0 + 0.01 * g * (2.0 * PI * x / 16.0).cos())) as f32
                })
                .collect();
            Ok((test, vec![100f32; side * side]))
        })
        .unwrap();
        super::super::pooling::video_q(&q.iter().map(|f| f[0]).collect::<Vec<_>>(), e.space)
    }

    #[test]
    fn a_noise_free_border_never_lowers_the_visible_difference() {
        // The same patch (+-4 sd inside the small field, so that the periodic filtering does
        // not wrap it) in a field 2 and 4 times as wide, the border at the reference's
        // luminance: the mean pooling of old gave 1/2 and 1/4 of the small field's Q. The
        // band filters reach past the patch and wrap around the small field (periodic), which
        // moves Q by up to 2e-4 either way: the tolerance.
        for (channels, space) in [(1.0, 1.5), (1.0, 3.0), (2.0, 2.0), (2.0, 4.0), (3.0, 2.6)] {
            let e = Pooling {
                channels,
                space,
                aperture_deg: f64::INFINITY,
            };
            let small = gabor_q(64, e);
            for side in [128, 256] {
                let big = gabor_q(side, e);
                assert!(
                    big >= small * (1.0 - 1e-3),
                    "{e:?}, {side} px: {big} < {small}"
                );
            }
        }
    }

    /// Q of a static test against a static reference (64 x 64 px at 32 ppd, 2 frames), each
    /// given as contrast per pixel on 100 cd/m^2, decided by the stage `comparison`.
    fn static_q(test: &[f32], reference: &[f32], comparison: DecisionStage, e: Pooling) -> f64 {
        let v = viewing(2);
        let mut filters = Filters::new(v, e.channels, NONE)
            .unwrap()
            .with_stage(comparison, e.space);
        let lum = |c: &[f32]| c.iter().map(|&c| 100.0 * (1.0 + c)).collect::<Vec<f32>>();
        let q = frame_differences(&mut filters, &Grid::one(e), Placement::Centre, |_| {
            Ok((lum(test), lum(reference)))
        })
        .unwrap();
        super::super::pooling::video_q(&q.iter().map(|f| f[0]).collect::<Vec<_>>(), e.space)
    }

    /// Deterministic white noise, uniform in [-a, a], one field per `seed`.
    fn noise(seed: u64, a: f32) -> Vec<f32> {
        (0..64 * 64u64)
            .map(|i| a * (2.0 * unit_f64(hash(seed, &[i])) as f32 - 1.0))
            .collect()
    }

    /// A Gabor patch's contrast per pixel (sd 8 px, 12.6 px per cycle),
    /// peak `c`, in the middle of the 64 x 64 field.
    fn gabor(c: f32) -> Vec<f32> {
        (0..64 * 64)
            .map(|i| {
                let (x, y) = ((i % 64) as f32 - 32.0, (i / 64) as f32 - 32.0);
                c * (-(x * x + y * y) / 128.0).exp() * (0.5 * x).cos()
            })
            .collect()
    }

    /// Q of a static pair as [`static_q`], the side-by-side stage with knee `a0`.
    fn knee_q(test: &[f32], reference: &[f32], a0: f32, e: Pooling) -> f64 {
        let v = viewing(2);
        let mut filters = Filters::new(v, e.channels, NONE)
            .unwrap()
            .side_by_side(SideBySide {
                space: e.space,
                knee: a0,
                orientation: None,
            });
        let lum = |c: &[f32]| c.iter().map(|&c| 100.0 * (1.0 + c)).collect::<Vec<f32>>();
        let q = frame_differences(&mut filters, &Grid::one(e), Placement::Centre, |_| {
            Ok((lum(test), lum(reference)))
        })
        .unwrap();
        super::super::pooling::video_q(&q.iter().map(|f| f[0]).collect::<Vec<_>>(), e.space)
    }

    #[test]
    fn side_by_side_against_a_blank_field_is_detection() {
        // ModelFest's case: the reference is uniform, so its amplitude is 0 and R(0) = 0. The
        // test's energy, blurred by a sum-preserving Gaussian of sd sigma, is at most
        // Q^beta / (2 pi sigma^2) anywhere (transducer::knee), so while Q stays under
        // a0 (2 pi sigma^2)^(1/beta) every local amplitude is below the knee, R is the
        // identity and the sum over the frame is the difference's: detection exactly (float
        // rounding aside). With the committed knee that bound is Q = d'_84 / k, ModelFest's
        // threshold, so every ModelFest threshold is predicted as the difference stage does.
        let blank = vec![0.0; 64 * 64];
        let area = 2.0 * PI * ADAPTATION_SIGMA_DEG.powi(2);
        for space in [2.0, 2.4, 3.0] {
            let e = Pooling {
                channels: 2.0,
                space,
                aperture_deg: f64::INFINITY,
            };
            let unit = static_q(&gabor(0.01), &blank, DecisionStage::Difference, e);
            // Scale the Gabor so that its Q is 0.99 of the bound for a0 = 0.3.
            let c = 0.01 * (0.99 * 0.3 * area.powf(1.0 / space) / unit) as f32;
            let d = static_q(&gabor(c), &blank, DecisionStage::Difference, e);
            let s = knee_q(&gabor(c), &blank, 0.3, e);
            assert!(
                d > 0.0 && (s / d - 1.0).abs() < 1e-3,
                "beta {space}: {s} vs {d}"
            );
            // Far above the knee the transducer compresses: less than the difference.
            let d10 = static_q(&gabor(30.0 * c), &blank, DecisionStage::Difference, e);
            let s10 = knee_q(&gabor(30.0 * c), &blank, 0.3, e);
            assert!(s10 < 0.8 * d10, "beta {space}: {s10} vs {d10}");
        }
    }

    #[test]
    fn a_field_filling_grating_at_its_threshold_sits_at_the_knee() {
        // The committed pooling (aperture sd 0.5 deg) and knee: a grating filling a 128 x 128
        // field at 64 px/deg (2 deg, 4 aperture sd) scaled to ModelFest's threshold Q is seen
        // by the side-by-side stage as by the difference stage (its local amplitude is at the
        // knee, so R is still the identity), and 3 times stronger, less (masked by itself).
        let v = Viewing {
            width: 128,
            height: 128,
            pixels_per_degree: 64.0,
            ..viewing(2)
        };
        let e = FITTED;
        let q = |c: f32, comparison: DecisionStage| {
            let mut filters = Filters::new(v, e.channels, NONE)
                .unwrap()
                .with_stage(comparison, e.space);
            let test: Vec<f32> = (0..128 * 128)
                .map(|i| {
                    let x = (i % 128) as f32 / 128.0;
                    100.0 * (1.0 + c * (2.0 * PI as f32 * 8.0 * x).cos())
                })
                .collect();
            let q = frame_differences(&mut filters, &Grid::one(e), Placement::Centre, |_| {
                Ok((test.clone(), vec![100f32; 128 * 128]))
            })
            .unwrap();
            super::super::pooling::video_q(&q.iter().map(|f| f[0]).collect::<Vec<_>>(), e.space)
        };
        let d84 = super::super::proportion_correct::two_ifc_d_prime_for(0.84).unwrap();
        let q84 = d84 / super::super::proportion_correct::DEFAULT_K;
        let c = 0.001 * (q84 / q(0.001, DecisionStage::Difference)) as f32;
        let (d, s) = (
            q(c, DecisionStage::Difference),
            q(c, DecisionStage::SideBySide),
        );
        assert!((d / q84 - 1.0).abs() < 1e-3, "{d} vs {q84}");
        assert!(
            (s / d - 1.0).abs() < 0.03,
            "side by side {s}, difference {d}"
        );
        let d3 = q(3.0 * c, DecisionStage::Difference);
        let s3 = q(3.0 * c, DecisionStage::SideBySide);
        assert!(s3 < 0.8 * d3, "{s3} vs {d3}");
    }

    #[test]
    fn side_by_side_discriminates_a_pedestal_by_a_weber_like_law() {
        // A field-filling grating pedestal of peak p (CSF-weighted threshold units) against
        // the same grating 2% stronger: far above the knee the cue is R'(a) Delta a with
        // R'(a) = (a / a0)^-eps and Delta a = 0.02 a, so Q grows as p^(1 - eps), and the
        // increment at threshold as p^eps (Legge & Foley's rising limb, eps = 0.7). The
        // difference stage's Q grows as p (masking by the pedestal aside).
        let e = Pooling {
            channels: 2.0,
            space: 2.4,
            aperture_deg: f64::INFINITY,
        };
        let s = sensitivity(4.0, 0.0, 100.0, CSF_AREA_DEG2) as f32;
        let grating = |p: f32| -> Vec<f32> {
            (0..64 * 64)
                .map(|i| p / s * (2.0 * PI as f32 * 8.0 * (i % 64) as f32 / 64.0).cos())
                .collect()
        };
        let q = |p: f32| knee_q(&grating(1.02 * p), &grating(p), 0.3, e);
        let (q1, q2, q3) = (q(4.0), q(16.0), q(64.0));
        for (lo, hi) in [(q1, q2), (q2, q3)] {
            let slope = (hi / lo).ln() / 4f64.ln();
            assert!(
                (slope - (1.0 - EPSILON as f64)).abs() < 0.05,
                "slope {slope} ({lo} -> {hi})"
            );
        }
    }

    #[test]
    fn side_by_side_grows_with_the_noise_contrast() {
        // A reference of noise at 2% against the same field stronger: more noise, more visible.
        let e = FITTED;
        let r = noise(3, 0.02);
        let mut last = 0.0;
        for f in [1.1, 1.25, 1.5, 2.0, 3.0, 4.0] {
            let t: Vec<f32> = r.iter().map(|v| v * f).collect();
            let q = static_q(&t, &r, DecisionStage::SideBySide, e);
            assert!(q > last, "x{f}: {q} <= {last}");
            last = q;
        }
    }

    #[test]
    fn side_by_side_sees_the_noise_level_not_its_values() {
        // Two independent noise fields of the same level look alike side by side (their
        // local energies differ only by sampling), while their difference is as large as the
        // noise; twice the level (2^2.4 = 5.3 times the energy) is seen either
        // way. The same field against itself is nothing.
        let e = FITTED;
        let (r, t1, t2) = (noise(1, 0.05), noise(2, 0.05), noise(2, 0.1));
        let same = static_q(&t1, &r, DecisionStage::SideBySide, e);
        let double = static_q(&t2, &r, DecisionStage::SideBySide, e);
        let same_diff = static_q(&t1, &r, DecisionStage::Difference, e);
        assert!(same < 0.5 * double, "{same} vs {double}");
        // The difference carries sqrt 2 times the noise; the energies only their sampling
        // fluctuation, large on this 2-deg field whose 1-2 cpd bands hold a few cycles (1.76
        // times less than the difference when written).
        assert!(same_diff > 1.2 * same, "{same_diff} vs {same}");
        let itself = static_q(&r, &r, DecisionStage::SideBySide, e);
        assert!(itself < 1e-3 * double, "{itself}");
    }

    #[test]
    fn identical_videos_have_no_visible_difference() {
        let v = viewing(3);
        let mut filters = Filters::new(v, FITTED.channels, shape::FITTED).unwrap();
        let q = frame_differences(&mut filters, &Grid::one(FITTED), Placement::Centre, |t| {
            let f: Vec<f32> = (0..64 * 64)
                .map(|i| ((i * 7 + t * 13) % 255) as f32)
                .collect();
            Ok((f.clone(), f))
        })
        .unwrap();
        assert_eq!(q, vec![vec![0.0]; 3]);
    }
}
