//! The visible difference between a test video and its reference, frame by frame:
//!
//! 1. luminance frames (cd/m^2, [`super::display`]);
//! 2. local adaptation: the reference frame blurred by a Gaussian of 0.5 deg (the local
//!    adaptation of FovVideoVDP's simple mode, Mantiuk et al. 2021), floored at 1 cd/m^2;
//!    contrasts relative to it: the difference e = (T - R) / L_a and the reference's own
//!    c = R / L_a - 1 (its structure, the masker);
//! 3. temporal channels: sustained and transient filters over the looped frames
//!    ([`super::temporal`]);
//! 4. spatial bands, each weighted per frequency by its channel's CSF at the reference's mean
//!    luminance and a fixed area ([`CSF_AREA_DEG2`]) ([`super::bands`], [`super::csf`]): d_{b,k} and m_{b,k};
//! 5. masking, d_{b,k} / T_e(m_{b,k}) ([`super::masking`]);
//! 6. pooling over bands and channels, then a Minkowski sum over space, per frame
//!    ([`super::pooling`]).
//!
//! Each signal's two channels travel packed as one complex image (e_S + i e_T, c_S + i c_T):
//! every filter is real and even in frequency, so one transform serves both channels (half the
//! transforms), and e is never packed with c, so identical videos give e = 0 exactly, hence
//! Q = 0 exactly.

use super::bands::{Fft2, band_centres, frequencies, radial_frequencies, window};
use super::csf::{SUSTAINED, TRANSIENT, spatial, sustained_response, transient_response};
use super::local::LocalMean;
use super::masking::{EPSILON, threshold_elevation};
use super::orientation::{self, OrientationMasking};
use super::pooling::{ChannelSums, Grid, Placement};
use super::shape::Shape;
use super::temporal::{Kernel, kernel};
use super::transducer::knee;
use anyhow::{Result, bail};
use rustfft::num_complex::Complex32;
use std::collections::BTreeMap;

/// Standard deviation of the local adaptation's Gaussian, degrees.
pub const ADAPTATION_SIGMA_DEG: f64 = 0.5;
/// Lowest adaptation luminance, cd/m^2 (below it Weber contrast is not a model of vision).
pub const ADAPTATION_FLOOR: f32 = 1.0;
/// The stimulus area at which the CSF is evaluated, deg^2: ModelFest's field (256 pixels at
/// 120 ppd, 2.133 deg square), the data the pooling was fitted on. stelaCSF's area term is
/// spatial summation; the Minkowski pooling ([`super::pooling`]) now sums over the picture,
/// so the CSF keeps the area of the data that fitted that summation instead of the video's
/// (which would count the summation twice on a large video).
pub const CSF_AREA_DEG2: f64 = (256.0 / 120.0) * (256.0 / 120.0);

/// The size and timing of a video pair, and the viewing conditions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Viewing {
    pub width: usize,
    pub height: usize,
    pub frames: usize,
    pub fps: f64,
    pub pixels_per_degree: f64,
    /// The reference's mean luminance over all pixels and frames (the CSF's adaptation level).
    pub mean_luminance: f64,
}

/// How the observer compares a test video with its reference.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Comparison {
    /// The difference T - R at each place: a flicker comparison, or ModelFest's 2IFC against a
    /// blank field (the default; what the model was fitted with).
    #[default]
    Difference,
    /// Side by side or in sequence, as the suite's trials show the pair: each video's local
    /// contrast amplitude per band and orientation channel, masked by the channel's local
    /// energy through the Weber-like transducer of [`super::transducer`], and the two videos'
    /// amplitudes compared channel by channel ([`super::orientation`], [`add_oriented`],
    /// [`read_at_aperture`]; docs/predict.md, "Decision stages"). The scene's content and the
    /// noise both raise the energy, so each masks the other within its channel. Without
    /// orientation channels ([`Filters::orientation_masking`] with `None`) it is the stage as
    /// first built: the channels' amplitudes summed before the comparison.
    SideBySide,
}

