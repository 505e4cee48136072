//! Shading [`LANES`] camera rays at once, for worlds with a packet form
//! ([`crate::accel::packet::SmallWorld`]): the primary rays go through
//! [`SmallWorld::intersect_lanes`](crate::accel::packet::SmallWorld::intersect_lanes)
//! together, and for each light the lanes' shadow rays through `occluded_lanes` together, so
//! the latency of one lane's square roots and divisions hides behind the others'.
//!
//! Each lane's radiance is [`Tracer::radiance`]'s to the bit: the same scalar code prepares
//! every shadow ray and shades every hit ([`Surface::new`], [`shadow_ray`], [`lit_by`]), the
//! per-lane sums add the same terms in the same order (ambient, then each light in scene
//! order, then the reflection: [`Tracer::combine`]), and the ray count grows by the same rays. Reflections take
//! the scalar path per lane.

use super::{Surface, Tracer, lit_by, shadow_ray};
use crate::accel::packet::{LANES, SmallWorld};
use crate::geometry::Ray;
use crate::light::LightSample;
use glam::Vec3;

impl Tracer<'_> {
    /// [`Tracer::radiance`]`(rays[i], 0)` for each lane `i` whose bit is set in `live` (the
    /// others give zero and cast nothing). The world must have a packet form.
    pub fn radiance_lanes(
        &self,
        small: &SmallWorld,
        rays: &[Ray; LANES],
        live: u32,
    ) -> [Vec3; LANES] {
        self.count(live);
        let hits = small.intersect_lanes(self.world, rays, live);
        let surfaces: [Option<Surface>; LANES] =
            std::array::from_fn(|i| Some(Surface::new(self.scene, &rays[i], hits[i].as_ref()?)));
        let direct = self.direct_lanes(small, rays, &surfaces);
        std::array::from_fn(|i| match &surfaces[i] {
            Some(s) => self.combine(&rays[i], s, 0, || direct[i]),
            None if live & (1 << i) != 0 => self.background(rays[i].dir),
            None => Vec3::ZERO,
        })
    }

    /// [`Tracer::direct`] for the lanes with a lit surface: per light, the lanes' shadow rays
    /// are tested together.
    fn direct_lanes(
        &self,
        small: &SmallWorld,
        rays: &[Ray; LANES],
        surfaces: &[Option<Surface>; LANES],
    ) -> [Vec3; LANES] {
        let mut sum = [Vec3::ZERO; LANES];
        // Filled in place per light (lanes outside `live` keep stale rays, never read).
        let mut shadows = *rays;
        let mut samples: [Option<(LightSample, f32)>; LANES] = [None; LANES];
        for light in &self.scene.lights {
            let mut live = 0;
            for (i, surface) in surfaces.iter().enumerate() {
                samples[i] = None;
                let Some(s) = surface.as_ref().filter(|s| s.m.lit()) else {
                    continue;
                };
                if let Some((shadow, sample, cos)) = shadow_ray(&rays[i], s, light) {
                    shadows[i] = shadow;
                    samples[i] = Some((sample, cos));
                    live |= 1 << i;
                }
            }
            if live == 0 {
                continue;
            }
            self.count(live);
            let blocked = small.occluded_lanes(self.world, &shadows, live);
            for (i, surface) in surfaces.iter().enumerate() {
                if let (Some((sample, cos)), Some(s), false) = (&samples[i], surface, blocked[i]) {
                    sum[i] += lit_by(s, sample, *cos);
                }
            }
        }
        sum
    }

    /// Count one ray per lane of `live`.
    fn count(&self, live: u32) {
        self.rays
            .set(self.rays.get() + u64::from(live.count_ones()));
    }
}
