//! Orbiting spheres in lanes: their centres at a packet's eight times, and one bound per
//! spinning group that tells the lanes passing far from all its spheres.
//!
//! Centres ([`Orbits::centres`], each when first asked for): each spin's rotation per lane by
//! [`Spin::at_lanes`] (the scalar path's own formula, [`Spin::at`] being it on a splat; once
//! per spin and packet that needs it), then
//! [`SpinChain::centre`]'s operations in lanes, in its order ([`Orbiter::centre`]), so a lane's
//! centre is the scalar path's to the bit. A packet's shadow and mirror rays carry its camera
//! rays' times, so they share them.
//!
//! Groups ([`Group`]): the spheres under one spin with the same chain above it (a carousel, a
//! wheel) stay within `B` of the group's head `p_0 + u_0 t` (`B` the largest `s |p_1| + R`
//! of its members, `s` the scale of `L_0 = s Q`, a sphere's own offset `p_1` still). A lane
//! whose ray passes farther than `B` from the head, or leaves it from outside, cannot hit any
//! of them, so brute force skips the whole group for a packet none of whose lanes pass near.
//! The test rounds: it culls a lane only when the computed squared distance exceeds
//! `B^2 (1 + 2^-10)^2` by `64u |o - h|^2` (each of `|o - h|^2`, `(o - h)·d` and `d·d` rounds by
//! a few `u`, and the squared distance they give is off by at most `8u |o - h|^2`); a lane
//! culled passes the spheres by at least `2^-10 B` plus the slack, far more than the sphere
//! test's own rounding, so the sphere test would have missed too: the same answers, bit for
//! bit (`accel::packet`'s tests).
//!
//! Slabs: a spin about the unit axis `a` keeps `a · p_1`, so each member's centre stays at
//! height `s a · p_1` above the head along `n = L_0 a / s` (the plane the group turns in), and
//! its sphere within `|n · (x - h)| <= H`, `H` the largest `|s a · p_1| + R` (a carousel is a
//! thin slab in a large bound). A lane that passes the bound but whose line's chord through
//! it stays outside the slab misses every member too ([`Group::beside`]): the chord's
//! midpoint, the foot of the line from the head, is at height `m = n · (o - h) - (n · d) k`
//! (`k = (o - h) · d / d · d`), and along the chord, of half length `sqrt(B^2 - D^2)`, the
//! height changes by at most `|n · d| / |d|` times that, so the lane is culled where
//! `(|m| - H)^2 d · d > (n · d)^2 (B^2 - D^2)` with `|m| > H`. Its rounding: `H` is padded by
//! `2^-10` of each member's reach (`s |p_1| + R`: the centres' and the stored `n`'s few `u`),
//! `|m|` is lowered by [`SLACK`] times `|o - h|_1 + |h|_inf` (its own rounding, of a few `u |o -
//! h|`, and the centres' absolute rounding), `|n · d|` raised by [`SLACK`]` |d|_1`, the chord
//! taken from the padded bound and the computed `D^2` as the bound test gives them (`limit -
//! D^2`, which is at least the true chord's square), and the right side grown by `2^-10`
//! against the products' rounding: a culled lane passes every member by more than the sphere
//! test's rounding, so the same answers, bit for bit.
//!
//! [`SpinChain::centre`]: super::chain::SpinChain::centre

use super::chain::{OneSpin, Spin};
use super::lanes::{Lane, Lanes, MAX_INSTANCES, RayPacket, SLACK, dot, each, mul};
use super::pose::Orbit;
use crate::simd::Kernel;
use glam::{Mat3A, Vec3A};
use std::cell::Cell;

/// Spinning groups culled together; the spheres of further groups are tested one by one.
pub(crate) const MAX_GROUPS: usize = 4;

/// Distinct spins a packet form's orbiting spheres may turn by (a world with more has none):
/// each packet works out each spin's rotation per lane.
pub(crate) const MAX_SPINS: usize = 4;

/// At most this many orbiting spheres in a packet form (as many as it has instances).
pub(crate) const MAX_ORBITS: usize = MAX_INSTANCES;