/// Everything that depends only on the viewing: transforms, weights, kernels.
pub struct Filters {
    viewing: Viewing,
    fft: Fft2,
    adaptation: Vec<f32>,
    /// Per band, per channel (sustained, transient): window^(1/beta_c) x CSF / (width height).
    bands: Vec<[Vec<f32>; 2]>,
    /// beta_c, the Minkowski exponent over bands and channels ([`super::pooling`]).
    channel_exponent: f64,
    kernels: [Kernel; 2],
    /// With [`Comparison::SideBySide`], the space exponent beta of the energies compared and
    /// the transducer's knee a0.
    side_by_side: Option<(f64, f32)>,
    /// The side-by-side stage's local means.
    local: Option<LocalMean>,
    /// The side-by-side stage's orientation channels ([`super::orientation`]), with each
    /// channel's window W_o^(1/beta_c) per coefficient.
    orientation: Option<(OrientationMasking, Vec<Vec<f32>>)>,
    /// With orientation channels, the cue's neighbourhood: the fitted aperture itself (its
    /// weight on D^beta, a Gaussian of sd s / sqrt(beta)), so the cue is read at the
    /// aperture's place ([`read_at_aperture`]) instead of summed under it.
    cue_local: Option<LocalMean>,
}

impl Filters {
    /// The filters of a viewing, for pooling over bands and channels with exponent
    /// `channel_exponent` (beta_c): each band's window is raised to 1 / beta_c, so the windows'
    /// beta_c-th powers sum to 1 and a grating between two band centres pools to its
    /// CSF-weighted contrast as one at a centre does (no ripple over frequency). `shape`
    /// corrects the CSF's weights ([`super::shape`]).
    pub fn new(v: Viewing, channel_exponent: f64, shape: Shape) -> Result<Self> {
        if v.width == 0 || v.height == 0 || v.frames == 0 {
            bail!(
                "a video of {}x{} pixels and {} frames has nothing to compare",
                v.width,
                v.height,
                v.frames
            );
        }
        if channel_exponent.is_nan() || channel_exponent < 1.0 {
            bail!(
                "the pooling exponent over bands and channels is {channel_exponent}; expected >= 1"
            );
        }
        if !(v.fps > 0.0 && v.pixels_per_degree > 0.0 && v.mean_luminance > 0.0) {
            bail!("frame rate, pixels per degree and mean luminance must be positive: {v:?}");
        }
        let n = (v.width * v.height) as f64;
        let rho = radial_frequencies(v.width, v.height, v.pixels_per_degree);
        let centres = band_centres(v.pixels_per_degree);
        let two_pi2_s2 = 2.0 * std::f64::consts::PI.powi(2) * ADAPTATION_SIGMA_DEG.powi(2);
        let adaptation = rho
            .iter()
            .map(|r| ((-two_pi2_s2 * r * r).exp() / n) as f32)
            .collect();
        let (l, a) = (v.mean_luminance, CSF_AREA_DEG2);
        let gain: Vec<f64> = frequencies(v.width, v.height, v.pixels_per_degree)
            .map(|(fx, fy)| shape.gain(fx, fy))
            .collect();
        let csf: [Vec<f64>; 2] = [SUSTAINED, TRANSIENT].map(|m| {
            rho.iter()
                .zip(&gain)
                .map(|(&r, &g)| g * spatial(&m, shape.csf_frequency(r), l, a))
                .collect()
        });
        let bands = (0..centres.len())
            .map(|b| {
                [0, 1].map(|k| {
                    rho.iter()
                        .zip(&csf[k])
                        .map(|(&r, &s)| {
                            let w = window(&centres, b, r).powf(1.0 / channel_exponent);
                            (w * s / n) as f32
                        })
                        .collect()
                })
            })
            .collect();
        Ok(Self {
            viewing: v,
            fft: Fft2::new(v.width, v.height),
            adaptation,
            bands,
            channel_exponent,
            kernels: [
                kernel(sustained_response, v.frames, v.fps),
                kernel(transient_response, v.frames, v.fps),
            ],
            side_by_side: None,
            local: None,
            orientation: None,
            cue_local: None,
        })
    }

