//! A packet's camera rays in worlds without a packet form (meshes: the thesis's plane scene;
//! spinning instances other than orbiting spheres), traced one lane at a time down their mirror
//! chains, with the sky at the end of every chain looked up in lanes.
//!
//! [`Tracer::radiance`] recurses: a reflective hit's radiance is `local + weight * L(bounce)`,
//! and most chains end in the sky (a floor or a chrome sphere reflects the sky more often than
//! anything else), each with a lookup of the environment map on its own. Here a lane walks its
//! chain as a loop, keeping each hit's `local` and `weight` ([`Chain`]); a chain that ends in
//! the sky waits for the packet's other lanes, the sky is looked up for all of them at once
//! ([`Environment::radiance_lanes`]), and each chain is folded from its deepest hit up. The
//! values and the order of every operation are the recursion's ([`Tracer::local`],
//! [`bounce`], `l + weight * x`), so each lane's radiance is [`Tracer::radiance`]'s to the
//! bit, and the ray count grows by the same rays.
//!
//! [`Environment::radiance_lanes`]: crate::environment::Environment::radiance_lanes

use super::packet::{V3, lanes, set};
use super::{Surface, Tracer, bounce};
#[cfg(test)]
use crate::accel::lanes::Lane;
use crate::accel::lanes::{LANES, Lanes, RayPacket};
use crate::geometry::Ray;
use glam::{Vec3, Vec3A};

/// Hits a lane keeps in its chain: a chain longer than this (a scene with more than four
/// bounces) goes on by the scalar recursion from its fifth hit. The thesis's scenes bounce
/// at most three times.
const KEPT: usize = 4;

/// One lane's mirror chain: each reflective hit's radiance before its reflection and the
/// weight of its reflection, from the camera ray's hit down.
#[derive(Clone, Copy, Default)]
struct Chain {
    local: [Vec3; KEPT],
    weight: [Vec3; KEPT],
    len: usize,
}

impl Chain {
    /// The radiance along the chain when its last ray brings `x`: [`Tracer::shade`]'s
    /// `l += weight * L(bounce)`, from the deepest hit up.
    #[inline]
    fn fold(&self, mut x: Vec3) -> Vec3 {
        for k in (0..self.len).rev() {
            x = self.local[k] + self.weight[k] * x;
        }
        x
    }
}

/// How a chain ends: in a radiance, or in the sky seen in a direction.
enum End {
    Radiance(Vec3),
    Sky(Vec3A),
}

