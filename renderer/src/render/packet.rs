//! Tracing a row [`LANES`] pixels at a time, for worlds with a packet form ([`SmallWorld`]):
//! lane `k` traces the samples of pixel `k` of the group and keeps its sum, so the pixels'
//! sums add in lanes with no serial chain through memory. The camera rays are made straight
//! in the lanes of a [`RayPacket`] (the samples too where the pixels shift the frame's points,
//! [`super::sample_lanes`], else each lane's scrambled sample and shutter time are scalar; a
//! moving camera's frame, the direction through the film point and its normalisation are done
//! for all lanes at once)
//! and shaded by [`Tracer::radiance_packet`], which answers in lanes too. No ray or radiance
//! is ever laid out one at a time.
//!
//! Bit identity with [`super::scalar_span`]: each lane does [`CameraRays::ray`]'s f32
//! operations in its order ([`Projection::direction`]: `sx = (2 fx / w - 1) hw`,
//! `sy = (1 - 2 fy / h) hh`, `d = (forward + right sx) + up sy`, and glam's SSE2
//! `normalize`, `d / sqrt((x x + y y) + z z)`), and each lane's radiance is added to its own
//! pixel in sample order.

use super::CameraRays;
use super::frame_lanes::frames_at;
use super::sample_lanes::{FilmLanes, ShiftedSamples};
use crate::accel::lanes::{LANES, Lanes, RayPacket, dot, each};
use crate::accel::packet::SmallWorld;
use crate::sampling::{FrameSampler, PixelSampler};
use crate::shading::Tracer;
#[cfg(doc)]
use crate::simd;
use crate::simd::Kernel;
use glam::{Vec3, Vec3A};

/// The pixels `x0..x0 + span.len()` of row `y`, to trace into `span` [`LANES`] at a time
/// ([`simd::run_in`] runs it in the lanes of a width; `run` returns the number of samples that
/// were not finite).
pub(super) struct Span<'s, 'a> {
    pub(super) tracer: &'s Tracer<'a>,
    /// The world's packet form, if it has one.
    pub(super) small: Option<&'a SmallWorld>,
    pub(super) sampler: &'s FrameSampler,
    pub(super) camera: &'s CameraRays<'s>,
    pub(super) x0: u32,
    pub(super) y: u32,
    pub(super) span: &'s mut [Vec3],
}

impl Kernel for Span<'_, '_> {
    type Output = u64;

    #[inline(always)]
    fn run<L: Lanes>(self) -> u64 {
        self.trace::<L>()
    }
}

impl Span<'_, '_> {
    /// One lane a pixel: sample `i` of every pixel of the group, for `i` in 0..spp, so each
    /// lane's radiance is added to its own pixel's running sum (kept in lanes) in sample
    /// order, the terms and order of [`super::scalar_span`].
    #[inline(always)]
    fn trace<L: Lanes>(self) -> u64 {
        let Span {
            tracer,
            small,
            sampler,
            camera,
            x0,
            y,
            span,
        } = self;
        let spp = sampler.spp();
        let mut non_finite = 0;
        let mut lanes = CameraLanes::<L>::new(camera);
        // Shifted samples stay in lanes throughout; scrambled ones are looked up lane by lane.
        let shifted = ShiftedSamples::new(sampler, camera.shutter);
        for (x, group) in (x0..).step_by(LANES).zip(span.chunks_mut(LANES)) {
            let pixels: [PixelSampler; LANES] =
                std::array::from_fn(|k| sampler.pixel(x + k.min(group.len() - 1) as u32, y));
            let shift = ShiftedSamples::shifts(&pixels);
            let columns = L::new(std::array::from_fn(|k| (x + k as u32) as f32 + 0.5));
            let mut sum = [L::ZERO; 3];
            for i in 0..spp {
                // Lanes outside `live` keep stale values: their results are never read.
                let (packet, live) = match &shifted {
                    Some(shifted) => {
                        let film = shifted.sample(&shift, columns, y as f32 + 0.5, i);
                        lanes.at(&film, (1 << group.len()) - 1)
                    }
                    None => lanes.set_all(&pixels[..group.len()], x, y, i),
                };
                if live == 0 {
                    continue;
                }
                let l = match small {
                    Some(small) => tracer.radiance_packet(small, &packet, live),
                    None => tracer.radiance_lanes(&packet, live),
                };
                let finite = l[0].is_finite() & l[1].is_finite() & l[2].is_finite();
                let add = finite.to_bitmask() & live;
                non_finite += u64::from((live & !add).count_ones());
                let add = L::lane_mask(add);
                sum = each(|c| add.bitselect(sum[c] + l[c], sum[c]));
            }
            let n = L::splat(spp as f32);
            let [r, g, b] = [sum[0] / n, sum[1] / n, sum[2] / n].map(L::to_array);
            for (k, pixel) in group.iter_mut().enumerate() {
                *pixel = Vec3::new(r[k], g[k], b[k]);
            }
        }
        non_finite
    }
}