/// An orbiting sphere's chain of one spin, and the index of its spin.
#[derive(Clone, Copy, Debug)]
struct Orbiter {
    spin: u32,
    chain: OneSpin,
}

impl Orbiter {
    /// [`SpinChain::centre`](super::chain::SpinChain::centre) in lanes, with the spin's
    /// rotation per lane `r` (columns): `(p_0 + u_0 t) + L_0 (R (p_1 + u_1 t))`.
    #[inline(always)]
    fn centre<L: Lanes>(&self, r: &[[L; 3]; 3], t: L) -> [L; 3] {
        let c = &self.chain;
        let inner = moving(c.inner_offset, c.inner_velocity, t);
        let turned = each(|k| r[0][k] * inner[0] + r[1][k] * inner[1] + r[2][k] * inner[2]);
        let out = match c.forward == Mat3A::IDENTITY {
            true => turned,
            false => mul(&c.forward, turned),
        };
        let head = moving(c.offset, c.velocity, t);
        each(|k| head[k] + out[k])
    }
}

/// [`moving`](super::chain::moving) in lanes: `p + v t` (glam's `p + v * t`), `p` for a still
/// `v`.
#[inline(always)]
fn moving<L: Lanes>(p: Vec3A, v: Vec3A, t: L) -> [L; 3] {
    let p = p.to_array();
    if v == Vec3A::ZERO {
        return each(|k| L::splat(p[k]));
    }
    let v = v.to_array();
    each(|k| L::splat(p[k]) + L::splat(v[k]) * t)
}

/// Orbiting spheres under one spin and one chain above it.
#[derive(Clone, Debug)]
struct Group {
    /// The orbit every member shares above its own offset (its spin, `p_0`, `u_0`, `L_0`).
    head: OneSpin,
    /// `(B (1 + 2^-10))^2`.
    bound2: f32,
    /// `n`, the unit normal of the plane the members turn in (`L_0 a`, normalised).
    axis: [f32; 3],
    /// `H`: the members' largest `|n · L_0 p_1| + R`, each padded by `2^-10` of its reach.
    half_height: f32,
    /// The members' instance indices.
    members: Vec<u32>,
}

/// The orbiting spheres of a packet form.
#[derive(Clone, Debug, Default)]
pub(crate) struct Orbits {
    orbiters: Vec<Orbiter>,
    /// The world's distinct spins ([`Orbiter::spin`] indexes them).
    spins: Vec<Spin>,
    groups: Vec<Group>,
}

/// The orbiting spheres' centres at a packet's eight times ([`Orbits::centres`]), each worked
/// out when first asked for (with its spin's rotation per lane, also kept), so a packet none of
/// whose rays passes near a group pays neither its rotations nor its centres; and the groups'
/// heads. One per camera packet, shared by its shadow and mirror rays, and made ready for the
/// next packet by [`Centres::reset`] rather than made anew: its cells are 3.4 kB, and zeroing
/// them per packet was a `memset` of 266 M instructions in the spheres scene's frame 100 at
/// 1 spp (spin8; `git show 1615eed:docs/benchmarks/lanes.md`).
pub(crate) struct Centres<'a> {
    orbits: &'a Orbits,
    time: Lane,
    heads: [[Lane; 3]; MAX_GROUPS],
    centres: [Cell<[Lane; 3]>; MAX_ORBITS],
    rotations: [Cell<[[Lane; 3]; 3]>; MAX_SPINS],
    /// Bit `k`: `centres[k]` is worked out.
    placed: Cell<u32>,
    /// Bit `s`: `rotations[s]` is worked out.
    turned: Cell<u32>,
}

