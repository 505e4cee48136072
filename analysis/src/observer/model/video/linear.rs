//! The model's linear stages for one viewing: local adaptation and contrast, the temporal
//! channels, and the CSF-weighted spatial bands (steps 2-4 of [`super::frame_sums`]). Each
//! signal's two channels travel packed as one complex image (e_S + i e_T, c_S + i c_T): every
//! filter is real and even in frequency, so one transform serves both channels.

use super::super::bands::{Fft2, band_centres, frequencies, radial_frequencies, window};
use super::super::csf::{SUSTAINED, TRANSIENT, spatial, sustained_response, transient_response};
use super::super::shape::Shape;
use super::super::temporal::{Kernel, kernel};
use super::viewing::{ADAPTATION_FLOOR, ADAPTATION_SIGMA_DEG, CSF_AREA_DEG2, Viewing};
use anyhow::{Result, bail};
use rustfft::num_complex::Complex32;
use std::collections::BTreeMap;

/// Everything linear that depends only on the viewing: transforms, weights, kernels.
pub struct Linear {
    viewing: Viewing,
    fft: Fft2,
    adaptation: Vec<f32>,
    /// Per band, per channel (sustained, transient): window^(1/beta_c) x CSF / (width height).
    bands: Vec<[Vec<f32>; 2]>,
    /// beta_c, the Minkowski exponent over bands and channels ([`super::super::pooling`]).
    channel_exponent: f64,
    kernels: [Kernel; 2],
}

impl Linear {
    /// The filters of a viewing, for pooling over bands and channels with exponent
    /// `channel_exponent` (beta_c): each band's window is raised to 1 / beta_c, so the windows'
    /// beta_c-th powers sum to 1 and a grating between two band centres pools to its
    /// CSF-weighted contrast as one at a centre does (no ripple over frequency). `shape`
    /// corrects the CSF's weights ([`super::super::shape`]).
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
        })
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
    pub fn contrast(&mut self, test: &[f32], reference: &[f32]) -> Vec<Complex32> {
        let la = self.adaptation(reference);
        test.iter()
            .zip(reference)
            .zip(&la)
            .map(|((&t, &r), &a)| Complex32::new((t - r) / a, r / a - 1.0))
            .collect()
    }

    /// Every frame offset the temporal kernels reach, sorted.
    pub fn offsets(&self) -> Vec<i64> {
        let mut o: Vec<i64> = self
            .kernels
            .iter()
            .flat_map(|k| k.taps.iter().map(|t| t.0))
            .collect();
        o.sort_unstable();
        o.dedup();
        o
    }

    /// Frame t's temporal channels, packed (the difference as e_S + i e_T, the reference as
    /// c_S + i c_T), and transformed: `contrasts` holds each frame's packed contrasts
    /// ([`Linear::contrast`]) for every frame the kernels reach.
    pub fn channels(
        &mut self,
        t: i64,
        contrasts: &BTreeMap<usize, Vec<Complex32>>,
        e_pack: &mut [Complex32],
        c_pack: &mut [Complex32],
    ) {
        let f = self.viewing.frames as i64;
        e_pack.iter_mut().for_each(|z| *z = Complex32::default());
        c_pack.iter_mut().for_each(|z| *z = Complex32::default());
        for (k, kernel) in self.kernels.iter().enumerate() {
            for &(o, w) in &kernel.taps {
                let src = &contrasts[&((t + o).rem_euclid(f) as usize)];
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
        self.fft.forward(e_pack);
        self.fft.forward(c_pack);
    }

    /// Band `b` of a packed spectrum Z = A + i B of two real images a, b (transposed layout):
    /// out = IFFT(w_S A + i w_T B), so out.re is a's sustained band and out.im b's transient
    /// band. A(k) = (Z(k) + conj Z(-k)) / 2 and B(k) = (Z(k) - conj Z(-k)) / 2i.
    /// With `orient`, restricted to one orientation channel: its window per coefficient
    /// ([`super::super::orientation`]).
    pub fn band(
        &mut self,
        z: &[Complex32],
        b: usize,
        orient: Option<&[f32]>,
        out: &mut [Complex32],
    ) {
        let (w, h) = (self.viewing.width, self.viewing.height);
        let [ws, wt] = &self.bands[b];
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
                self.band(&z, b, None, &mut out);
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

    /// The number of spatial bands.
    pub fn bands(&self) -> usize {
        self.bands.len()
    }
}
