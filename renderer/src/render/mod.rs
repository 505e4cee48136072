//! Rendering one frame: build the world for the frame's shutter, then trace every pixel's
//! samples, tiles in parallel (rayon). A pixel's value depends only on the scene, the sampler
//! (seed, frame) and the pixel, and its samples are summed in a fixed order, so the bytes are
//! the same whatever the thread count or the order tiles finish in.

pub mod pipeline;
pub mod sequence;

use crate::accel::World;
use crate::film::Film;
use crate::geometry::Ray;
use crate::progress::Progress;
use crate::sampling::{FrameSampler, SamplingConfig};
use crate::scene::Scene;
use crate::shading::Tracer;
use anyhow::Result;
use glam::Vec3;
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

/// Side of the square tiles a frame is traced in, in pixels. Tiles keep neighbouring rays (and
/// their BVH nodes and environment texels) on one core, and 256 pixels of work per task leave
/// rayon's work stealing little to balance at the end of a frame.
pub const TILE: u32 = 16;

/// Render scene frame `frame` (its shutter per [`crate::scene::Settings::shutter`]) with
/// `sampling` and the stimulus `seed`, at the scene's size. Tiles of [`TILE`] x [`TILE`]
/// pixels are traced in parallel; `progress` advances by each tile's samples as tiles finish.
pub fn render_frame(
    scene: &Scene,
    sampling: &SamplingConfig,
    seed: u64,
    frame: u32,
    progress: &dyn Progress,
) -> Result<(Film, FrameStats)> {
    let sampler = FrameSampler::new(sampling, seed, frame)?;
    let shutter = scene.settings.shutter(frame);
    let world = World::build(scene.instances.clone(), shutter);
    let (w, h) = (scene.settings.width, scene.settings.height);
    let (tiles_x, tiles_y) = (w.div_ceil(TILE), h.div_ceil(TILE));
    let tiles: Vec<(Vec<Vec3>, FrameStats)> = (0..tiles_x * tiles_y)
        .into_par_iter()
        .map(|i| {
            let x0 = (i % tiles_x) * TILE;
            let y0 = (i / tiles_x) * TILE;
            let (x1, y1) = ((x0 + TILE).min(w), (y0 + TILE).min(h));
            let tracer = Tracer::new(&world, scene);
            let mut pixels = vec![Vec3::ZERO; ((x1 - x0) * (y1 - y0)) as usize];
            let mut stats = FrameStats::default();
            for (row, y) in pixels.chunks_mut((x1 - x0) as usize).zip(y0..y1) {
                let (samples, non_finite) = render_span(&tracer, &sampler, shutter, x0, y, row);
                stats.samples += samples;
                stats.non_finite += non_finite;
            }
            stats.rays = tracer.rays();
            progress.advance(stats.samples);
            (pixels, stats)
        })
        .collect();
    let mut film = Film::new(w, h);
    let mut stats = FrameStats::default();
    for (i, (pixels, s)) in (0..).zip(&tiles) {
        let x0 = ((i % tiles_x) * TILE) as usize;
        let y0 = ((i / tiles_x) * TILE) as usize;
        let tw = (TILE.min(w - x0 as u32)) as usize;
        for (dy, row) in pixels.chunks(tw).enumerate() {
            let at = (y0 + dy) * w as usize + x0;
            film.pixels[at..at + tw].copy_from_slice(row);
        }
        stats += *s;
    }
    Ok((film, stats))
}

/// Trace every sample of the pixels `x0..x0 + span.len()` of row `y` into `span`; returns the
/// samples traced and how many were not finite.
fn render_span(
    tracer: &Tracer,
    sampler: &FrameSampler,
    shutter: (f32, f32),
    x0: u32,
    y: u32,
    span: &mut [Vec3],
) -> (u64, u64) {
    let scene = tracer.scene;
    let camera = &scene.camera;
    let projection = camera.projection(scene.settings.width, scene.settings.height);
    let spp = sampler.spp();
    let mut non_finite = 0;
    for (x, pixel) in (x0..).zip(span.iter_mut()) {
        let mut sum = Vec3::ZERO;
        let pixel_sampler = sampler.pixel(x, y);
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
    ((span.len() * spp) as u64, non_finite)
}