impl Centres<'_> {
    /// Ready for a packet at times `time`: its groups' heads, and no centre or rotation worked
    /// out yet (the cells keep the last packet's values, never read: `placed` and `turned` say
    /// which are this packet's).
    #[inline]
    pub(crate) fn reset(&mut self, time: Lane) {
        self.time = time;
        self.heads = self.orbits.heads(time);
        self.placed.set(0);
        self.turned.set(0);
    }

    /// Orbit `k`'s centre per lane, in the lanes `L` of the packet asking.
    #[inline(always)]
    pub(crate) fn of<L: Lanes>(&self, k: usize) -> [L; 3] {
        if self.placed.get() & (1 << k) == 0 {
            self.place::<L>(k);
        }
        let c = self.centres[k].get();
        each(|i| L::from_wide(c[i]))
    }

    /// Works out orbit `k`'s centre (and its spin's rotation if not yet) in lanes `L`, out of
    /// line (most packets need few) but in `L`'s instructions ([`Lanes::enter`]).
    #[inline(never)]
    fn place<L: Lanes>(&self, k: usize) {
        L::enter(Place(self, k));
    }
}

/// [`Centres::place`]'s work.
struct Place<'c, 'a>(&'c Centres<'a>, usize);

impl Kernel for Place<'_, '_> {
    type Output = ();
    #[inline(always)]
    fn run<L: Lanes>(self) {
        let Place(c, k) = self;
        let o = &c.orbits.orbiters[k];
        let s = o.spin as usize;
        let time = L::from_wide(c.time);
        let wide = |v: [L; 3]| [v[0].to_wide(), v[1].to_wide(), v[2].to_wide()];
        let rotation = match c.turned.get() & (1 << s) {
            0 => {
                let r = c.orbits.spins[s].at_lanes(time);
                c.rotations[s].set([wide(r[0]), wide(r[1]), wide(r[2])]);
                c.turned.set(c.turned.get() | 1 << s);
                r
            }
            _ => {
                let r = c.rotations[s].get();
                let lanes = |v: [Lane; 3]| each(|i| L::from_wide(v[i]));
                [lanes(r[0]), lanes(r[1]), lanes(r[2])]
            }
        };
        c.centres[k].set(wide(o.centre(&rotation, time)));
        c.placed.set(c.placed.get() | 1 << k);
    }
}

impl Orbits {
    pub(crate) fn new(spins: Vec<Spin>) -> Self {
        Self {
            spins,
            ..Self::default()
        }
    }

    /// Adds `orbit` (a sphere's: one spin, else `None`); its index.
    pub(crate) fn add(&mut self, orbit: &Orbit) -> Option<usize> {
        let chain = orbit.chain.single()?;
        if self.orbiters.len() == MAX_ORBITS || orbit.spins[0] as usize >= MAX_SPINS {
            return None;
        }
        self.orbiters.push(Orbiter {
            spin: orbit.spins[0],
            chain,
        });
        Some(self.orbiters.len() - 1)
    }

    /// Groups the orbiting spheres `(instance, orbit index, radius)` whose own offset is still
    /// (at most [`MAX_GROUPS`] groups); returns the instances left out of every group.
    pub(crate) fn group(&mut self, spheres: &[(u32, usize, f32)]) -> Vec<u32> {
        let mut loose = Vec::new();
        for &(instance, k, radius) in spheres {
            let c = self.orbiters[k].chain;
            let head = OneSpin {
                inner_offset: Vec3A::ZERO,
                inner_velocity: Vec3A::ZERO,
                ..c
            };
            let at = self.groups.iter().position(|g| g.head == head);
            let at = match at {
                _ if c.inner_velocity != Vec3A::ZERO => None,
                Some(g) => Some(g),
                None if self.groups.len() < MAX_GROUPS => {
                    let axis = (c.forward * Vec3A::from(c.spin.axis())).normalize();
                    self.groups.push(Group {
                        head,
                        bound2: 0.0,
                        axis: axis.to_array(),
                        half_height: 0.0,
                        members: Vec::new(),
                    });
                    Some(self.groups.len() - 1)
                }
                None => None,
            };
            let Some(g) = at else {
                loose.push(instance);
                continue;
            };
            // A sphere in centre form scales uniformly, so `L_0 = s Q` and `|L_0 R p_1| =
            // s |p_1|`, `s` any column's length (the largest: rounding).
            let f = c.forward;
            let norm = f
                .x_axis
                .length()
                .max(f.y_axis.length())
                .max(f.z_axis.length());
            let reach = norm * c.inner_offset.length() + radius;
            let group = &mut self.groups[g];
            let padded = reach * (1.0 + 1.0 / 1024.0);
            group.bound2 = group.bound2.max(padded * padded);
            let height = Vec3A::from(group.axis).dot(f * c.inner_offset).abs() + radius;
            group.half_height = group.half_height.max(height + reach / 1024.0);
            group.members.push(instance);
        }
        loose
    }

