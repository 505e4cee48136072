//! Shading [`LANES`] camera rays at once, in lanes, for worlds with a packet form
//! ([`SmallWorld`]). The rays arrive as a [`RayPacket`] and stay in lanes: the nearest hits,
//! the normals turned towards the viewer, each light's sample, the shadow rays (tested
//! together by [`SmallWorld::blocked`]) and the Lambert and Phong terms are computed for all
//! lanes at once, so the latency of one lane's square roots and divisions hides behind the
//! others' and no lane pays for moving its data between vector layouts.
//!
//! Each lane's radiance is [`Tracer::radiance`]'s to the bit: every lane does the scalar
//! code's f32 operations ([`Surface::new`], [`shadow_ray`](super::shadow_ray),
//! [`lit_by`](super::lit_by), [`SurfaceHit::spawn_point`], [`Light::sample`]) in the scalar
//! order, the sums add the same terms in the same order (ambient, then each light in scene
//! order, then the reflection: [`Tracer::local`]), and the ray count grows by the same rays.
//! Mirror reflections stay in lanes too: each reflective lane's mirror ray and Fresnel weight
//! are the scalar [`bounce`]'s, and the packet's mirror rays are traced as a packet one bounce
//! deeper, recursively to `max_depth` (`Tracer::packet_at`), each lane adding `weight * L`
//! last, as [`Tracer::shade`] does. What the lanes do not do, a lane hands to the scalar code:
//! a ray the packet form cannot trace (see [`crate::accel::packet`]) is traced by
//! [`Tracer::radiance`], a shadow ray by [`World::occluded`](crate::accel::World::occluded), and
//! the Phong lobe's and the Fresnel curve's `powf` per lane. The lanes that miss look up the
//! environment together ([`crate::environment::Environment::radiance_lanes`]). The orbiting
//! spheres' centres are worked out once per camera packet ([`SmallWorld::centres`]) and shared
//! by its shadow and mirror rays, which keep its times.

use super::{Surface, Tracer, bounce, phong};
use crate::accel::SurfaceHit;
use crate::accel::lanes::{LANES, Lane, Lanes, RayPacket, dot, each, point_at};
use crate::accel::packet::{Centres, Nearest, SmallWorld};
use crate::light::Light;
use crate::material::Material;
use crate::simd::Kernel;
use glam::{Vec3, Vec3A};

/// A vector per lane.
pub type V3<L = Lane> = [L; 3];

impl<'a> Tracer<'a> {
    /// [`Tracer::radiance`]`(ray lane i, 0)` for each lane `i` whose bit is set in `live`, in
    /// lanes (the others' values are not to be read; they cast nothing). `small` must be the
    /// world's packet form.
    #[inline(always)]
    pub fn radiance_packet<L: Lanes>(
        &self,
        small: &'a SmallWorld,
        ray: &RayPacket<L>,
        live: u32,
    ) -> V3<L> {
        // The orbiting spheres' centres at the lanes' times, for every ray of the packet: the
        // tracer's cells, made once and reset per packet.
        let mut cells = self.centres.borrow_mut();
        let centres = cells.get_or_insert_with(|| small.centres(ray.time.to_wide()));
        centres.reset(ray.time.to_wide());
        self.packet_at(small, centres, ray, live, 0)
    }

    /// [`Tracer::radiance`]`(ray lane i, depth)` for the lanes of `live`, in lanes; `centres`
    /// at the lanes' times (a mirror ray keeps its camera ray's time).
    #[inline(always)]
    fn packet_at<L: Lanes>(
        &self,
        small: &SmallWorld,
        centres: &Centres,
        ray: &RayPacket<L>,
        live: u32,
        depth: u32,
    ) -> V3<L> {
        let simple = SmallWorld::simple_packet(self.world.shutter(), ray, live);
        let nearest = small.nearest(ray, simple, centres);
        // A tie between instances is the scalar path's to break.
        let packet = simple & !nearest.tie.to_bitmask();
        self.count(packet);
        let hit = packet & nearest.hit();
        let mut out = match hit {
            0 => [L::ZERO; 3],
            _ => {
                let h = Hits::new(self, small, centres, ray, &nearest, hit);
                self.shade_packet(small, centres, ray, &h, depth)
            }
        };
        self.background_lanes(ray, packet & !hit, &mut out);
        for i in lanes(live & !packet) {
            set(&mut out, i, self.radiance(&ray.lane(i), depth));
        }
        out
    }