    /// These filters comparing as `comparison` says, with space exponent `space` (beta). The
    /// side-by-side stage's knee is the detection threshold of ModelFest's fit
    /// ([`super::transducer::knee`] with [`super::decision::DEFAULT_K`]), and it compares the
    /// videos per orientation channel ([`super::orientation::COMMITTED`]).
    pub fn comparing(self, comparison: Comparison, space: f64) -> Self {
        let d84 = super::decision::two_ifc_d_prime_for(super::decision::CRITERION)
            .expect("the criterion is inside (0.5, 1)");
        let a0 = knee(
            d84,
            super::decision::DEFAULT_K,
            super::pooling::FITTED.aperture_deg,
            space,
        );
        let oriented = (comparison == Comparison::SideBySide).then_some(orientation::COMMITTED);
        self.comparing_with_knee(comparison, space, a0)
            .orientation_masking(oriented)
    }

    /// As [`Filters::comparing`], with the transducer's knee `a0` given (infinite: no
    /// compression, the local energies compared as they are).
    pub fn comparing_with_knee(mut self, comparison: Comparison, space: f64, a0: f32) -> Self {
        self.side_by_side = (comparison == Comparison::SideBySide).then_some((space, a0));
        let v = self.viewing;
        self.local = self
            .side_by_side
            .map(|_| LocalMean::new(v.width, v.height, v.pixels_per_degree, ADAPTATION_SIGMA_DEG));
        self
    }

    /// The side-by-side stage's masking split into orientation channels (`None`: each band's
    /// masker pools every orientation, the stage as first committed).
    pub fn orientation_masking(mut self, masking: Option<OrientationMasking>) -> Self {
        let v = self.viewing;
        let root = 1.0 / self.channel_exponent;
        self.orientation = masking.map(|m| {
            let k = m.orientations.max(2);
            let windows = (0..k)
                .map(|o| {
                    frequencies(v.width, v.height, v.pixels_per_degree)
                        .map(|(fx, fy)| orientation::window(k, o, fx, fy).powf(root) as f32)
                        .collect()
                })
                .collect();
            (
                OrientationMasking {
                    orientations: k,
                    ..m
                },
                windows,
            )
        });
        self.cue_local = match (&self.orientation, self.side_by_side) {
            (Some(_), Some((space, _))) => Some(LocalMean::new(
                v.width,
                v.height,
                v.pixels_per_degree,
                cue_sd_deg(space),
            )),
            _ => None,
        };
        self
    }

    /// Two real images blurred by the Gaussian of [`ADAPTATION_SIGMA_DEG`] (sum-preserving,
    /// periodic), packed as re and im: one transform pair for both.
    fn blur_pair(&mut self, a: &[f32], b: &[f32]) -> Vec<Complex32> {
        let mut z: Vec<Complex32> = a
            .iter()
            .zip(b)
            .map(|(&x, &y)| Complex32::new(x, y))
            .collect();
        self.fft.forward(&mut z);
        for (z, g) in z.iter_mut().zip(&self.adaptation) {
            *z *= *g;
        }
        self.fft.inverse(&mut z);
        z
    }

    /// The local adaptation luminance of a reference frame: blurred, floored.
    pub fn adaptation(&mut self, reference: &[f32]) -> Vec<f32> {
        let zero = vec![0.0; reference.len()];
        let la = self.blur_pair(reference, &zero);
        la.iter().map(|a| a.re.max(ADAPTATION_FLOOR)).collect()
    }

    /// Packed contrasts e + i c of one frame pair.
    fn contrast(&mut self, test: &[f32], reference: &[f32]) -> Vec<Complex32> {
        let la = self.adaptation(reference);
        test.iter()
            .zip(reference)
            .zip(&la)
            .map(|((&t, &r), &a)| Complex32::new((t - r) / a, r / a - 1.0))
            .collect()
    }
}

impl Filters {
    /// Band `b` of a packed spectrum Z = A + i B of two real images a, b (transposed layout):
    /// out = IFFT(w_S A + i w_T B), so out.re is a's sustained band and out.im b's transient
    /// band. A(k) = (Z(k) + conj Z(-k)) / 2 and B(k) = (Z(k) - conj Z(-k)) / 2i.
    fn band(&mut self, z: &[Complex32], b: usize, out: &mut [Complex32]) {
        self.band_in(z, b, None, out);
    }

