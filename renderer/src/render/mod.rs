//! Rendering one frame: build the world for the frame's shutter, then trace every pixel's
//! samples, tiles in parallel (rayon). A pixel's value depends only on the scene, the sampler
//! (seed, frame) and the pixel, and its samples are summed in a fixed order, so the bytes are
//! the same whatever the thread count or the order tiles finish in.

mod frame_lanes;
mod packet;
pub mod pipeline;
mod sample_lanes;
pub mod sequence;

use crate::accel::World;
use crate::camera::{Camera, Projection};
use crate::film::Film;
use crate::geometry::Ray;
use crate::progress::Progress;
use crate::sampling::PixelSampler;
use crate::sampling::{FrameSampler, SamplingConfig};
use crate::scene::Scene;
use crate::shading::Tracer;
use crate::simd::{self, Width};
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
    render_frame_on(scene, sampling, seed, frame, progress, Some(simd::widest()))
}

/// [`render_frame`], tracing [`LANES`](crate::accel::lanes::LANES) samples at once in lanes of
/// width `packets` if some (camera rays in lanes; shaded in lanes where the world has a packet
/// form, [`World::small`]), else one at a time; every way gives the same bytes (the tests
/// compare them).
pub(crate) fn render_frame_on(
    scene: &Scene,
    sampling: &SamplingConfig,
    seed: u64,
    frame: u32,
    progress: &dyn Progress,
    packets: Option<Width>,
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
                let (samples, non_finite) =
                    render_span(&tracer, packets, &sampler, shutter, x0, y, row);
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

/// Trace every sample of the pixels `x0..x0 + span.len()` of row `y` into `span`, [`LANES`]
/// at a time in lanes of width `packets` if some (shaded in lanes where the world has a packet form, [`World::small`],
/// else lane by lane); returns the samples traced and how many were not finite.
fn render_span(
    tracer: &Tracer,
    packets: Option<Width>,
    sampler: &FrameSampler,
    shutter: (f32, f32),
    x0: u32,
    y: u32,
    span: &mut [Vec3],
) -> (u64, u64) {
    let scene = tracer.scene;
    let camera = CameraRays {
        camera: &scene.camera,
        projection: scene
            .camera
            .projection(scene.settings.width, scene.settings.height),
        shutter,
    };
    let spp = sampler.spp();
    let non_finite = match packets {
        Some(width) => simd::run_in(
            width,
            packet::Span {
                tracer,
                small: tracer.world.small(),
                sampler,
                camera: &camera,
                x0,
                y,
                span,
            },
        ),
        None => scalar_span(tracer, sampler, &camera, x0, y, span),
    };
    ((span.len() * spp) as u64, non_finite)
}

/// Camera rays of one frame.
struct CameraRays<'a> {
    camera: &'a Camera,
    projection: Projection,
    shutter: (f32, f32),
}

impl CameraRays<'_> {
    /// The ray of sample `i` of pixel `(x, y)`.
    #[inline]
    fn ray(&self, pixel: &PixelSampler, x: u32, y: u32, i: usize) -> Option<Ray> {
        let (fx, fy, time) = self.film_point(pixel, x, y, i);
        // A moving camera can lose its frame only between validated frame boundaries
        // (look-at passing through the eye); such a sample is black, never NaN.
        let view = self.camera.frame_at(time)?;
        let dir = self.projection.direction(&view, fx, fy);
        Some(Ray::new(view.eye, dir, time))
    }

    /// Sample `i` of pixel `(x, y)` on the film, in pixels from the top-left corner, and its
    /// scene time.
    #[inline(always)]
    fn film_point(&self, pixel: &PixelSampler, x: u32, y: u32, i: usize) -> (f32, f32, f32) {
        let s = pixel.sample(i);
        let time = self.shutter.0 + s.t * (self.shutter.1 - self.shutter.0);
        (x as f32 + 0.5 + s.dx, y as f32 + 0.5 + s.dy, time)
    }
}