    /// [`Tracer::background`] of the lanes of `missed` into `out` (left as it is in the
    /// others): the environment lookups in lanes ([`Environment::radiance_lanes`]).
    ///
    /// [`Environment::radiance_lanes`]: crate::environment::Environment::radiance_lanes
    #[inline(always)]
    fn background_lanes<L: Lanes>(&self, ray: &RayPacket<L>, missed: u32, out: &mut V3<L>) {
        let Some(env) = self.scene.environment.as_ref().filter(|_| missed != 0) else {
            return;
        };
        let sky = env.radiance_lanes(&ray.dir, missed);
        let m = L::lane_mask(missed);
        *out = each(|k| m.bitselect(sky[k], out[k]));
    }

    /// [`Tracer::shade`] at `depth` for the lanes of `h` (zero in the others).
    #[inline(always)]
    fn shade_packet<L: Lanes>(
        &self,
        small: &SmallWorld,
        centres: &Centres,
        ray: &RayPacket<L>,
        h: &Hits<L>,
        depth: u32,
    ) -> V3<L> {
        let hit = h.lanes;
        let direct = self.direct_packet(small, centres, ray, h);
        // [`Tracer::local`]: the ambient term, then the direct light for a lit material.
        let (lit, hit_lanes) = (L::lane_mask(h.m.lit), L::lane_mask(hit));
        let a = self.scene.settings.ambient_light.to_array();
        // A loop, not a closure: a closure of this many lane operations was left out of line,
        // outside the AVX2 entry (`bench/lanes.sh` finds such calls).
        let mut l = [L::ZERO; 3];
        for (k, l) in l.iter_mut().enumerate() {
            let ambient = h.m.ambient[k] * L::splat(a[k]);
            *l = hit_lanes.bitselect(lit.bitselect(ambient + direct[k], ambient), L::ZERO);
        }
        // Then the mirror reflection ([`Tracer::reflects`]), its rays traced as a packet.
        let reflect = match depth < self.max_depth {
            true => hit & h.m.reflective,
            false => 0,
        };
        if reflect != 0 {
            self.reflect_packet(small, centres, ray, h, reflect, depth, &mut l);
        }
        l
    }

    /// `l += `[`Tracer::reflection`] for the lanes of `reflect`: each lane's mirror ray and
    /// Fresnel weight are the scalar [`bounce`]'s, the rays are traced together one bounce
    /// deeper ([`Tracer::packet_at`], recursively), and each lane adds `weight * L(bounce)`
    /// (`0` for a material without a Fresnel curve), as the recursion does.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn reflect_packet<L: Lanes>(
        &self,
        small: &SmallWorld,
        centres: &Centres,
        ray: &RayPacket<L>,
        h: &Hits<L>,
        reflect: u32,
        depth: u32,
        l: &mut V3<L>,
    ) {
        // Lanes outside `live` keep the incoming rays (never read).
        let mut mirror = *ray;
        let mut weight = [L::ZERO; 3];
        let mut live = 0;
        for i in lanes(reflect) {
            let r = ray.lane(i);
            let hit = h.hit(small, i);
            if let Some((b, w)) = bounce(&r, &Surface::new(self.scene, &r, &hit)) {
                set(&mut mirror.origin, i, b.origin.into());
                set(&mut mirror.dir, i, b.dir.into());
                mirror.t_max.as_mut_array()[i] = b.t_max;
                set(&mut weight, i, w);
                live |= 1 << i;
            }
        }
        let x = match live {
            0 => [L::ZERO; 3],
            // Through the lanes' entry: a recursion cannot inline (`simd::Lanes::enter`).
            _ => L::enter(Bounce {
                tracer: self,
                small,
                centres,
                ray: &mirror,
                live,
                depth: depth + 1,
            }),
        };
        let (on, add) = (L::lane_mask(live), L::lane_mask(reflect));
        *l = each(|k| {
            let reflection = on.bitselect(weight[k] * x[k], L::ZERO);
            add.bitselect(l[k] + reflection, l[k])
        });
    }

    /// [`Tracer::direct`] for the lit lanes of `h`: per light, the lanes' shadow rays are
    /// made and tested together.
    #[inline(always)]
    fn direct_packet<L: Lanes>(
        &self,
        small: &SmallWorld,
        centres: &Centres,
        ray: &RayPacket<L>,
        h: &Hits<L>,
    ) -> V3<L> {
        let mut sum = [L::ZERO; 3];
        let lit = h.lanes & h.m.lit;
        if lit == 0 {
            return sum;
        }
        for light in &self.scene.lights {
            let s = LightLanes::sample(light, &h.point);
            // [`shadow_ray`](super::shadow_ray): `None` below either surface.
            let cos = dot(&h.ns, &s.towards);
            let below = cos.simd_le(L::ZERO) | dot(&h.ng, &s.towards).simd_le(L::ZERO);
            let live = lit & s.ok.to_bitmask() & !below.to_bitmask();
            if live == 0 {
                continue;
            }
            self.count(live);
            let shadow = s.shadow_ray(ray, h);
            let open = live & !self.blocked(small, centres, &shadow, live);
            if open == 0 {
                continue;
            }
            let add = h.lit_by(&s, cos, open);
            let open = L::lane_mask(open);
            sum = each(|k| open.bitselect(sum[k] + add[k], sum[k]));
        }
        sum
    }

    /// [`World::occluded`](crate::accel::World::occluded) for the lanes of `live`: the lanes
    /// blocked.
    #[inline(always)]
    fn blocked<L: Lanes>(
        &self,
        small: &SmallWorld,
        centres: &Centres,
        shadow: &RayPacket<L>,
        live: u32,
    ) -> u32 {
        let simple = SmallWorld::simple_packet(self.world.shutter(), shadow, live);
        let mut blocked = match simple {
            0 => 0,
            _ => small.blocked(shadow, simple, centres),
        };
        for i in lanes(live & !simple) {
            blocked |= u32::from(self.world.occluded_cached(&shadow.lane(i), &self.poses)) << i;
        }
        blocked
    }

    /// Count one ray per lane of `live`.
    pub(super) fn count(&self, live: u32) {
        self.rays
            .set(self.rays.get() + u64::from(live.count_ones()));
    }
}

