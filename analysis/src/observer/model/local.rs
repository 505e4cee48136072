//! Local means: a sum-preserving Gaussian average of an image, the neighbourhood over which the
//! side-by-side stage ([`super::decision_stage`]) measures each video's contrast energy. The
//! Gaussian (sd 0.5 deg, 23 px at the thesis's 46 px/deg) passes nothing above a few tenths
//! of a cycle per degree, so it is computed on a grid `factor` times coarser: block
//! means, the Gaussian by FFT, then bilinear interpolation back (periodic). Both steps keep the
//! image's sum exactly (each coarse sample's interpolation weights over the fine grid sum to
//! factor^2), which the stage's reduction to detection relies on; the coarse grid costs
//! 1 / factor^2 of a full-size transform, so the stage can afford one per band.

use super::bands::{Fft2, radial_frequencies};
use rustfft::num_complex::Complex32;

/// A Gaussian local mean of one image size.
pub struct LocalMean {
    width: usize,
    height: usize,
    factor: usize,
    fft: Fft2,
    /// The Gaussian's transfer on the coarse grid, divided by its pixel count (the inverse
    /// transform is unnormalised).
    gain: Vec<f32>,
}

impl LocalMean {
    /// The mean under a Gaussian of sd `sigma_deg` on `width` x `height` pixels at
    /// `pixels_per_degree`. The coarse factor is the largest power of two up to a quarter of
    /// the sd in pixels that divides both sides (1: the full grid).
    pub fn new(width: usize, height: usize, pixels_per_degree: f64, sigma_deg: f64) -> Self {
        let sd_px = sigma_deg * pixels_per_degree;
        let mut factor = 1;
        while 2.0 * factor as f64 <= sd_px / 4.0
            && width.is_multiple_of(2 * factor)
            && height.is_multiple_of(2 * factor)
        {
            factor *= 2;
        }
        let (cw, ch) = (width / factor, height / factor);
        let n = (cw * ch) as f64;
        let k = 2.0 * std::f64::consts::PI.powi(2) * sigma_deg * sigma_deg;
        let gain = radial_frequencies(cw, ch, pixels_per_degree / factor as f64)
            .iter()
            .map(|r| ((-k * r * r).exp() / n) as f32)
            .collect();
        Self {
            width,
            height,
            factor,
            fft: Fft2::new(cw, ch),
            gain,
        }
    }

    /// The coarse grid's factor.
    pub fn factor(&self) -> usize {
        self.factor
    }

    /// The local means of two images (one transform pair for both).
    pub fn pair(&mut self, a: &[f32], b: &[f32]) -> (Vec<f32>, Vec<f32>) {
        let (f, w) = (self.factor, self.width);
        let (cw, ch) = (w / f, self.height / f);
        let mut z = vec![Complex32::default(); cw * ch];
        let inv = 1.0 / (f * f) as f32;
        for (py, (ra, rb)) in a.chunks_exact(w).zip(b.chunks_exact(w)).enumerate() {
            let row = &mut z[(py / f) * cw..][..cw];
            for ((zc, ba), bb) in row
                .iter_mut()
                .zip(ra.chunks_exact(f))
                .zip(rb.chunks_exact(f))
            {
                let (x, y): (f32, f32) = (ba.iter().sum(), bb.iter().sum());
                *zc += Complex32::new(x * inv, y * inv);
            }
        }
        self.fft.forward(&mut z);
        for (z, g) in z.iter_mut().zip(&self.gain) {
            *z *= *g;
        }
        self.fft.inverse(&mut z);
        if f == 1 {
            return z.iter().map(|v| (v.re, v.im)).unzip();
        }
        // Bilinear, periodic: coarse sample i sits at fine position i f + (f - 1) / 2.
        let axis = |n: usize, c: usize| -> Vec<(usize, usize, f32)> {
            (0..n)
                .map(|x| {
                    let u = (x as f32 - 0.5 * (f as f32 - 1.0)) / f as f32;
                    let i0 = u.floor();
                    let t = u - i0;
                    let i0 = (i0 as i64).rem_euclid(c as i64) as usize;
                    (i0, (i0 + 1) % c, t)
                })
                .collect()
        };
        let (ax, ay) = (axis(w, cw), axis(self.height, ch));
        let mut out_a = Vec::with_capacity(a.len());
        let mut out_b = Vec::with_capacity(a.len());
        for &(y0, y1, ty) in &ay {
            for &(x0, x1, tx) in &ax {
                let v = (z[y0 * cw + x0] * (1.0 - tx) + z[y0 * cw + x1] * tx) * (1.0 - ty)
                    + (z[y1 * cw + x0] * (1.0 - tx) + z[y1 * cw + x1] * tx) * ty;
                out_a.push(v.re);
                out_b.push(v.im);
            }
        }
        (out_a, out_b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_the_sum_and_a_constant_and_smooths() {
        // 64 x 64 at 32 px/deg, sd 0.5 deg = 16 px: factor 4.
        let mut m = LocalMean::new(64, 64, 32.0, 0.5);
        assert_eq!(m.factor(), 4);
        let spike: Vec<f32> = (0..64 * 64)
            .map(|i| if i == 64 * 20 + 7 { 1.0 } else { 0.0 })
            .collect();
        let flat = vec![3.0f32; 64 * 64];
        let (s, c) = m.pair(&spike, &flat);
        let sum: f32 = s.iter().sum();
        assert!((sum - 1.0).abs() < 1e-4, "{sum}");
        assert!(c.iter().all(|v| (v - 3.0).abs() < 1e-4));
        // The spike spread under a Gaussian of 2 pi 16^2 = 1608 px: its peak near 1 / 1608.
        let peak = s.iter().cloned().fold(0.0, f32::max);
        assert!(peak > 0.5 / 1608.0 && peak < 1.5 / 1608.0, "{peak}");
        // An odd size falls back to the full grid, exactly as the full-size blur.
        assert_eq!(LocalMean::new(63, 64, 32.0, 0.5).factor(), 1);
    }
}