    /// As [`Filters::band`], restricted to orientation channel `o` ([`super::orientation`]).
    fn band_in(&mut self, z: &[Complex32], b: usize, o: Option<usize>, out: &mut [Complex32]) {
        let (w, h) = (self.viewing.width, self.viewing.height);
        let [ws, wt] = &self.bands[b];
        let orient = o.and_then(|o| self.orientation.as_ref().map(|(_, win)| &win[o]));
        for kx in 0..w {
            let mx = (w - kx) % w;
            for ky in 0..h {
                let i = kx * h + ky;
                let m = z[mx * h + (h - ky) % h].conj();
                let a = (z[i] + m) * 0.5;
                let bb = (z[i] - m) * Complex32::new(0.0, -0.5);
                let g = orient.map_or(1.0, |win| win[i]);
                out[i] = (a * ws[i] + Complex32::new(0.0, 1.0) * bb * wt[i]) * g;
            }
        }
        self.fft.inverse(out);
    }

    /// The band images of a static contrast image c on a uniform reference, per band
    /// (sustained, transient): the pipeline's d_{b,S} and d_{b,T} for e(x, t) = c(x) before
    /// the temporal channels, with nothing to mask them (the reference's contrast is 0).
    pub fn static_bands(&mut self, contrast: &[f32]) -> Vec<[Vec<f32>; 2]> {
        let mut z: Vec<Complex32> = contrast.iter().map(|&c| Complex32::new(c, c)).collect();
        self.fft.forward(&mut z);
        let mut out = vec![Complex32::default(); z.len()];
        (0..self.bands.len())
            .map(|b| {
                self.band(&z, b, &mut out);
                [
                    out.iter().map(|v| v.re).collect(),
                    out.iter().map(|v| v.im).collect(),
                ]
            })
            .collect()
    }

    /// The sustained and transient channels' outputs at every frame for a time course g
    /// (frame -> value) of the looped video.
    pub fn time_courses(&self, g: impl Fn(usize) -> f64) -> [Vec<f32>; 2] {
        let f = self.viewing.frames as i64;
        self.kernels.clone().map(|k| {
            (0..f)
                .map(|t| {
                    k.taps
                        .iter()
                        .map(|&(o, w)| w * g((t + o).rem_euclid(f) as usize) as f32)
                        .sum()
                })
                .collect()
        })
    }

    /// The channel exponent and viewing these filters were made for.
    pub fn channel_exponent(&self) -> f64 {
        self.channel_exponent
    }