    /// The groups: each one's members (instance indices).
    pub(crate) fn groups(&self) -> impl Iterator<Item = (usize, &[u32])> {
        self.groups
            .iter()
            .enumerate()
            .map(|(g, group)| (g, group.members.as_slice()))
    }

    /// The centres at the times `time` of a packet's lanes (each when first asked for), and
    /// the groups' heads.
    #[inline]
    pub(crate) fn centres(&self, time: Lane) -> Centres<'_> {
        const ZERO: [Lane; 3] = [Lane::ZERO; 3];
        Centres {
            orbits: self,
            time,
            heads: self.heads(time),
            centres: std::array::from_fn(|_| Cell::new(ZERO)),
            rotations: std::array::from_fn(|_| Cell::new([ZERO; 3])),
            placed: Cell::new(0),
            turned: Cell::new(0),
        }
    }

    /// The groups' heads `p_0 + u_0 t` at the times `time`.
    #[inline(always)]
    fn heads(&self, time: Lane) -> [[Lane; 3]; MAX_GROUPS] {
        std::array::from_fn(|g| match self.groups.get(g) {
            Some(group) => moving(group.head.offset, group.head.velocity, time),
            None => [Lane::ZERO; 3],
        })
    }

    /// The lanes of `active` whose ray may pass near group `g`'s spheres (see the module
    /// notes); the others surely miss them all. `a` is the rays' `d · d`.
    #[inline(always)]
    pub(crate) fn near<L: Lanes>(
        &self,
        g: usize,
        ray: &RayPacket<L>,
        a: L,
        centres: &Centres,
        active: u32,
    ) -> u32 {
        if active == 0 {
            return 0;
        }
        let group = &self.groups[g];
        let head = centres.heads[g];
        let head = &each(|k| L::from_wide(head[k]));
        let oc: [L; 3] = each(|k| ray.origin[k] - head[k]);
        let cc = dot(&oc, &oc);
        let hb = dot(&oc, &ray.dir);
        let limit = L::splat(group.bound2) + L::splat(SLACK) * cc;
        let k = hb / a;
        let d2 = cc - hb * k;
        let past = d2.simd_gt(limit);
        let away = hb.simd_gt(L::ZERO) & cc.simd_gt(limit);
        let near = active & !(past | away).to_bitmask();
        if near == 0 {
            return 0;
        }
        near & !group.beside(&oc, &ray.dir, a, head, k, limit - d2)
    }
}

impl Group {
    /// The lanes whose line's chord through the bound stays outside the slab (see the module
    /// notes): `oc = o - h`, `a = d · d`, `k = oc · d / a`, `chord2 = limit - D^2` from the
    /// bound test.
    #[inline(always)]
    fn beside<L: Lanes>(
        &self,
        oc: &[L; 3],
        d: &[L; 3],
        a: L,
        head: &[L; 3],
        k: L,
        chord2: L,
    ) -> u32 {
        let n = self.axis.map(L::splat);
        let dz = dot(&n, d);
        let m = dot(&n, oc) - dz * k;
        let far = head[0]
            .abs()
            .fast_max(head[1].abs())
            .fast_max(head[2].abs());
        let slack = L::splat(SLACK);
        let margin = m.abs() - L::splat(self.half_height) - slack * (l1(oc) + far);
        let tilt = dz.abs() + slack * l1(d);
        let rise = tilt * tilt * chord2 * L::splat(1.0 + 1.0 / 1024.0);
        let clear = margin.simd_gt(L::ZERO) & (margin * margin * a).simd_gt(rise);
        clear.to_bitmask()
    }
}

/// `|v|_1`, lane by lane.
#[inline(always)]
fn l1<L: Lanes>(v: &[L; 3]) -> L {
    v[0].abs() + v[1].abs() + v[2].abs()
}
