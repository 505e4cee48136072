//! Pooling the visible difference over channels, space and time into one number Q per video
//! (and one per frame, for the spread over frames).
//!
//! With d_{b,k}(x, t) the masked, CSF-weighted difference in spatial band b and temporal
//! channel k (in threshold units):
//!
//! 1. channels, linear (Minkowski exponent 1): D(x, t) = sum_{b,k} |d_{b,k}(x, t)|, as stelaCSF
//!    adds its sustained and transient mechanisms linearly and FovVideoVDP pools spatial
//!    channels with exponent 1 (Mantiuk et al. 2021); with the bands a partition of unity, a
//!    single grating's D is exactly its CSF-weighted contrast;
//! 2. space and time, energy (exponent 2), as a mean: Q_t^2 = 2 mean_x D(x, t)^2 and
//!    Q^2 = mean_t Q_t^2. Energy summation is what Rovamo et al. (1993) found within the
//!    critical area, which stelaCSF's area term already holds (the CSF is evaluated at the
//!    video's area), so the mean does not sum area twice; over time the mean makes a looped
//!    video's noise as visible as one loop's. The factor 2 makes a drifting grating of
//!    contrast c give Q = S c (its mean of cos^2 is 1/2): Q = 1 is the CSF's threshold, and
//!    noise of the same energy as a threshold grating has Q = 1.

/// Accumulates one frame's D(x)^2.
#[derive(Clone, Debug, Default)]
pub struct FramePool {
    sum_sq: f64,
    pixels: usize,
}

impl FramePool {
    /// Add a frame's channel-summed map D(x).
    pub fn add_map(&mut self, d: &[f32]) {
        self.sum_sq += d.iter().map(|&v| (v as f64) * (v as f64)).sum::<f64>();
        self.pixels += d.len();
    }

    /// Q_t = sqrt(2 mean D^2).
    pub fn q(&self) -> f64 {
        if self.pixels == 0 {
            return 0.0;
        }
        (2.0 * self.sum_sq / self.pixels as f64).sqrt()
    }
}

/// Q of the whole video from its frames' Q_t: sqrt(mean Q_t^2).
pub fn video_q(frames: &[f64]) -> f64 {
    if frames.is_empty() {
        return 0.0;
    }
    (frames.iter().map(|q| q * q).sum::<f64>() / frames.len() as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sinusoid_of_amplitude_a_pools_to_a() {
        let n = 64;
        let d: Vec<f32> = (0..n)
            .map(|i| {
                3.0 * (2.0 * std::f32::consts::PI * 4.0 * i as f32 / n as f32)
                    .cos()
                    .abs()
            })
            .collect();
        let mut p = FramePool::default();
        p.add_map(&d);
        assert!((p.q() - 3.0).abs() < 1e-5);
        assert!((video_q(&[3.0, 4.0]) - 12.5f64.sqrt()).abs() < 1e-12);
        assert_eq!(video_q(&[]), 0.0);
    }
}