    pub fn viewing(&self) -> Viewing {
        self.viewing
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
    let v = filters.viewing;
    let grid = Grid {
        channels: vec![filters.channel_exponent],
        ..pooling.clone()
    };
    let mut out = Vec::with_capacity(v.frames);
    let read = filters.cue_local.is_some();
    frame_sums(filters, load, |_, sums| {
        out.push(if read {
            read_at_aperture(sums, &grid, v, placement)
        } else {
            sums.frame_q(&grid, v.pixels_per_degree, v.width, placement)
        })
    })?;
    Ok(out)
}

/// The sd (deg) of the oriented side-by-side stage's cue neighbourhood: the fitted aperture's
/// weight on D^beta, exp(-beta r^2 / (2 s^2)), a Gaussian of sd s / sqrt(beta).
fn cue_sd_deg(space: f64) -> f64 {
    super::pooling::FITTED.aperture_deg / space.sqrt()
}

/// Q_t of the oriented side-by-side stage: its cue D is already a local amplitude over the
/// aperture's own window (normalised to sum 1), so Q^beta = 2 pi (s^2 / beta) D^beta read at
/// one place, the aperture's: the centre, or the most visible place. Against a blank field
/// below the knee that is the difference stage's aperture-weighted sum exactly (one channel;
/// several mix through beta_c as they do at a pixel). An infinite aperture sums D^beta over
/// the frame instead.
fn read_at_aperture(sums: &ChannelSums, grid: &Grid, v: Viewing, placement: Placement) -> Vec<f64> {
    let bc = sums.exponents[0];
    let sum = &sums.sums[0];
    let mut out = Vec::new();
    for p in grid.space_pairs(bc) {
        let r = (p.space / bc) as f32;
        let d: Vec<f64> = sum.iter().map(|&x| x.max(0.0).powf(r) as f64).collect();
        let q_beta = if !p.aperture_deg.is_finite() {
            d.iter().sum::<f64>() / v.pixels_per_degree.powi(2)
        } else {
            let read = match placement {
                Placement::MostVisible => d.iter().cloned().fold(0.0, f64::max),
                Placement::Centre => {
                    let (w, h) = (v.width, v.height);
                    let (x0, y0) = ((w - 1) / 2, (h - 1) / 2);
                    let (x1, y1) = (w / 2, h / 2);
                    0.25 * (d[y0 * w + x0] + d[y0 * w + x1] + d[y1 * w + x0] + d[y1 * w + x1])
                }
            };
            2.0 * std::f64::consts::PI * p.aperture_deg.powi(2) / p.space * read
        };
        out.push(q_beta.powf(1.0 / p.space));
    }
    out
}

/// The pipeline up to the pooling over space: `each(t, sums)` receives frame t's per-pixel
/// sums over bands and channels, sum_b (|d_S| + |d_T|)^beta_c, with beta_c the filters'
/// ([`frame_differences`] pools them; [`super::explain`] maps them).
pub fn frame_sums(
    filters: &mut Filters,
    mut load: impl FnMut(usize) -> Result<(Vec<f32>, Vec<f32>)>,
    mut each: impl FnMut(usize, &ChannelSums),
) -> Result<()> {
    let v = filters.viewing;
    let f = v.frames as i64;
    let pixels = v.width * v.height;
    let offsets: Vec<i64> = {
        let mut o: Vec<i64> = filters
            .kernels
            .iter()
            .flat_map(|k| k.taps.iter().map(|t| t.0))
            .collect();
        o.sort_unstable();
        o.dedup();
        o
    };
    let mut cache: BTreeMap<usize, Vec<Complex32>> = BTreeMap::new();
    let mut e_pack = vec![Complex32::default(); pixels];
    let mut c_pack = vec![Complex32::default(); pixels];
    let mut e_band = vec![Complex32::default(); pixels];
    let mut c_band = vec![Complex32::default(); pixels];
    let mut sums = ChannelSums::new(&[filters.channel_exponent], pixels);
    let (mut sustained, mut transient) = (vec![0f32; pixels], vec![0f32; pixels]);
    // Side by side: each video's own sums, the test's contrast e + c and the reference's c,
    // unmasked: the transducer on their local amplitudes does the masking.
    let mut own = [0, 1].map(|_| ChannelSums::new(&[filters.channel_exponent], pixels));
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
                let z = filters.contrast(&test, &reference);
                slot.insert(z);
            }
        }
        sums.clear();
        own.iter_mut().for_each(ChannelSums::clear);
        // The difference's two channels packed as e_S + i e_T, the reference's as c_S + i c_T.
        e_pack.iter_mut().for_each(|z| *z = Complex32::default());
        c_pack.iter_mut().for_each(|z| *z = Complex32::default());
        for (k, kernel) in filters.kernels.iter().enumerate() {
            for &(o, w) in &kernel.taps {
                let src = &cache[&((t + o).rem_euclid(f) as usize)];
                for ((e, c), s) in e_pack.iter_mut().zip(c_pack.iter_mut()).zip(src) {
                    if k == 0 {
                        e.re += s.re * w;
                        c.re += s.im * w;
                    } else {
                        e.im += s.re * w;
                        c.im += s.im * w;
                    }
                }
            }
        }
        filters.fft.forward(&mut e_pack);
        filters.fft.forward(&mut c_pack);
        for b in 0..filters.bands.len() {
            filters.band(&e_pack, b, &mut e_band);
            filters.band(&c_pack, b, &mut c_band);
            if let Some((space, a0)) = filters.side_by_side {
                if filters.orientation.is_some() {
                    let bufs = (&mut e_band[..], &mut c_band[..]);
                    add_oriented(filters, &mut sums, (&e_pack, &c_pack), b, bufs, (space, a0));
                } else {
                    add_videos(filters, &mut own, &e_band, &c_band, space, a0);
                }
                continue;
            }
            for (((s, t), e), c) in sustained
                .iter_mut()
                .zip(transient.iter_mut())
                .zip(&e_band)
                .zip(&c_band)
            {
                *s = e.re / threshold_elevation(c.re);
                *t = e.im / threshold_elevation(c.im);
            }
            sums.add(&sustained, &transient);
        }
        if let (Some((space, _)), None) = (filters.side_by_side, &filters.orientation) {
            side_by_side(filters, &own, space, &mut sums);
        }
        each(t as usize, &sums);
    }
    Ok(())
}