impl Tracer<'_> {
    /// [`Tracer::radiance`]`(ray lane i, 0)` for each lane `i` of `live`, for worlds without a
    /// packet form: the camera rays were made in lanes, the lanes whose rays miss the world's
    /// box are culled together ([`World::may_hit_lanes`]), each other lane walks its mirror
    /// chain by the scalar path's intersections and shading, and every chain that ends in the
    /// sky (a culled lane's included) is finished by one lookup in lanes.
    ///
    /// [`World::may_hit_lanes`]: crate::accel::World::may_hit_lanes
    #[inline(always)]
    pub fn radiance_lanes<L: Lanes>(&self, ray: &RayPacket<L>, live: u32) -> V3<L> {
        let mut out = [L::ZERO; 3];
        self.count(live);
        // Rays that surely hit nothing see the sky without the scalar path's walk.
        let maybe = self.world.may_hit_lanes(ray, live);
        if maybe == 0 {
            // A packet of sky only (most of the plane scene's): no chains to keep or fold
            // (an empty chain's fold is its sky), and the lookup is zero in the other lanes.
            return self.sky_lanes(&ray.dir, live);
        }
        let mut sky = live & !maybe;
        let mut dirs = ray.dir;
        let mut chains = [Chain::default(); LANES];
        for i in lanes(maybe) {
            match self.chain(ray.lane(i), &mut chains[i]) {
                End::Radiance(x) => set(&mut out, i, chains[i].fold(x)),
                End::Sky(dir) => {
                    sky |= 1 << i;
                    set(&mut dirs, i, dir.into());
                }
            }
        }
        if sky != 0 {
            let seen = self.sky_lanes(&dirs, sky);
            for i in lanes(sky) {
                let x = Vec3::from(seen.each_ref().map(|c| c.as_array()[i]));
                set(&mut out, i, chains[i].fold(x));
            }
        }
        out
    }

    /// Follows `ray` (counted already) down its mirror chain, keeping each reflective hit in
    /// `chain`, until a hit that does not reflect, the sky, or [`KEPT`] kept hits.
    fn chain(&self, mut ray: Ray, chain: &mut Chain) -> End {
        let mut depth = 0;
        loop {
            let Some(hit) = self.world.intersect_cached(&ray, &self.poses) else {
                return End::Sky(ray.dir);
            };
            let s = Surface::new(self.scene, &ray, &hit);
            let l = self.local(&s, || self.direct(&ray, &s));
            if !self.reflects(&s, depth) {
                return End::Radiance(l);
            }
            match bounce(&ray, &s) {
                Some((next, weight)) if chain.len < KEPT => {
                    chain.local[chain.len] = l;
                    chain.weight[chain.len] = weight;
                    chain.len += 1;
                    // The bounce, as [`Tracer::radiance`] counts it.
                    self.count(1);
                    ray = next;
                    depth += 1;
                }
                // No Fresnel curve (the reflection adds zero), or a chain too long to keep.
                _ => return End::Radiance(l + self.reflection(&ray, &s, depth)),
            }
        }
    }

    /// [`Tracer::background`] in the directions `dirs` of the lanes of `sky`, in lanes.
    #[inline(always)]
    fn sky_lanes<L: Lanes>(&self, dirs: &V3<L>, sky: u32) -> V3<L> {
        match &self.scene.environment {
            Some(env) => env.radiance_lanes(dirs, sky),
            None => [L::ZERO; 3],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::World;
    use crate::hash::{hash, unit_f32};
    use crate::scene::Scene;
    use std::path::Path;

    /// Rays into the wedge where the thesis's chrome centre sphere sits on the (reflective)
    /// floor bounce many times: with 12 bounces allowed some chains outgrow what a lane keeps
    /// and go on by the recursion. With and without the sky map, every lane's radiance and the
    /// rays cast are the scalar path's to the bit.
    #[test]
    fn chains_in_lanes_equal_the_recursion_bit_for_bit_past_what_a_lane_keeps() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/thesis/spheres.json");
        let mut scene = Scene::load(&path).unwrap();
        scene.settings.max_depth = 12;
        let (t0, t1) = scene.settings.shutter(100);
        let world = World::build(scene.instances.clone(), (t0, t1));
        let mut past_kept = 0;
        for sky in [true, false] {
            if !sky {
                scene.environment = None;
            }
            for p in 0..16u64 {
                let h = |i: u64, k: u64| unit_f32(hash(p, &[i, k]));
                let rays: [Ray; LANES] = std::array::from_fn(|i| {
                    let i = i as u64;
                    let origin = Vec3A::new(h(i, 0) - 0.5, 0.02 + 0.1 * h(i, 1), 1.5);
                    let target = Vec3A::new(0.2 * h(i, 2) - 0.1, 0.05 * h(i, 3), 0.0);
                    Ray::new(
                        origin,
                        (target - origin).normalize(),
                        t0 + (t1 - t0) * h(i, 4),
                    )
                });
                let lanes_tracer = Tracer::new(&world, &scene);
                let got = lanes_tracer.radiance_lanes(&RayPacket::<Lane>::new(&rays), 0xff);
                let scalar = Tracer::new(&world, &scene);
                for (i, ray) in rays.iter().enumerate() {
                    let before = scalar.rays();
                    let want = scalar.radiance(ray, 0);
                    // Each kept hit casts its bounce and at most one shadow ray.
                    past_kept += usize::from(scalar.rays() - before > 2 * (KEPT as u64 + 1));
                    let x = Vec3::from(got.each_ref().map(|c| c.as_array()[i]));
                    assert_eq!(
                        x.to_array().map(f32::to_bits),
                        want.to_array().map(f32::to_bits)
                    );
                }
                assert_eq!(lanes_tracer.rays(), scalar.rays(), "packet {p}, sky {sky}");
            }
        }
        assert!(
            past_kept > 0,
            "no chain outgrew a lane's: the test would not fail"
        );
    }
}
