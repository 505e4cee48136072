//! Spatial frequency analysis of a frame: a 2D FFT (rustfft), the radial frequency of every
//! coefficient in cycles per degree, octave bands, and the CSF-weighted band filters.
//!
//! Bands: centres rho_b = (ppd / 2) 2^-b (the top band at the Nyquist frequency), down to the
//! last at or above [`LOWEST_CENTRE_CPD`], whatever the picture's size (so a border around a
//! picture adds no band and splits none); windows cos^2(pi/2 log2(rho / rho_b)) between neighbouring centres,
//! so the bands sum to exactly 1 at every frequency (the top band keeps everything above its
//! centre, the bottom band everything below, the mean included). Filtering in the frequency
//! domain makes the frame periodic: content near one edge leaks into the opposite edge's
//! coarsest bands (not corrected; test and reference leak alike).

use rustfft::num_complex::Complex32;
use rustfft::{Fft, FftPlanner};
use std::sync::Arc;

/// Forward and inverse 2D transforms of one frame size. The spectrum is stored transposed
/// (index kx * height + ky), which saves a transpose each way.
pub struct Fft2 {
    pub width: usize,
    pub height: usize,
    row_fwd: Arc<dyn Fft<f32>>,
    row_inv: Arc<dyn Fft<f32>>,
    col_fwd: Arc<dyn Fft<f32>>,
    col_inv: Arc<dyn Fft<f32>>,
    scratch: Vec<Complex32>,
    tmp: Vec<Complex32>,
}

impl Fft2 {
    pub fn new(width: usize, height: usize) -> Self {
        let mut p = FftPlanner::new();
        let (row_fwd, row_inv) = (p.plan_fft_forward(width), p.plan_fft_inverse(width));
        let (col_fwd, col_inv) = (p.plan_fft_forward(height), p.plan_fft_inverse(height));
        let scratch_len = [&row_fwd, &row_inv, &col_fwd, &col_inv]
            .iter()
            .map(|f| f.get_inplace_scratch_len())
            .max()
            .unwrap_or(0);
        Self {
            width,
            height,
            row_fwd,
            row_inv,
            col_fwd,
            col_inv,
            scratch: vec![Complex32::default(); scratch_len],
            tmp: vec![Complex32::default(); width * height],
        }
    }

    /// Row-major image -> transposed spectrum, in place (unnormalised).
    pub fn forward(&mut self, data: &mut [Complex32]) {
        self.row_fwd.process_with_scratch(data, &mut self.scratch);
        transpose(data, &mut self.tmp, self.width, self.height);
        self.col_fwd
            .process_with_scratch(&mut self.tmp, &mut self.scratch);
        data.copy_from_slice(&self.tmp);
    }

    /// Transposed spectrum -> row-major image, in place (unnormalised: the filters carry the
    /// 1 / (width height)).
    pub fn inverse(&mut self, data: &mut [Complex32]) {
        self.col_inv.process_with_scratch(data, &mut self.scratch);
        transpose(data, &mut self.tmp, self.height, self.width);
        self.row_inv
            .process_with_scratch(&mut self.tmp, &mut self.scratch);
        data.copy_from_slice(&self.tmp);
    }
}

/// `src` is `rows` rows of `cols`; `dst` gets `cols` rows of `rows`.
fn transpose(src: &[Complex32], dst: &mut [Complex32], cols: usize, rows: usize) {
    const B: usize = 32;
    for r0 in (0..rows).step_by(B) {
        for c0 in (0..cols).step_by(B) {
            for r in r0..(r0 + B).min(rows) {
                for c in c0..(c0 + B).min(cols) {
                    dst[c * rows + r] = src[r * cols + c];
                }
            }
        }
    }
}

/// Signed frequency index k of an n-point transform, in cycles per sample.
fn signed(k: usize, n: usize) -> f64 {
    let k = if k > n / 2 {
        k as f64 - n as f64
    } else {
        k as f64
    };
    k / n as f64
}

/// Radial frequency (cpd) of every coefficient, in the transposed layout of [`Fft2`].
pub fn radial_frequencies(width: usize, height: usize, ppd: f64) -> Vec<f64> {
    frequencies(width, height, ppd)
        .map(|(fx, fy)| fx.hypot(fy))
        .collect()
}

/// Horizontal and vertical frequency (cpd) of every coefficient, in the transposed layout of
/// [`Fft2`].
pub fn frequencies(width: usize, height: usize, ppd: f64) -> impl Iterator<Item = (f64, f64)> {
    (0..width).flat_map(move |kx| {
        (0..height).map(move |ky| (ppd * signed(kx, width), ppd * signed(ky, height)))
    })
}

/// The lowest band centre is the last octave at or above this frequency, cpd: ModelFest's 256
/// pixels at 120 ppd get the six bands that three cycles per picture gave them before the
/// centres were fixed, 60 down to 1.9 cpd.
pub const LOWEST_CENTRE_CPD: f64 = 1.0;

/// Band centres in cpd, finest first.
pub fn band_centres(ppd: f64) -> Vec<f64> {
    let count = (((0.5 * ppd / LOWEST_CENTRE_CPD).log2().floor() as i64) + 1).max(1) as usize;
    (0..count)
        .map(|b| 0.5 * ppd / 2f64.powi(b as i32))
        .collect()
}

/// Weight of band `b` of `centres` at frequency `rho` (the windows sum to 1).
pub fn window(centres: &[f64], b: usize, rho: f64) -> f64 {
    let last = centres.len() - 1;
    if rho <= 0.0 {
        return if b == last { 1.0 } else { 0.0 };
    }
    let u = (rho / centres[b]).log2();
    if (b == 0 && u >= 0.0) || (b == last && u <= 0.0) {
        return 1.0;
    }
    if u.abs() >= 1.0 {
        return 0.0;
    }
    (0.5 * std::f64::consts::PI * u).cos().powi(2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn windows_partition_unity() {
        let c = band_centres(39.5);
        assert_eq!(c.len(), 5);
        assert_eq!(band_centres(120.0).len(), 6);
        assert!((band_centres(120.0)[5] - 1.875).abs() < 1e-12);
        for i in 0..2000 {
            let rho = i as f64 * 0.02;
            let s: f64 = (0..c.len()).map(|b| window(&c, b, rho)).sum();
            assert!((s - 1.0).abs() < 1e-12, "{rho}: {s}");
        }
    }

    #[test]
    fn transforms_invert_and_put_a_cosine_at_its_frequency() {
        let (w, h) = (12, 8);
        let mut fft = Fft2::new(w, h);
        let img: Vec<Complex32> = (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f32, (i / w) as f32);
                let v =
                    (2.0 * std::f32::consts::PI * (3.0 * x / w as f32 + 1.0 * y / h as f32)).cos();
                Complex32::new(v, 0.0)
            })
            .collect();
        let mut d = img.clone();
        fft.forward(&mut d);
        // All energy at (kx, ky) = (3, 1) and (w - 3, h - 1), each w h / 2.
        let at = |kx: usize, ky: usize| d[kx * h + ky].norm();
        assert!((at(3, 1) - (w * h) as f32 / 2.0).abs() < 1e-3);
        assert!((at(w - 3, h - 1) - (w * h) as f32 / 2.0).abs() < 1e-3);
        let rho = radial_frequencies(w, h, 10.0);
        assert!((rho[3 * h + 1] - 10.0 * (0.25f64).hypot(0.125)).abs() < 1e-12);
        fft.inverse(&mut d);
        for (a, b) in d.iter().zip(&img) {
            assert!((a.re / (w * h) as f32 - b.re).abs() < 1e-5);
        }
    }
}