/// Add one band of each video, test (e + c) and reference (c), masked: each video's band
/// magnitude n_V = |v_S| + |v_T| times the gain of the band's local contrast,
/// g = R'(m) = min(1, (m / a0)^-eps) ([`super::transducer`]), with m the local amplitude of the
/// two videos' mean band energy, m = (G * (n_T^beta + n_R^beta) / 2)^(1/beta). Both videos'
/// noise and the scene's content in the band raise m: each masks the other.
fn add_videos(
    filters: &mut Filters,
    own: &mut [ChannelSums; 2],
    e_band: &[Complex32],
    c_band: &[Complex32],
    space: f64,
    a0: f32,
) {
    let (nt, nr): (Vec<f32>, Vec<f32>) = e_band
        .iter()
        .zip(c_band)
        .map(|(e, c)| {
            (
                (e.re + c.re).abs() + (e.im + c.im).abs(),
                c.re.abs() + c.im.abs(),
            )
        })
        .unzip();
    let b = space as f32;
    let energy: Vec<f32> = nt
        .iter()
        .zip(&nr)
        .map(|(t, r)| 0.5 * (t.powf(b) + r.powf(b)))
        .collect();
    let zero = vec![0.0; nt.len()];
    let local = filters.local.as_mut().expect("side-by-side filters");
    let (m, _) = local.pair(&energy, &zero);
    let gain: Vec<f32> = m
        .iter()
        .map(|&m| gain(m.max(0.0).powf(1.0 / b), a0))
        .collect();
    for (sums, n) in own.iter_mut().zip([nt, nr]) {
        let masked: Vec<f32> = n.iter().zip(&gain).map(|(n, g)| n * g).collect();
        sums.add(&masked, &zero);
    }
}

/// One band of each video split into orientation channels ([`super::orientation`]), compared
/// channel by channel: each channel's signal n_V,o is masked by its own local energy and,
/// weighted by w, the mean of the other channels' (m_o^beta = G * (E_o + w mean_{o' != o}
/// E_o'), E the two videos' mean energy n^beta), each video's local amplitude of it taken,
/// a_V,o = (G * (g_o n_V,o)^beta)^(1/beta), and |a_T,o - a_R,o| added to `sums` as one more
/// channel of the Minkowski sum over bands and channels. Comparing per channel, not the
/// videos' summed amplitudes, is what keeps energy in one channel from masking another
/// (summed, a mask adds in quadrature to the target's channel: Meese's orthogonal mask then
/// masks as a parallel one would). `packs` are the spectra of the difference and the
/// reference, `bufs` scratch for their band images.
fn add_oriented(
    filters: &mut Filters,
    sums: &mut ChannelSums,
    packs: (&[Complex32], &[Complex32]),
    b: usize,
    bufs: (&mut [Complex32], &mut [Complex32]),
    (space, a0): (f64, f32),
) {
    let (e_band, c_band) = bufs;
    // The settings only: cloning the whole field would copy every window (K full-size images).
    let m = filters
        .orientation
        .as_ref()
        .map(|(m, _)| *m)
        .expect("oriented filters");
    let beta = space as f32;
    let powers: Vec<[Vec<f32>; 2]> = (0..m.orientations)
        .map(|o| {
            filters.band_in(packs.0, b, Some(o), e_band);
            filters.band_in(packs.1, b, Some(o), c_band);
            band_powers(e_band, c_band, beta)
        })
        .collect();
    let maskers = maskers(filters, &powers, m.cross_weight as f32);
    // g^beta = (m / a0)^(-eps beta) = (m^beta / a0^beta)^-eps above the knee, 1 below: the
    // gain raised to beta is the gain of m^beta at the knee a0^beta, one power instead of a
    // root and two powers.
    let knee = a0.powf(beta);
    let inv = 1.0 / beta;
    let cue_local = filters.cue_local.as_mut().expect("oriented filters");
    for ([nt, nr], masker) in powers.iter().zip(&maskers) {
        let g: Vec<f32> = masker.iter().map(|&e| gain(e, knee)).collect();
        let masked = |n: &[f32]| -> Vec<f32> { n.iter().zip(&g).map(|(n, g)| n * g).collect() };
        let (at, ar) = cue_local.pair(&masked(nt), &masked(nr));
        let cue: Vec<f32> = at
            .iter()
            .zip(&ar)
            .map(|(&t, &r)| (root(t, inv) - root(r, inv)).abs())
            .collect();
        sums.add_one(&cue);
    }
}