/// [`Tracer::packet_at`] for a packet's mirror rays, as a [`Kernel`].
struct Bounce<'a, 'b, L: Lanes> {
    tracer: &'a Tracer<'b>,
    small: &'a SmallWorld,
    centres: &'a Centres<'a>,
    ray: &'a RayPacket<L>,
    live: u32,
    depth: u32,
}

impl<L: Lanes> Kernel for Bounce<'_, '_, L> {
    type Output = V3<L>;

    /// In lanes of type `M`: `L` itself (`Lanes::enter`), so the casts are no-ops.
    #[inline(always)]
    fn run<M: Lanes>(self) -> V3<L> {
        let ray = self.ray.cast::<M>();
        let x = (self.tracer).packet_at(self.small, self.centres, &ray, self.live, self.depth);
        each(|k| L::from_wide(x[k].to_wide()))
    }
}

/// The hits of a packet ready to shade: [`Surface`] in lanes, with the materials' terms.
struct Hits<L: Lanes> {
    /// The lanes shaded here (bit `i` for lane `i`).
    lanes: u32,
    /// The instance each lane hit.
    instance: L,
    t: L,
    point: V3<L>,
    /// The normal as the instance faces ([`SurfaceHit`]'s geometric and shading normal).
    normal: V3<L>,
    /// The normals turned towards the viewer, and the direction towards the viewer.
    ng: V3<L>,
    ns: V3<L>,
    v: V3<L>,
    m: Materials<L>,
}

impl<L: Lanes> Hits<L> {
    /// The hits of the lanes of `lanes`: each instance's normals and material for the lanes
    /// it won, for the instances some lane won only (a packet meets one to three of the
    /// world's up to 24 instances).
    #[inline(always)]
    fn new(
        tracer: &Tracer,
        small: &SmallWorld,
        centres: &Centres,
        ray: &RayPacket<L>,
        nearest: &Nearest<L>,
        lanes: u32,
    ) -> Self {
        let point = point_at(&ray.origin, &ray.dir, nearest.t);
        let mut normal = [L::ZERO; 3];
        let mut m = Materials::default();
        let on_lanes = L::lane_mask(lanes);
        let instances = nearest.instance.to_array();
        let mut pending = lanes;
        while pending != 0 {
            let i = instances[pending.trailing_zeros() as usize] as usize;
            let on = nearest.is(i) & on_lanes;
            pending &= !on.to_bitmask();
            normal = select(on, &small.normal(i, ray, nearest.t, centres), &normal);
            let material = &tracer.scene.materials[small.material(i) as usize];
            m.add(on, material, tracer.max_depth > 0);
        }
        let v = each(|k| -ray.dir[k]);
        let (ng, ns) = facing_normals(&normal, &v);
        Self {
            lanes,
            instance: nearest.instance,
            t: nearest.t,
            point,
            normal,
            ng,
            ns,
            v,
            m,
        }
    }

