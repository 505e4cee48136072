//! Shading [`LANES`] camera rays at once, for worlds with a packet form
//! ([`crate::accel::packet::SmallWorld`]): the primary rays go through
//! [`SmallWorld::intersect_lanes`](crate::accel::packet::SmallWorld::intersect_lanes)
//! together, and for each light the lanes' shadow rays through `occluded_lanes` together, so
//! the latency of one lane's square roots and divisions hides behind the others'.
//!
//! Each lane's radiance is [`Tracer::radiance`]'s to the bit: the same scalar code prepares
//! every shadow ray and shades every hit ([`shadow_ray`], [`lit_by`], [`facing_normals`]), the
//! per-lane sums add the same terms in the same order (ambient, then each light in scene
//! order, then the reflection), and the ray count grows by the same rays. Reflections take
//! the scalar path per lane.

use super::{Tracer, facing_normals, lit_by, shadow_ray};
use crate::accel::SurfaceHit;
use crate::accel::packet::{LANES, SmallWorld};
use crate::geometry::Ray;
use crate::light::LightSample;
use crate::material::Material;
use glam::{Vec3, Vec3A};

/// A lane's hit, ready to shade.
struct Surface<'a> {
    hit: &'a SurfaceHit,
    m: &'a Material,
    ng: Vec3A,
    ns: Vec3A,
    v: Vec3A,
}

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
        let surfaces: [Option<Surface>; LANES] = std::array::from_fn(|i| {
            let hit = hits[i].as_ref()?;
            let v = -rays[i].dir;
            let (ng, ns) = facing_normals(hit, v);
            let m = &self.scene.materials[hit.material as usize];
            Some(Surface { hit, m, ng, ns, v })
        });
        let direct = self.direct_lanes(small, rays, &surfaces);
        std::array::from_fn(|i| match &surfaces[i] {
            Some(s) => {
                let mut l = s.m.ambient * self.scene.settings.ambient_light;
                if s.m.lit() {
                    l += direct[i];
                }
                if 0 < self.max_depth && s.m.reflective() {
                    l += self.reflection(&rays[i], s.hit, s.m, s.ng, s.ns, s.v, 0);
                }
                l
            }
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
                if let Some((shadow, sample, cos)) = shadow_ray(&rays[i], s.hit, s.ng, s.ns, light)
                {
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
                    sum[i] += lit_by(s.m, s.ns, s.v, sample, *cos);
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
