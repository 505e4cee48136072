//! Rendering one frame: build the world for the frame's shutter, then trace every pixel's
//! samples, rows in parallel (rayon). A pixel's value depends only on the scene, the sampler
//! (seed, frame) and the pixel, and its samples are summed in a fixed order, so the bytes are
//! the same whatever the thread count or the order rows finish in.

pub mod sequence;

use crate::accel::World;
use crate::film::Film;
use crate::geometry::Ray;
use crate::sampling::{FrameSampler, SamplingConfig};
use crate::scene::Scene;
use crate::shading::Tracer;
use anyhow::Result;
use glam::Vec3;
use indicatif::ProgressBar;
use rayon::prelude::*;

/// Counts from one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameStats {
    /// Camera samples traced (pixels x spp).
    pub samples: u64,
    /// Rays cast: primary, shadow and reflection.
    pub rays: u64,
    /// Samples whose radiance was NaN or infinite (counted, then taken as 0). Should be 0.
    pub non_finite: u64,
}

impl std::ops::AddAssign for FrameStats {
    fn add_assign(&mut self, o: Self) {
        self.samples += o.samples;
        self.rays += o.rays;
        self.non_finite += o.non_finite;
    }
}

/// Render scene frame `frame` (its shutter per [`crate::scene::Settings::shutter`]) with
/// `sampling` and the stimulus `seed`, at the scene's size. `progress` advances by each row's
/// samples as rows finish.
pub fn render_frame(
    scene: &Scene,
    sampling: &SamplingConfig,
    seed: u64,
    frame: u32,
    progress: Option<&ProgressBar>,
) -> Result<(Film, FrameStats)> {
    let sampler = FrameSampler::new(sampling, seed, frame)?;
    let shutter = scene.settings.shutter(frame);
    let world = World::build(scene.instances.clone(), shutter);
    let (w, h) = (scene.settings.width, scene.settings.height);
    let mut film = Film::new(w, h);
    let stats = film
        .pixels
        .par_chunks_mut(w as usize)
        .enumerate()
        .map(|(y, row)| {
            let tracer = Tracer::new(&world, scene);
            let stats = render_row(&tracer, &sampler, shutter, y as u32, row);
            if let Some(p) = progress {
                p.inc(stats.samples);
            }
            stats
        })
        .reduce(FrameStats::default, |mut a, b| {
            a += b;
            a
        });
    Ok((film, stats))
}

/// Trace every sample of row `y` into `row`.
fn render_row(
    tracer: &Tracer,
    sampler: &FrameSampler,
    shutter: (f32, f32),
    y: u32,
    row: &mut [Vec3],
) -> FrameStats {
    let scene = tracer.scene;
    let camera = &scene.camera;
    let projection = camera.projection(scene.settings.width, scene.settings.height);
    let spp = sampler.spp();
    let mut non_finite = 0;
    for (x, pixel) in row.iter_mut().enumerate() {
        let mut sum = Vec3::ZERO;
        let pixel_sampler = sampler.pixel(x as u32, y);
        for i in 0..spp {
            let s = pixel_sampler.sample(i);
            let time = shutter.0 + s.t * (shutter.1 - shutter.0);
            // A moving camera can lose its frame only between validated frame boundaries
            // (look-at passing through the eye); such a sample is black, never NaN.
            let Some(view) = camera.frame_at(time) else {
                continue;
            };
            let dir = projection.direction(&view, x as f32 + 0.5 + s.dx, y as f32 + 0.5 + s.dy);
            let l = tracer.radiance(&Ray::new(view.eye, dir, time), 0);
            if l.is_finite() {
                sum += l;
            } else {
                non_finite += 1;
            }
        }
        *pixel = sum / spp as f32;
    }
    FrameStats {
        samples: (row.len() * spp) as u64,
        rays: tracer.rays(),
        non_finite,
    }
}
