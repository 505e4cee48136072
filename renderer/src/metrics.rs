//! Error of a rendered frame against its scene's reference ("speed against error" in the
//! design): RMSE and relative MSE on linear HDR radiance, PSNR and FLIP on the 8-bit display
//! frames. Per-frame values are combined over a video with [`ErrorAccumulator`].

use crate::manifest::ErrorMetrics;
use anyhow::{Result, ensure};

/// The `+ 0.01` in relative MSE keeps dark reference pixels from dominating (the usual
/// definition in the rendering literature, e.g. Rousselle et al. 2011).
pub const REL_MSE_EPSILON: f64 = 0.01;

/// Highest PSNR reported. Identical frames have infinite PSNR, which must not reach a
/// manifest; 100 dB is an 8-bit MSE of 6.5e-6, far below one quantisation step.
pub const PSNR_CAP_DB: f64 = 100.0;

/// Pixels per degree of visual angle for FLIP: the thesis's monitor (Dell U2311H, 1920 pixels
/// over 0.509 m) seen from 0.7 m, the viewing distance FLIP's authors assume by default.
pub fn flip_pixels_per_degree() -> f32 {
    nv_flip::pixels_per_degree(0.7, 1920.0, 0.509)
}

/// Root mean squared error over every channel of two linear frames.
pub fn rmse(test: &[[f32; 3]], reference: &[[f32; 3]]) -> Result<f64> {
    Ok(mse(test, reference)?.sqrt())
}

/// Mean squared error over every channel of two linear frames.
pub fn mse(test: &[[f32; 3]], reference: &[[f32; 3]]) -> Result<f64> {
    mean_over_channels(test, reference, |x, r| (x - r) * (x - r))
}

/// Relative MSE: mean over channels of `(x - r)^2 / (r^2 + 0.01)`.
pub fn rel_mse(test: &[[f32; 3]], reference: &[[f32; 3]]) -> Result<f64> {
    mean_over_channels(test, reference, |x, r| {
        (x - r) * (x - r) / (r * r + REL_MSE_EPSILON)
    })
}

fn mean_over_channels(
    test: &[[f32; 3]],
    reference: &[[f32; 3]],
    f: impl Fn(f64, f64) -> f64,
) -> Result<f64> {
    ensure!(
        test.len() == reference.len() && !test.is_empty(),
        "frames differ in size ({} and {} pixels)",
        test.len(),
        reference.len()
    );
    let sum: f64 = test
        .iter()
        .zip(reference)
        .flat_map(|(a, b)| (0..3).map(move |c| (sanitize(a[c]), sanitize(b[c]))))
        .map(|(x, r)| f(x, r))
        .sum();
    Ok(sum / (3 * test.len()) as f64)
}

/// Non-finite radiance never reaches a metric: it counts as zero.
fn sanitize(v: f32) -> f64 {
    if v.is_finite() { v as f64 } else { 0.0 }
}

/// Mean squared error of two 8-bit images (any channel layout, same length).
pub fn mse8(test: &[u8], reference: &[u8]) -> Result<f64> {
    ensure!(
        test.len() == reference.len() && !test.is_empty(),
        "display frames differ in size ({} and {} bytes)",
        test.len(),
        reference.len()
    );
    let sum: u64 = test
        .iter()
        .zip(reference)
        .map(|(&a, &b)| {
            let d = a as i64 - b as i64;
            (d * d) as u64
        })
        .sum();
    Ok(sum as f64 / test.len() as f64)
}

/// PSNR in dB for an 8-bit MSE, capped at [`PSNR_CAP_DB`].
pub fn psnr_from_mse8(mse: f64) -> f64 {
    let floor = 255.0 * 255.0 * 10f64.powf(-PSNR_CAP_DB / 10.0);
    10.0 * (255.0 * 255.0 / mse.max(floor)).log10()
}

/// Mean FLIP error of two 8-bit sRGB RGB images of `width` x `height`.
pub fn flip(test: &[u8], reference: &[u8], width: u32, height: u32) -> Result<f64> {
    let n = width as usize * height as usize * 3;
    ensure!(
        test.len() == n && reference.len() == n && n > 0,
        "display frames must be {width}x{height} RGB ({n} bytes), got {} and {}",
        test.len(),
        reference.len()
    );
    let r = nv_flip::FlipImageRgb8::with_data(width, height, reference);
    let t = nv_flip::FlipImageRgb8::with_data(width, height, test);
    let map = nv_flip::flip(r, t, flip_pixels_per_degree());
    let values = map.to_vec();
    let mean = values.iter().map(|&v| sanitize(v)).sum::<f64>() / values.len() as f64;
    Ok(mean)
}

/// The error of one frame. Display MSE is kept (not PSNR) so that a video's PSNR can be taken
/// from its mean MSE, which stays finite when some frames are identical to the reference.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrameError {
    pub mse: f64,
    pub rel_mse: f64,
    pub display_mse: f64,
    pub flip: f64,
}