/// v^(1 / beta) of a local mean, which can leave -1e-9 where the energy is 0 (clamped), and
/// 0 without a power where it is 0.
fn root(v: f32, inv: f32) -> f32 {
    if v > 0.0 { v.powf(inv) } else { 0.0 }
}

/// Each video's band norm raised to beta, n_T^beta and n_R^beta, from one channel's band
/// images of the difference (e) and the reference (c): the test video is e + c.
fn band_powers(e_band: &[Complex32], c_band: &[Complex32], beta: f32) -> [Vec<f32>; 2] {
    let pow = |v: f32| if v > 0.0 { v.powf(beta) } else { 0.0 };
    e_band
        .iter()
        .zip(c_band)
        .map(|(e, c)| {
            (
                pow((e.re + c.re).abs() + (e.im + c.im).abs()),
                pow(c.re.abs() + c.im.abs()),
            )
        })
        .unzip::<_, _, Vec<f32>, Vec<f32>>()
        .into()
}

/// Each channel's masker m_o^beta = G * (E_o + w mean_{o' != o} E_o'), with E the two videos'
/// mean energy (n_T^beta + n_R^beta) / 2; the local means two channels to a transform pair.
fn maskers(filters: &mut Filters, powers: &[[Vec<f32>; 2]], w: f32) -> Vec<Vec<f32>> {
    let energy = |[t, r]: &[Vec<f32>; 2]| -> Vec<f32> {
        t.iter().zip(r).map(|(t, r)| 0.5 * (t + r)).collect()
    };
    let mut means = Vec::with_capacity(powers.len());
    for two in powers.chunks(2) {
        let a = energy(&two[0]);
        let b = two.get(1).map_or_else(|| vec![0.0; a.len()], energy);
        let (ma, mb) = local_of(filters, &a, &b);
        means.push(ma);
        if two.len() == 2 {
            means.push(mb);
        }
    }
    if w == 0.0 {
        return means;
    }
    let others = w / (means.len() - 1) as f32;
    let total: Vec<f32> = (0..means[0].len())
        .map(|i| means.iter().map(|m| m[i]).sum())
        .collect();
    means
        .iter()
        .map(|own| {
            own.iter()
                .zip(&total)
                .map(|(&e, &all)| e + others * (all - e))
                .collect()
        })
        .collect()
}

/// The side-by-side stage's local means of two images.
fn local_of(filters: &mut Filters, a: &[f32], b: &[f32]) -> (Vec<f32>, Vec<f32>) {
    filters
        .local
        .as_mut()
        .expect("side-by-side filters")
        .pair(a, b)
}

/// dR/da of [`super::transducer::respond`]: 1 up to the knee, (a / a0)^-eps above.
fn gain(a: f32, a0: f32) -> f32 {
    if a <= a0 {
        1.0
    } else {
        (a / a0).powf(-EPSILON)
    }
}