/// One ray at a time: each pixel's samples summed in order 0..spp; returns the number of
/// samples that were not finite.
fn scalar_span(
    tracer: &Tracer,
    sampler: &FrameSampler,
    camera: &CameraRays,
    x0: u32,
    y: u32,
    span: &mut [Vec3],
) -> u64 {
    let spp = sampler.spp();
    let mut non_finite = 0;
    for (x, pixel) in (x0..).zip(span.iter_mut()) {
        let pixel_sampler = sampler.pixel(x, y);
        let mut sum = Vec3::ZERO;
        for ray in (0..spp).filter_map(|i| camera.ray(&pixel_sampler, x, y, i)) {
            let l = tracer.radiance(&ray, 0);
            if l.is_finite() {
                sum += l;
            } else {
                non_finite += 1;
            }
        }
        *pixel = sum / spp as f32;
    }
    non_finite
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::progress::NoProgress;
    use serde_json::json;
    use std::path::Path;

    /// Spheres (moving, turned and scaled, mirror-like) over a rectangle and an infinite plane,
    /// a rectangle seen from its back, a point and a directional light, a moving camera: every
    /// kind of work the packet path does.
    fn small_scene() -> Scene {
        let v = json!({
            "format": "blurlab-scene/1",
            "materials": [
                {"name": "m", "diffuse": [0.6, 0.5, 0.4], "specular": [0.3, 0.3, 0.3],
                 "ambient": [0.1, 0.1, 0.1], "fresnel": {"min": 0.2, "max": 1.0, "exponent": 5}},
                {"name": "shiny", "diffuse": [0.2, 0.3, 0.4], "specular": [0.5, 0.5, 0.5],
                 "phong_exponent": 30},
                {"name": "floor", "diffuse": [0.5, 0.5, 0.5]}
            ],
            "objects": [
                {"name": "ball", "type": "sphere", "radius": 0.5, "material": "m",
                 "location": [-1, 0.5, 0], "velocity": [2, 0, 0]},
                {"name": "egg", "type": "sphere", "radius": 0.4, "material": "shiny",
                 "location": [1, 0.6, -0.5], "rotation": [10, 20, 30], "scale": [1, 1.5, 0.8]},
                {"name": "still", "type": "sphere", "radius": 0.3, "material": "shiny",
                 "location": [0.2, 0.3, 1]},
                {"name": "rug", "type": "plane", "material": "m", "half_extent": [1, 0.7],
                 "location": [0, 0.01, 0.5]},
                {"name": "wall", "type": "plane", "material": "shiny", "half_extent": [0.6, 0.5],
                 "location": [-1.6, 0.8, -0.8], "rotation": [-80, 20, 0]},
                {"name": "floor", "type": "plane", "material": "floor"}
            ],
            "lights": [
                {"type": "point", "position": [2, 3, 2], "intensity": 8},
                {"type": "directional", "direction": [-1, -2, -1]}
            ],
            "camera": {"location": [0, 1.5, 5], "look_at": [0, 0.5, 0], "fov": 45,
                       "location_velocity": [0.5, 0, 0]},
            "settings": {"start_time": 0.0, "frame_time": 0.1, "frames": 2, "width": 37,
                         "height": 21, "max_depth": 2, "ambient_light": [0.3, 0.3, 0.4]},
        });
        Scene::from_json(&v.to_string(), Path::new("small.json")).unwrap()
    }

    /// [`small_scene`] with a still camera (its frame set once), a mirror-like floor and a
    /// small environment map that misses and reflections see.
    fn still_scene_under_a_sky() -> Scene {
        let mut scene = small_scene();
        let c = &scene.camera;
        let still = |m: crate::camera::Moving| crate::camera::Moving::still(m.at_zero);
        scene.camera = Camera::new(
            still(c.location),
            still(c.look_at),
            still(c.up),
            c.fov_degrees,
        )
        .unwrap();
        let floor = scene.materials.len() - 1;
        scene.materials[floor] = scene.materials[0];
        let (w, h) = (8, 4);
        let texels = (0..w * h)
            .map(|i| Vec3::new(i as f32 * 0.1, 0.5, 1.0 / (1.0 + i as f32)))
            .collect();
        let (env, _) = crate::environment::Environment::new(w, h, texels, 1.5, 30.0);
        scene.environment = Some(std::sync::Arc::new(env));
        scene
    }

    /// The sampling a frame test renders with: the default (Gaussian spatial filter), box
    /// filters (the packet path's samples in lanes), box filters with scrambled points.
    #[derive(Clone, Copy, Debug)]
    enum Filters {
        Default,
        Box,
        BoxScrambled,
    }

    impl Filters {
        fn sampling(self, spp: u32) -> SamplingConfig {
            let boxed = SamplingConfig {
                spp,
                point_set: "sobol".parse().unwrap(),
                time_filter: "box".parse().unwrap(),
                spatial_filter: Some(crate::sampling::SpatialFilter::Box),
                ..SamplingConfig::default()
            };
            match self {
                Filters::Default => SamplingConfig {
                    spp,
                    ..SamplingConfig::default()
                },
                Filters::Box => boxed,
                Filters::BoxScrambled => SamplingConfig {
                    randomization: Some(crate::sampling::Randomization::Scramble),
                    ..boxed
                },
            }
        }
    }

    /// A film's pixels as bits.
    fn bits(f: &Film) -> Vec<[u32; 3]> {
        f.pixels
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect()
    }

    /// The thesis's scene `name` (`scenes/thesis/`) at `width` x `height`.
    fn thesis_scene(name: &str, width: u32, height: u32) -> Scene {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../scenes/thesis")
            .join(format!("{name}.json"));
        let mut scene = Scene::load(&path).unwrap();
        (scene.settings.width, scene.settings.height) = (width, height);
        scene
    }

    /// The thesis's own scenes, the plane without a packet form (a moving mesh under a moving
    /// camera: its camera rays in lanes) and the spheres with one (orbiting spheres: traced and
    /// shaded in lanes, mirror bounces included): the same bytes as one ray at a time, with the scenes' own sampling (Gaussian pixel filter, triangle time
    /// filter) and a box-filtered one, at the frames the benchmarks time.
    #[test]
    fn thesis_scenes_in_lanes_equal_scalar_frames_bit_for_bit() {
        for (name, frame, size) in [("plane", 93, (45, 40)), ("spheres", 100, (29, 24))] {
            let scene = thesis_scene(name, size.0, size.1);
            let world = World::build(scene.instances.clone(), scene.settings.shutter(frame));
            // The spheres (orbiting balls, a fixed one, a plane) have a packet form.
            assert_eq!(world.small().is_some(), name == "spheres", "{name}");
            for (spp, sampling) in [
                (3, scene.settings.sampling.clone()),
                (8, Filters::Box.sampling(8)),
            ] {
                let sampling = SamplingConfig { spp, ..sampling };
                let render = |packets| {
                    render_frame_on(&scene, &sampling, 5, frame, &NoProgress, packets).unwrap()
                };
                let (b, sb) = render(None);
                for &width in simd::widths() {
                    let (a, sa) = render(Some(width));
                    assert_eq!(sa, sb, "{name}, spp {spp}, {width:?}");
                    assert!(sa.rays > sa.samples, "{name}: some samples hit something");
                    assert!(
                        bits(&a) == bits(&b),
                        "{name}, spp {spp}, {width:?}: the pixels differ"
                    );
                }
            }
        }
    }

    #[test]
    fn packet_frames_equal_scalar_frames_bit_for_bit() {
        for (name, scene) in [
            ("moving camera", small_scene()),
            ("still camera, sky", still_scene_under_a_sky()),
        ] {
            assert_eq!(scene.camera.is_moving(), name == "moving camera");
            let shutter = scene.settings.shutter(1);
            assert!(
                World::build(scene.instances.clone(), shutter)
                    .small()
                    .is_some()
            );
            for (spp, filters) in [1, 3, 4, 5, 7, 8, 9, 16].into_iter().flat_map(|spp| {
                [
                    (spp, Filters::Default),
                    (spp, Filters::Box),
                    (spp, Filters::BoxScrambled),
                ]
            }) {
                let sampling = filters.sampling(spp);
                let render = |packets| {
                    render_frame_on(&scene, &sampling, 3, 1, &NoProgress, packets).unwrap()
                };
                let (b, sb) = render(None);
                for &width in simd::widths() {
                    let (a, sa) = render(Some(width));
                    assert_eq!(sa, sb, "{name}, spp {spp}, {filters:?}, {width:?}");
                    assert!(
                        bits(&a) == bits(&b),
                        "{name}, spp {spp}, {filters:?}, {width:?}: the pixels differ"
                    );
                    assert!(sa.rays > sa.samples * 2, "shadow and mirror rays are cast");
                }
            }
        }
    }
}
