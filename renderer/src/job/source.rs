//! Where a job's frames come from. The runner asks a [`FrameSource`] per scene for frames; the
//! real one wraps the renderer's scene ([`SceneSource`]); [`SyntheticSource`] is an analytic
//! moving pattern, sampled through the real [`FrameSampler`], that lets the job machinery
//! (expansion, resume, shards, metrics, reports) be tested in milliseconds.

use crate::film::{RenderedFrame, srgb8};
use crate::sampling::{FrameSampler, SamplingConfig};
use anyhow::Result;

/// The settings of a scene that shape its stimuli.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameSetup {
    pub width: u32,
    pub height: u32,
    pub frames: u32,
    pub fps: f64,
}

/// A scene as the runner sees it.
pub trait FrameSource: Send + Sync {
    fn setup(&self) -> FrameSetup;
    /// Render `frame` with `sampling` and the stimulus's `seed`.
    fn render(&self, sampling: &SamplingConfig, seed: u64, frame: u32) -> Result<RenderedFrame>;
    /// The same scene at another size (for calibration renders).
    fn resized(&self, width: u32, height: u32) -> Result<Box<dyn FrameSource>>;
}

/// Bright stripes drifting right plus a small very bright spot (an HDR "highlight"), filtered
/// over the pixel and the shutter by the sampler's warped samples.
#[derive(Clone, Debug)]
pub struct SyntheticSource {
    pub setup: FrameSetup,
    /// Pixels the pattern moves per frame.
    pub speed: f32,
    /// Animation frame rendered as frame 0.
    pub first_frame: u32,
    /// The scene's own sampling block, under each stimulus's settings
    /// ([`SamplingConfig::over`]), as a real scene's `settings.sampling`.
    pub sampling: SamplingConfig,
}

impl SyntheticSource {
    pub fn new(width: u32, height: u32, frames: u32) -> Self {
        Self {
            setup: FrameSetup {
                width,
                height,
                frames,
                fps: 30.0,
            },
            speed: 3.0,
            first_frame: 0,
            sampling: SamplingConfig::default(),
        }
    }

    fn radiance(&self, x: f32, y: f32) -> [f32; 3] {
        let s = 0.5 + 0.5 * (0.4 * x).sin();
        let (cx, cy) = (
            self.setup.width as f32 * 0.5,
            self.setup.height as f32 * 0.5,
        );
        let spot = if (x - cx).powi(2) + (y - cy).powi(2) < 4.0 {
            20.0
        } else {
            0.0
        };
        [s + spot, 0.5 * s + spot, 0.2 + spot]
    }
}

impl FrameSource for SyntheticSource {
    fn setup(&self) -> FrameSetup {
        self.setup
    }

    fn render(&self, sampling: &SamplingConfig, seed: u64, frame: u32) -> Result<RenderedFrame> {
        let frame = self.first_frame + frame;
        let sampler = FrameSampler::new(&sampling.over(&self.sampling), seed, frame)?;
        let (w, h) = (self.setup.width, self.setup.height);
        let mut linear = Vec::with_capacity((w * h) as usize);
        for y in 0..h {
            for x in 0..w {
                let mut sum = [0f32; 3];
                let pixel = sampler.pixel(x, y);
                for i in 0..sampler.spp() {
                    let s = pixel.sample(i);
                    let shift = self.speed * (frame as f32 + s.t);
                    let r = self.radiance(x as f32 + 0.5 + s.dx - shift, y as f32 + 0.5 + s.dy);
                    for c in 0..3 {
                        sum[c] += r[c];
                    }
                }
                linear.push(sum.map(|v| v / sampler.spp() as f32));
            }
        }
        let display = linear.iter().flat_map(|p| p.map(srgb8)).collect();
        Ok(RenderedFrame { linear, display })
    }

    fn resized(&self, width: u32, height: u32) -> Result<Box<dyn FrameSource>> {
        let mut s = self.clone();
        s.setup.width = width;
        s.setup.height = height;
        Ok(Box::new(s))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_curve_hits_its_end_points_and_midpoint() {
        assert_eq!(srgb8(0.0), 0);
        assert_eq!(srgb8(1.0), 255);
        assert_eq!(srgb8(30.0), 255);
        assert_eq!(srgb8(f32::NAN), 0);
        // sRGB encodes linear 0.2140 as 0.5 (127.5 / 255).
        assert!((srgb8(0.2140) as i32 - 128).abs() <= 1);
    }

    #[test]
    fn synthetic_frames_are_deterministic_and_sized() {
        let src = SyntheticSource::new(6, 4, 2);
        let cfg = SamplingConfig::default();
        let a = src.render(&cfg, 9, 1).unwrap();
        let b = src.render(&cfg, 9, 1).unwrap();
        assert_eq!(a.display, b.display);
        assert_eq!(a.linear.len(), 24);
        assert_eq!(a.display.len(), 72);
        assert_ne!(src.render(&cfg, 10, 1).unwrap().linear, a.linear);
    }
}