/// The side-by-side cue into `sums`: each video's local amplitude of its masked band norm,
/// a_V = (G * N_V^beta)^(1/beta), and sums = |a_T - a_R|^beta_c, so that the pooling's
/// (sums)^(beta / beta_c) is |a_T - a_R|^beta. Against a blank field below the knee, a_R = 0
/// and a_T^beta = G * D^beta, whose sum over the frame is the difference stage's.
fn side_by_side(filters: &mut Filters, own: &[ChannelSums; 2], space: f64, sums: &mut ChannelSums) {
    let r = (space / filters.channel_exponent) as f32;
    let [nt, nr] = [0, 1].map(|k| {
        own[k].sums[0]
            .iter()
            .map(|&v| v.powf(r))
            .collect::<Vec<f32>>()
    });
    let local = filters.local.as_mut().expect("side-by-side filters");
    let (et, er) = local.pair(&nt, &nr);
    let (inv, bc) = (1.0 / space as f32, filters.channel_exponent as f32);
    // The means can leave -1e-9 where the energy is 0: clamped before the root.
    let amp = |v: f32| v.max(0.0).powf(inv);
    for ((acc, t), r) in sums.sums[0].iter_mut().zip(&et).zip(&er) {
        *acc = (amp(*t) - amp(*r)).abs().powf(bc);
    }
}

#[cfg(test)]
mod tests {
    use super::super::csf::sensitivity;
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
    /// given as contrast per pixel on 100 cd/m^2, compared as `comparison` says.
    fn static_q(test: &[f32], reference: &[f32], comparison: Comparison, e: Pooling) -> f64 {
        let v = viewing(2);
        let mut filters = Filters::new(v, e.channels, NONE)
            .unwrap()
            .comparing(comparison, e.space);
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
            .comparing_with_knee(Comparison::SideBySide, e.space, a0);
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
            let unit = static_q(&gabor(0.01), &blank, Comparison::Difference, e);
            // Scale the Gabor so that its Q is 0.99 of the bound for a0 = 0.3.
            let c = 0.01 * (0.99 * 0.3 * area.powf(1.0 / space) / unit) as f32;
            let d = static_q(&gabor(c), &blank, Comparison::Difference, e);
            let s = knee_q(&gabor(c), &blank, 0.3, e);
            assert!(
                d > 0.0 && (s / d - 1.0).abs() < 1e-3,
                "beta {space}: {s} vs {d}"
            );
            // Far above the knee the transducer compresses: less than the difference.
            let d10 = static_q(&gabor(30.0 * c), &blank, Comparison::Difference, e);
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
        let q = |c: f32, comparison: Comparison| {
            let mut filters = Filters::new(v, e.channels, NONE)
                .unwrap()
                .comparing(comparison, e.space);
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
        let d84 = super::super::decision::two_ifc_d_prime_for(0.84).unwrap();
        let q84 = d84 / super::super::decision::DEFAULT_K;
        let c = 0.001 * (q84 / q(0.001, Comparison::Difference)) as f32;
        let (d, s) = (q(c, Comparison::Difference), q(c, Comparison::SideBySide));
        assert!((d / q84 - 1.0).abs() < 1e-3, "{d} vs {q84}");
        assert!(
            (s / d - 1.0).abs() < 0.03,
            "side by side {s}, difference {d}"
        );
        let d3 = q(3.0 * c, Comparison::Difference);
        let s3 = q(3.0 * c, Comparison::SideBySide);
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
            let q = static_q(&t, &r, Comparison::SideBySide, e);
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
        let same = static_q(&t1, &r, Comparison::SideBySide, e);
        let double = static_q(&t2, &r, Comparison::SideBySide, e);
        let same_diff = static_q(&t1, &r, Comparison::Difference, e);
        assert!(same < 0.5 * double, "{same} vs {double}");
        // The difference carries sqrt 2 times the noise; the energies only their sampling
        // fluctuation, large on this 2-deg field whose 1-2 cpd bands hold a few cycles (1.76
        // times less than the difference when written).
        assert!(same_diff > 1.2 * same, "{same_diff} vs {same}");
        let itself = static_q(&r, &r, Comparison::SideBySide, e);
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