/// A packet's camera rays before their directions: each lane's film point and time, and the
/// camera's frame per lane (set once for a still camera, per sample in lanes for a moving one:
/// [`frames_at`]).
struct CameraLanes<'a, L: Lanes> {
    camera: &'a CameraRays<'a>,
    /// The camera does not move: `frame` is set once.
    still: bool,
    fx: [f32; LANES],
    fy: [f32; LANES],
    time: [f32; LANES],
    /// Eye, forward, right, up: per axis, in lanes.
    frame: [[L; 3]; 4],
}

impl<'a, L: Lanes> CameraLanes<'a, L> {
    #[inline(always)]
    fn new(camera: &'a CameraRays<'a>) -> Self {
        let still = !camera.camera.is_moving();
        let splat = |v: Vec3A| each(|k| L::splat(v[k]));
        let frame = match camera.camera.frame_at(0.0).filter(|_| still) {
            Some(view) => [view.eye, view.forward, view.right, view.up].map(splat),
            None => [[L::ZERO; 3]; 4],
        };
        Self {
            camera,
            still,
            fx: [0.0; LANES],
            fy: [0.0; LANES],
            time: [0.0; LANES],
            frame,
        }
    }

    /// Each lane `k` of `pixels` (pixel `(x + k, y)`) takes sample `i`: the packet, and its
    /// live lanes (those of `pixels` where the camera has a frame at the sample's time; the
    /// others' samples are black, as [`CameraRays::ray`] makes them).
    #[inline(always)]
    fn set_all(
        &mut self,
        pixels: &[PixelSampler],
        x: u32,
        y: u32,
        i: usize,
    ) -> (RayPacket<L>, u32) {
        for (k, pixel) in pixels.iter().enumerate() {
            (self.fx[k], self.fy[k], self.time[k]) =
                self.camera.film_point(pixel, x + k as u32, y, i);
        }
        let film = FilmLanes {
            fx: L::new(self.fx),
            fy: L::new(self.fy),
            time: L::new(self.time),
        };
        self.at(&film, (1u32 << pixels.len()) - 1)
    }

    /// The packet through `film`'s points at its times, and the lanes of `live` where the
    /// camera has a frame at the lane's time (the others' samples are black, as
    /// [`CameraRays::ray`] makes them).
    #[inline(always)]
    fn at(&mut self, film: &FilmLanes<L>, mut live: u32) -> (RayPacket<L>, u32) {
        if !self.still {
            let (frame, defined) = frames_at(self.camera.camera, film.time);
            self.frame = frame;
            live &= defined;
        }
        (self.packet(film), live)
    }

    /// The lanes' rays through the film points `film` at its times:
    /// [`Projection::direction`](crate::camera::Projection::direction) in lanes.
    #[inline(always)]
    fn packet(&self, film: &FilmLanes<L>) -> RayPacket<L> {
        let p = &self.camera.projection;
        let two = L::splat(2.0);
        let (fx, fy) = (film.fx, film.fy);
        let sx = (two * fx * L::splat(p.inv_width) - L::ONE) * L::splat(p.half_width);
        let sy = (L::ONE - two * fy * L::splat(p.inv_height)) * L::splat(p.half_height);
        let [eye, forward, right, up] = self.frame;
        let d: [L; 3] = each(|k| forward[k] + right[k] * sx + up[k] * sy);
        let length = dot(&d, &d).sqrt();
        RayPacket {
            origin: eye,
            dir: each(|k| d[k] / length),
            time: film.time,
            t_max: L::splat(f32::INFINITY),
        }
    }
}