    /// Lane `i`'s hit as [`World::intersect`](crate::accel::World::intersect) gives it.
    fn hit(&self, small: &SmallWorld, i: usize) -> SurfaceHit {
        let instance = self.instance.as_array()[i] as u32;
        let normal: Vec3A = lane(&self.normal, i);
        SurfaceHit {
            t: self.t.as_array()[i],
            point: lane(&self.point, i),
            geometric_normal: normal,
            shading_normal: normal,
            instance,
            material: small.material(instance as usize),
        }
    }

    /// [`lit_by`](super::lit_by) in lanes: the Lambert and Phong terms of the light sample
    /// `s` with `cos = ns · l`, for the lanes of `open`.
    #[inline(always)]
    fn lit_by(&self, s: &LightLanes<L>, cos: L, open: u32) -> V3<L> {
        let phong = self.m.phong & open;
        let specular = match phong {
            0 => [L::ZERO; 3],
            _ => self.specular(&s.towards, phong),
        };
        let (irradiance, diffuse) = (&s.irradiance, &self.m.diffuse);
        each(|k| irradiance[k] * (diffuse[k] * cos + specular[k]))
    }

    /// `m.specular * phong(reflect(-l, ns) · v, p)` for the lanes of `phong`, zero for the
    /// others (as [`lit_by`](super::lit_by) skips it for a material without specular).
    #[inline(always)]
    fn specular(&self, towards: &V3<L>, phong_lanes: u32) -> V3<L> {
        // [`reflect`](super::reflect)`(-l, ns)`: `d - n (2 (d · n))`.
        let d = each(|k| -towards[k]);
        let twice = L::splat(2.0) * dot(&d, &self.ns);
        let r: V3<L> = each(|k| d[k] - self.ns[k] * twice);
        let r_dot_v = dot(&r, &self.v).to_array();
        let exponent = self.m.exponent.to_array();
        let lobe = L::new(std::array::from_fn(|i| {
            if phong_lanes & (1 << i) != 0 {
                phong(r_dot_v[i], exponent[i])
            } else {
                0.0
            }
        }));
        let on = L::lane_mask(phong_lanes);
        each(|k| on.bitselect(self.m.specular[k] * lobe, L::ZERO))
    }
}

/// The materials of a packet's hits, in lanes; the flags are lane bits.
#[derive(Default)]
struct Materials<L: Lanes> {
    ambient: V3<L>,
    diffuse: V3<L>,
    specular: V3<L>,
    exponent: L,
    /// [`Material::lit`].
    lit: u32,
    /// Specular not zero: the Phong lobe is computed.
    phong: u32,
    /// [`Material::reflective`] where the tracer casts reflection rays at all.
    reflective: u32,
}

impl<L: Lanes> Materials<L> {
    /// Material `m` for the lanes of `on`.
    #[inline(always)]
    fn add(&mut self, on: L, m: &Material, reflections: bool) {
        self.ambient = select(on, &splat(m.ambient), &self.ambient);
        self.diffuse = select(on, &splat(m.diffuse), &self.diffuse);
        self.specular = select(on, &splat(m.specular), &self.specular);
        self.exponent = on.bitselect(L::splat(m.phong_exponent), self.exponent);
        let bits = on.to_bitmask();
        let flag = |yes: bool| if yes { bits } else { 0 };
        self.lit |= flag(m.lit());
        self.phong |= flag(m.specular != Vec3::ZERO);
        self.reflective |= flag(reflections && m.reflective());
    }
}

/// [`Light::sample`] in lanes, and the shadow ray it asks for.
struct LightLanes<L: Lanes> {
    towards: V3<L>,
    /// `None` for a directional light (infinitely far).
    distance: Option<L>,
    irradiance: V3<L>,
    /// The lanes the light can light (not sitting on a point light).
    ok: L,
}

