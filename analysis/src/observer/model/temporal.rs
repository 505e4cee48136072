//! Temporal channels: the sustained and transient mechanisms of the CSF ([`super::csf`]) as
//! filters over a video's frames.
//!
//! A trial plays each video in a loop, so a video of F frames at `fps` is periodic and its
//! temporal frequencies are omega_j = fps min(j, F - j) / F. A channel with the real, even
//! frequency response R(omega) is the circular convolution with
//!
//! ```text
//! h[n] = (1/F) sum_j R(omega_j) cos(2 pi j n / F)
//! ```
//!
//! (zero phase, so the sustained and transient outputs of one grating stay in phase and add as
//! the CSF adds them). Long videos keep the taps within +-0.25 s ([`MAX_HALF_SECONDS`]): the
//! responses are smooth, so their kernels are short (tested at 30 fps: > 99.5% of each kernel's energy).

use std::f64::consts::PI;

/// Longest reach of a kernel on either side, seconds.
pub const MAX_HALF_SECONDS: f64 = 0.25;

/// A temporal filter as (frame offset, weight) taps, offsets taken modulo the frame count.
#[derive(Clone, Debug, PartialEq)]
pub struct Kernel {
    pub taps: Vec<(i64, f32)>,
}

/// The periodic kernel of response `r` for `frames` frames at `fps`, truncated to
/// [`MAX_HALF_SECONDS`] when the video is longer than that window.
pub fn kernel(r: impl Fn(f64) -> f64, frames: usize, fps: f64) -> Kernel {
    let f = frames as i64;
    let full: Vec<f64> = (0..f)
        .map(|n| {
            (0..f)
                .map(|j| {
                    let omega = fps * j.min(f - j) as f64 / f as f64;
                    r(omega) * (2.0 * PI * (j * n) as f64 / f as f64).cos()
                })
                .sum::<f64>()
                / f as f64
        })
        .collect();
    let half = (MAX_HALF_SECONDS * fps).ceil() as i64;
    let taps = if 2 * half + 1 >= f {
        (0..f).map(|n| (n, full[n as usize] as f32)).collect()
    } else {
        (-half..=half)
            .map(|n| (n, full[n.rem_euclid(f) as usize] as f32))
            .collect()
    };
    Kernel { taps }
}

/// Energy fraction of the full periodic kernel that `kernel` keeps (1 when not truncated).
pub fn kept_energy(r: impl Fn(f64) -> f64 + Copy, frames: usize, fps: f64) -> f64 {
    let all: f64 = kernel_full_energy(r, frames, fps);
    let kept: f64 = kernel(r, frames, fps)
        .taps
        .iter()
        .map(|&(_, w)| (w as f64).powi(2))
        .sum();
    kept / all
}

fn kernel_full_energy(r: impl Fn(f64) -> f64, frames: usize, fps: f64) -> f64 {
    // Parseval: sum h^2 = (1/F) sum_j R(omega_j)^2.
    let f = frames as i64;
    (0..f)
        .map(|j| r(fps * j.min(f - j) as f64 / f as f64).powi(2))
        .sum::<f64>()
        / f as f64
}

#[cfg(test)]
mod tests {
    use super::super::csf::{sustained_response, transient_response};
    use super::*;

    /// Filter a sequence circularly.
    fn apply(k: &Kernel, x: &[f64]) -> Vec<f64> {
        let f = x.len() as i64;
        (0..f)
            .map(|t| {
                k.taps
                    .iter()
                    .map(|&(o, w)| w as f64 * x[(t + o).rem_euclid(f) as usize])
                    .sum()
            })
            .collect()
    }

    #[test]
    fn a_sinusoid_at_a_video_frequency_is_scaled_by_the_response() {
        // 6 frames at 30 fps (the demo): frequencies 0, 5, 10, 15 Hz, exact circular filter.
        for (r, name) in [
            (sustained_response as fn(f64) -> f64, "sustained"),
            (transient_response, "transient"),
        ] {
            let k = kernel(r, 6, 30.0);
            for j in 0..=3 {
                let x: Vec<f64> = (0..6)
                    .map(|t| (2.0 * PI * (j * t) as f64 / 6.0).cos())
                    .collect();
                let y = apply(&k, &x);
                let g = r(5.0 * j as f64);
                for t in 0..6 {
                    assert!((y[t] - g * x[t]).abs() < 1e-5, "{name} {j} {t}");
                }
            }
        }
    }

    #[test]
    fn long_videos_keep_nearly_all_of_each_kernel() {
        for r in [sustained_response as fn(f64) -> f64, transient_response] {
            let e = kept_energy(r, 210, 30.0);
            assert!(e > 0.995, "{e}");
        }
        assert_eq!(kernel(sustained_response, 210, 30.0).taps.len(), 2 * 8 + 1);
    }
}
