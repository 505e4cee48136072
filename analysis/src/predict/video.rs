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
//!    luminance and the video's area ([`super::bands`], [`super::csf`]): d_{b,k} and m_{b,k};
//! 5. masking, d_{b,k} / T_e(m_{b,k}) ([`super::masking`]);
//! 6. pooling over bands and channels, then space, per frame ([`super::pooling`]).
//!
//! Each signal's two channels travel packed as one complex image (e_S + i e_T, c_S + i c_T):
//! every filter is real and even in frequency, so one transform serves both channels (half the
//! transforms), and e is never packed with c, so identical videos give e = 0 exactly, hence
//! Q = 0 exactly.

use super::bands::{Fft2, band_centres, radial_frequencies, window};
use super::csf::{SUSTAINED, TRANSIENT, spatial, sustained_response, transient_response};
use super::masking::threshold_elevation;
use super::pooling::FramePool;
use super::temporal::{Kernel, kernel};
use anyhow::{Result, bail};
use rustfft::num_complex::Complex32;
use std::collections::BTreeMap;

/// Standard deviation of the local adaptation's Gaussian, degrees.
pub const ADAPTATION_SIGMA_DEG: f64 = 0.5;
/// Lowest adaptation luminance, cd/m^2 (below it Weber contrast is not a model of vision).
pub const ADAPTATION_FLOOR: f32 = 1.0;

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

impl Viewing {
    /// The video's area in deg^2 (the CSF's stimulus area).
    pub fn area_deg2(&self) -> f64 {
        (self.width * self.height) as f64 / self.pixels_per_degree.powi(2)
    }
}

/// Everything that depends only on the viewing: transforms, weights, kernels.
pub struct Filters {
    viewing: Viewing,
    fft: Fft2,
    adaptation: Vec<f32>,
    /// Per band, per channel (sustained, transient): window x CSF / (width height).
    bands: Vec<[Vec<f32>; 2]>,
    kernels: [Kernel; 2],
}

impl Filters {
    pub fn new(v: Viewing) -> Result<Self> {
        if v.width == 0 || v.height == 0 || v.frames == 0 {
            bail!(
                "a video of {}x{} pixels and {} frames has nothing to compare",
                v.width,
                v.height,
                v.frames
            );
        }
        if !(v.fps > 0.0 && v.pixels_per_degree > 0.0 && v.mean_luminance > 0.0) {
            bail!("frame rate, pixels per degree and mean luminance must be positive: {v:?}");
        }
        let n = (v.width * v.height) as f64;
        let rho = radial_frequencies(v.width, v.height, v.pixels_per_degree);
        let centres = band_centres(v.width, v.height, v.pixels_per_degree);
        let two_pi2_s2 = 2.0 * std::f64::consts::PI.powi(2) * ADAPTATION_SIGMA_DEG.powi(2);
        let adaptation = rho
            .iter()
            .map(|r| ((-two_pi2_s2 * r * r).exp() / n) as f32)
            .collect();
        let (l, a) = (v.mean_luminance, v.area_deg2());
        let csf: [Vec<f64>; 2] =
            [SUSTAINED, TRANSIENT].map(|m| rho.iter().map(|&r| spatial(&m, r, l, a)).collect());
        let bands = (0..centres.len())
            .map(|b| {
                [0, 1].map(|k| {
                    rho.iter()
                        .zip(&csf[k])
                        .map(|(&r, &s)| (window(&centres, b, r) * s / n) as f32)
                        .collect()
                })
            })
            .collect();
        Ok(Self {
            viewing: v,
            fft: Fft2::new(v.width, v.height),
            adaptation,
            bands,
            kernels: [
                kernel(sustained_response, v.frames, v.fps),
                kernel(transient_response, v.frames, v.fps),
            ],
        })
    }

    /// Packed contrasts e + i c of one frame pair.
    fn contrast(&mut self, test: &[f32], reference: &[f32]) -> Vec<Complex32> {
        let mut la: Vec<Complex32> = reference.iter().map(|&r| Complex32::new(r, 0.0)).collect();
        self.fft.forward(&mut la);
        for (z, g) in la.iter_mut().zip(&self.adaptation) {
            *z *= *g;
        }
        self.fft.inverse(&mut la);
        test.iter()
            .zip(reference)
            .zip(&la)
            .map(|((&t, &r), a)| {
                let a = a.re.max(ADAPTATION_FLOOR);
                Complex32::new((t - r) / a, r / a - 1.0)
            })
            .collect()
    }
}