impl<L: Lanes> LightLanes<L> {
    #[inline(always)]
    fn sample(light: &Light, point: &V3<L>) -> Self {
        match *light {
            Light::Point { position, power } => {
                let p = position.to_array();
                let d: V3<L> = each(|k| L::splat(p[k]) - point[k]);
                let d2 = dot(&d, &d);
                let ok = d2.simd_gt(L::ZERO) & d2.is_finite();
                let dist = d2.sqrt();
                Self {
                    towards: each(|k| d[k] / dist),
                    distance: Some(dist),
                    irradiance: each(|k| L::splat(power[k]) / d2),
                    ok,
                }
            }
            Light::Directional {
                towards,
                irradiance,
            } => Self {
                towards: splat(towards.into()),
                distance: None,
                irradiance: splat(irradiance),
                ok: L::lane_mask(u32::MAX),
            },
        }
    }

    /// [`shadow_ray`](super::shadow_ray)'s ray: from [`SurfaceHit::spawn_point`] towards
    /// the light, as far as the light (and no farther than its distance past the hit point).
    #[inline(always)]
    fn shadow_ray(&self, ray: &RayPacket<L>, h: &Hits<L>) -> RayPacket<L> {
        let origin = spawn_point(&h.point, &h.normal, &self.towards);
        let t_max = match self.distance {
            None => L::splat(f32::INFINITY),
            Some(distance) => {
                let back: V3<L> = each(|k| h.point[k] - origin[k]);
                let t = dot(&back, &self.towards) + distance;
                distance.is_finite().bitselect(t, L::splat(f32::INFINITY))
            }
        };
        RayPacket {
            origin,
            dir: self.towards,
            time: ray.time,
            t_max,
        }
    }
}

/// [`SurfaceHit::spawn_point`] in lanes: the point pushed off the surface along the normal
/// `n` (as the instance faces), towards `dir`'s side, by `1e-5 (1 + max |p_k|)`.
#[inline(always)]
fn spawn_point<L: Lanes>(point: &V3<L>, n: &V3<L>, dir: &V3<L>) -> V3<L> {
    let a = each(|k| point[k].abs());
    // glam's `max_element`: `maxps(maxps(x, y), z)`.
    let largest = a[0].fast_max(a[1]).fast_max(a[2]);
    let eps = L::splat(1e-5) * (L::ONE + largest);
    let side = dot(dir, n)
        .simd_ge(L::ZERO)
        .bitselect(L::ONE, L::splat(-1.0));
    let step = eps * side;
    each(|k| point[k] + n[k] * step)
}

/// [`facing_normals`](super::facing_normals) in lanes (the hit's geometric and shading
/// normals are both `n`).
#[inline(always)]
fn facing_normals<L: Lanes>(n: &V3<L>, v: &V3<L>) -> (V3<L>, V3<L>) {
    let zero = n[0].simd_eq(L::ZERO) & n[1].simd_eq(L::ZERO) & n[2].simd_eq(L::ZERO);
    let finite = n[0].is_finite() & n[1].is_finite() & n[2].is_finite();
    let bad = zero | (finite ^ L::lane_mask(u32::MAX));
    let ng = select(bad, v, n);
    let ng = flip_where(dot(&ng, v).simd_lt(L::ZERO), &ng);
    let ns = select(bad, &ng, n);
    let ns = flip_where(dot(&ns, &ng).simd_lt(L::ZERO), &ns);
    (ng, ns)
}

/// `-v` in the lanes of `m`, `v` in the others.
#[inline(always)]
fn flip_where<L: Lanes>(m: L, v: &V3<L>) -> V3<L> {
    let sign = m & L::splat(-0.0);
    each(|k| v[k] ^ sign)
}

/// `a` in the lanes of `m`, `b` in the others.
#[inline(always)]
fn select<L: Lanes>(m: L, a: &V3<L>, b: &V3<L>) -> V3<L> {
    each(|k| m.bitselect(a[k], b[k]))
}

#[inline(always)]
fn splat<L: Lanes>(v: Vec3) -> V3<L> {
    each(|k| L::splat(v[k]))
}

/// Lane `i` of `v`.
#[inline(always)]
fn lane<T: From<[f32; 3]>, L: Lanes>(v: &V3<L>, i: usize) -> T {
    T::from(v.each_ref().map(|c| c.as_array()[i]))
}

/// Set lane `i` of `v` to `x`.
#[inline(always)]
pub(super) fn set<L: Lanes>(v: &mut V3<L>, i: usize, x: Vec3) {
    for (c, x) in v.iter_mut().zip(x.to_array()) {
        c.as_mut_array()[i] = x;
    }
}

/// The lanes of `bits`, in order.
#[inline(always)]
pub(super) fn lanes(bits: u32) -> impl Iterator<Item = usize> {
    (0..LANES).filter(move |i| bits & (1 << i) != 0)
}