impl FrameError {
    /// Compare one frame (linear and display versions) with the reference's.
    pub fn measure(
        test_linear: &[[f32; 3]],
        reference_linear: &[[f32; 3]],
        test_display: &[u8],
        reference_display: &[u8],
        width: u32,
        height: u32,
    ) -> Result<Self> {
        Ok(Self {
            mse: mse(test_linear, reference_linear)?,
            rel_mse: rel_mse(test_linear, reference_linear)?,
            display_mse: mse8(test_display, reference_display)?,
            flip: flip(test_display, reference_display, width, height)?,
        })
    }
}

/// Averages frame errors over a video. RMSE is the root of the mean MSE and PSNR comes from
/// the mean display MSE (errors of a video as one long signal); relative MSE and FLIP are
/// plain means over frames.
#[derive(Clone, Debug, Default)]
pub struct ErrorAccumulator {
    n: usize,
    mse: f64,
    rel_mse: f64,
    display_mse: f64,
    flip: f64,
}

impl ErrorAccumulator {
    pub fn add(&mut self, e: &FrameError) {
        self.n += 1;
        self.mse += e.mse;
        self.rel_mse += e.rel_mse;
        self.display_mse += e.display_mse;
        self.flip += e.flip;
    }

    /// The averaged metrics, or `None` when no frame was added.
    pub fn finish(&self) -> Option<ErrorMetrics> {
        if self.n == 0 {
            return None;
        }
        let n = self.n as f64;
        Some(ErrorMetrics {
            rmse: (self.mse / n).sqrt(),
            rel_mse: self.rel_mse / n,
            psnr: psnr_from_mse8(self.display_mse / n),
            flip: self.flip / n,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp(n: usize) -> Vec<[f32; 3]> {
        (0..n)
            .map(|i| {
                let v = i as f32 / n as f32;
                [v, 2.0 * v, 0.5 + v]
            })
            .collect()
    }

    fn ramp8(w: u32, h: u32) -> Vec<u8> {
        (0..w * h * 3).map(|i| (40 + (i * 7) % 160) as u8).collect()
    }

    #[test]
    fn a_frame_against_itself_has_no_error() {
        let a = ramp(64);
        assert_eq!(rmse(&a, &a).unwrap(), 0.0);
        assert_eq!(rel_mse(&a, &a).unwrap(), 0.0);
        let d = ramp8(16, 8);
        assert_eq!(mse8(&d, &d).unwrap(), 0.0);
        assert_eq!(psnr_from_mse8(0.0), PSNR_CAP_DB);
        assert_eq!(flip(&d, &d, 16, 8).unwrap(), 0.0);
    }

    #[test]
    fn a_constant_offset_gives_its_known_error() {
        let a = ramp(64);
        let b: Vec<[f32; 3]> = a.iter().map(|p| p.map(|c| c + 0.25)).collect();
        // Every channel differs by exactly 0.25 (up to f32 rounding of the additions).
        assert!((rmse(&b, &a).unwrap() - 0.25).abs() < 1e-6);
        let ones = vec![[1.0f32; 3]; 10];
        let more = vec![[1.5f32; 3]; 10];
        assert!((rel_mse(&more, &ones).unwrap() - 0.25 / 1.01).abs() < 1e-12);

        let d = ramp8(16, 8);
        let e: Vec<u8> = d.iter().map(|v| v + 10).collect();
        assert_eq!(mse8(&e, &d).unwrap(), 100.0);
        let expected = 10.0 * (65025.0f64 / 100.0).log10(); // 28.131 dB
        assert!((psnr_from_mse8(100.0) - expected).abs() < 1e-12);
    }

    #[test]
    fn flip_grows_with_the_difference_and_stays_in_unit_range() {
        let (w, h) = (32, 32);
        let base = vec![100u8; (w * h * 3) as usize];
        let mut last = 0.0;
        for off in [5u8, 40, 120] {
            let t: Vec<u8> = base.iter().map(|v| v + off).collect();
            let f = flip(&t, &base, w, h).unwrap();
            assert!(f > last && f <= 1.0, "offset {off}: flip {f} after {last}");
            last = f;
        }
    }

    #[test]
    fn video_average_uses_mean_mse() {
        let mut acc = ErrorAccumulator::default();
        assert!(acc.finish().is_none());
        let frame = |mse, d| FrameError {
            mse,
            rel_mse: mse,
            display_mse: d,
            flip: 0.5 * mse,
        };
        acc.add(&frame(0.0, 0.0));
        acc.add(&frame(0.5, 200.0));
        let m = acc.finish().unwrap();
        assert_eq!(m.rmse, 0.5);
        assert_eq!(m.rel_mse, 0.25);
        assert!((m.psnr - psnr_from_mse8(100.0)).abs() < 1e-12);
        assert_eq!(m.flip, 0.125);
    }

    #[test]
    fn mismatched_sizes_are_errors_not_panics() {
        assert!(rmse(&ramp(3), &ramp(4)).is_err());
        assert!(mse8(&[1, 2], &[1]).is_err());
        assert!(flip(&[0; 12], &[0; 12], 4, 4).is_err());
    }
}