impl Filters {
    /// Band `b` of a packed spectrum Z = A + i B of two real images a, b (transposed layout):
    /// out = IFFT(w_S A + i w_T B), so out.re is a's sustained band and out.im b's transient
    /// band. A(k) = (Z(k) + conj Z(-k)) / 2 and B(k) = (Z(k) - conj Z(-k)) / 2i.
    fn band(&mut self, z: &[Complex32], b: usize, out: &mut [Complex32]) {
        let (w, h) = (self.viewing.width, self.viewing.height);
        let [ws, wt] = &self.bands[b];
        for kx in 0..w {
            let mx = (w - kx) % w;
            for ky in 0..h {
                let i = kx * h + ky;
                let m = z[mx * h + (h - ky) % h].conj();
                let a = (z[i] + m) * 0.5;
                let bb = (z[i] - m) * Complex32::new(0.0, -0.5);
                out[i] = a * ws[i] + Complex32::new(0.0, 1.0) * bb * wt[i];
            }
        }
        self.fft.inverse(out);
    }
}

/// Per-frame visible difference Q_t of a video pair; `load(t)` gives frame t's luminance
/// (test, reference). Frames are loaded as the temporal window reaches them and dropped after.
pub fn frame_differences(
    filters: &mut Filters,
    mut load: impl FnMut(usize) -> Result<(Vec<f32>, Vec<f32>)>,
) -> Result<Vec<f64>> {
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
    let mut out = Vec::with_capacity(v.frames);
    let mut e_pack = vec![Complex32::default(); pixels];
    let mut c_pack = vec![Complex32::default(); pixels];
    let mut e_band = vec![Complex32::default(); pixels];
    let mut c_band = vec![Complex32::default(); pixels];
    let mut d = vec![0f32; pixels];
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
        d.iter_mut().for_each(|x| *x = 0.0);
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
            for ((acc, e), c) in d.iter_mut().zip(&e_band).zip(&c_band) {
                *acc +=
                    e.re.abs() / threshold_elevation(c.re) + e.im.abs() / threshold_elevation(c.im);
            }
        }
        let mut pool = FramePool::default();
        pool.add_map(&d);
        out.push(pool.q());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::super::csf::sensitivity;
    use super::*;
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

    /// Q of a drifting grating of contrast `c`, `cycles` per video width, `j` cycles per loop
    /// of `frames` frames, on a uniform reference of 100 cd/m^2.
    fn grating_q(v: Viewing, c: f64, cycles: f64, j: f64) -> f64 {
        let mut filters = Filters::new(v).unwrap();
        let q = frame_differences(&mut filters, |t| {
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
        super::super::pooling::video_q(&q)
    }

    #[test]
    fn a_drifting_grating_gives_the_csf_weighted_contrast() {
        // 8 frames at 30 fps: temporal frequencies are multiples of 3.75 Hz.
        let v = viewing(8);
        for (cycles, j) in [(2.0, 0.0), (4.0, 1.0), (8.0, 2.0), (16.0, 1.0), (4.0, 4.0)] {
            let rho = cycles * v.pixels_per_degree / v.width as f64;
            let omega = j * v.fps / v.frames as f64;
            let s = sensitivity(rho, omega, 100.0, v.area_deg2());
            let c = 0.5 / s;
            let q = grating_q(v, c, cycles, j);
            assert!((q - 0.5).abs() < 0.5 * 2e-3, "{rho} cpd {omega} Hz: {q}");
        }
    }

    #[test]
    fn identical_videos_have_no_visible_difference() {
        let v = viewing(3);
        let mut filters = Filters::new(v).unwrap();
        let q = frame_differences(&mut filters, |t| {
            let f: Vec<f32> = (0..64 * 64)
                .map(|i| ((i * 7 + t * 13) % 255) as f32)
                .collect();
            Ok((f.clone(), f))
        })
        .unwrap();
        assert_eq!(q, vec![0.0; 3]);
    }
}
