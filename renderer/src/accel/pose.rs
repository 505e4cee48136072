//! Where an instance is at a ray's time, in the form rays need: the map from world to object
//! space (thesis Chapter III, "Transform Nodes in Scene Graph": rays move, geometry does not).
//!
//! Three kinds, decided once per world build, so an object pays only for the motion it has:
//! fixed (the pose is computed once; no per-ray motion work), translating (one multiply-add per
//! ray), spinning (per ray, one rotation per spinning layer and the inverse written down:
//! [`SpinChain`]). A zero-velocity instance is fixed, so it takes exactly the code path of an
//! instance without motion.
//!
//! A sphere whose chain scales uniformly is the same sphere however it is turned: its pose is
//! only its centre ([`PoseOverTime::centred`]; the world gives it its world radius), so rays
//! meet it in world space, moved by the centre alone ([`Pose::centred`]: no matrix), and a
//! spinning one needs only the chain's translation ([`SpinChain::centre`], no inverse), with
//! the rotation of each spin shared by every instance it turns ([`Spins`], [`PoseCache`]).

use super::chain::{Spin, SpinChain};
use super::instant::Pose;
use crate::motion::Motion;
use glam::{Mat3A, Vec3A};
use std::cell::Cell;

/// How an instance's pose depends on time.
#[derive(Clone, Debug, PartialEq)]
pub enum PoseOverTime {
    Fixed(Pose),
    /// Pose at scene time 0, and the world velocity of the object's origin.
    Translating {
        at_zero: Pose,
        velocity: Vec3A,
    },
    /// Boxed: the chain is larger than the other variants, and the poses are read per ray.
    Spinning(Box<SpinChain>),
    /// A sphere's spinning chain in centre form: the pose is [`Pose::centred`] at
    /// [`SpinChain::centre`] ([`PoseOverTime::centred`]).
    Orbiting(Box<Orbit>),
}

/// A spinning sphere's chain, and the world's index ([`Spins`]) of each of its spins, under
/// which a [`PoseCache`] keeps the spin's rotation for every instance it turns.
#[derive(Clone, Debug, PartialEq)]
pub struct Orbit {
    pub chain: SpinChain,
    pub spins: Vec<u32>,
}

/// The distinct spins of a world's orbiting spheres (a group's spin is every member's).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Spins(Vec<Spin>);

impl Spins {
    /// The index of `spin`, added if new.
    fn index(&mut self, spin: &Spin) -> u32 {
        let at = self.0.iter().position(|s| s == spin).unwrap_or_else(|| {
            self.0.push(*spin);
            self.0.len() - 1
        });
        at as u32
    }

    pub fn len(&self) -> usize {
        self.0.len()
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Spin `i`.
    pub fn get(&self, i: u32) -> &Spin {
        &self.0[i as usize]
    }
}

impl PoseOverTime {
    pub fn new(motion: &Motion) -> Self {
        let at_zero = Pose::from_world_from_object(motion.world_from_object(0.0));
        if motion.is_static() {
            PoseOverTime::Fixed(at_zero)
        } else {
            match SpinChain::new(motion) {
                Some(chain) => PoseOverTime::Spinning(Box::new(chain)),
                None => PoseOverTime::Translating {
                    at_zero,
                    velocity: motion.linear_velocity(),
                },
            }
        }
    }

    /// The pose of a sphere whose chain scales uniformly (`Motion::uniform_scale`), in centre
    /// form: its centre only ([`Pose::centred`]), fixed, translating or orbiting as the chain
    /// moves; the sphere's radius must be scaled by the chain's scale. A sphere is the same
    /// whatever its orientation, so rays meet it in world space: the same roots as through the
    /// full inverse to rounding (the bytes of a turned or spinning sphere's image change at
    /// that level: `docs/geometry.md`, "Spheres from their centre"), for less work. Each spin
    /// gets its index in `spins`.
    pub fn centred(motion: &Motion, spins: &mut Spins) -> Self {
        let at_zero = Pose::centred(motion.world_from_object(0.0).translation);
        if motion.is_static() {
            return PoseOverTime::Fixed(at_zero);
        }
        match SpinChain::new(motion) {
            Some(chain) => {
                let spins = chain.spins().map(|s| spins.index(s)).collect();
                PoseOverTime::Orbiting(Box::new(Orbit { chain, spins }))
            }
            None => PoseOverTime::Translating {
                at_zero,
                velocity: motion.linear_velocity(),
            },
        }
    }

    /// Always inlined, so fixed and translating poses stay in registers in the traversal's
    /// leaf test (with the chain inlined too, LLVM made this whole function a call returning
    /// the pose through memory, callgrind showed); the spinning case is a call to
    /// [`SpinChain::at`], whose own work dwarfs the call.
    #[inline(always)]
    pub fn at(&self, t: f32) -> Pose {
        match self {
            PoseOverTime::Fixed(p) => *p,
            PoseOverTime::Translating { at_zero, velocity } => Pose {
                translation: at_zero.translation + *velocity * t,
                ..*at_zero
            },
            PoseOverTime::Spinning(chain) => chain.at(t),
            PoseOverTime::Orbiting(orbit) => Pose::centred(orbit.chain.centre(t, |_, s| s.at(t))),
        }
    }

    pub fn is_fixed(&self) -> bool {
        matches!(self, PoseOverTime::Fixed(_))
    }
}

/// The last pose of each spinning instance and the ray time it was computed for, so that the
/// rays of one camera sample (its primary, shadow and mirror rays share its time) compute a
/// spinning pose once: [`SpinChain::at`] (a rotation per spinning layer, a sine and cosine
/// each) was 14% of the thesis's spheres scene (perf, frame 100). An orbiting sphere's centre
/// takes its rotations from the last rotation of each of the world's [`Spins`], so the
/// spheres of one spinning group share one sine and cosine per time. A pure function of the time's
/// bits, so a cached pose or rotation is the one computed again, to the bit. One per thread's
/// piece of work (a [`crate::shading::Tracer`]); empty, it caches nothing.
#[derive(Debug, Default)]
pub struct PoseCache {
    slots: Vec<Cell<Option<(u32, Pose)>>>,
    rotations: Vec<Cell<Option<(u32, Mat3A)>>>,
}

/// `slot`'s value when it holds time `t`, else `make()`, kept.
#[inline(always)]
fn cached<T: Copy>(slot: Option<&Cell<Option<(u32, T)>>>, t: f32, make: impl FnOnce() -> T) -> T {
    let Some(slot) = slot else {
        return make();
    };
    match slot.get() {
        Some((bits, v)) if bits == t.to_bits() => v,
        _ => {
            let v = make();
            slot.set(Some((t.to_bits(), v)));
            v
        }
    }
}

impl PoseCache {
    /// A cache for a world of `instances` instances and `spins` distinct orbiting spins.
    pub fn new(instances: usize, spins: usize) -> Self {
        Self {
            slots: vec![Cell::new(None); instances],
            rotations: vec![Cell::new(None); spins],
        }
    }

    /// `pose.at(t)` for instance `instance`, from the cache when it holds that instance at
    /// that very time.
    #[inline(always)]
    pub fn at(&self, instance: u32, pose: &PoseOverTime, t: f32) -> Pose {
        let slot = self.slots.get(instance as usize);
        match pose {
            PoseOverTime::Spinning(chain) => cached(slot, t, || chain.at(t)),
            PoseOverTime::Orbiting(orbit) => cached(slot, t, || {
                let rotation = |k: usize, s: &Spin| self.rotation(orbit.spins[k], s, t);
                Pose::centred(orbit.chain.centre(t, rotation))
            }),
            _ => pose.at(t),
        }
    }

    /// `spin.at(t)` for the world's spin `index`, from the cache when it holds that time.
    #[inline]
    pub fn rotation(&self, index: u32, spin: &Spin, t: f32) -> Mat3A {
        cached(self.rotations.get(index as usize), t, || spin.at(t))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Ray;
    use crate::motion::MotionLayer;
    use glam::{Quat, Vec3};

    fn layer(location: [f32; 3], velocity: [f32; 3]) -> MotionLayer {
        MotionLayer {
            location: Vec3::from(location),
            velocity: Vec3::from(velocity),
            rotation: Quat::from_rotation_y(0.7),
            scale: Vec3::new(2.0, 3.0, 0.5),
            ..MotionLayer::default()
        }
    }

    #[test]
    fn translating_chains_match_the_evaluated_chain() {
        let m = Motion {
            layers: vec![
                layer([10.0, 0.0, -3.0], [1.0, 2.0, 0.0]),
                layer([1.0, 1.0, 1.0], [0.0, 0.0, -4.0]),
            ],
        };
        let pose = PoseOverTime::new(&m);
        assert!(matches!(pose, PoseOverTime::Translating { .. }));
        for t in [-12.5f32, 0.0, 0.3, 7.0] {
            let exact = Pose::from_world_from_object(m.world_from_object(t));
            let fast = pose.at(t);
            // Both compute ~10 products of O(10) terms: a few ulps of 50.
            assert!((exact.translation - fast.translation).abs().max_element() < 1e-4);
            assert_eq!(exact.object_from_world, fast.object_from_world);
        }
    }

    #[test]
    fn cached_poses_are_the_computed_ones() {
        let spin = Motion {
            layers: vec![MotionLayer {
                angular_velocity: Vec3::new(0.3, 2.0, -1.0),
                ..layer([1.0, 2.0, 3.0], [0.5, 0.0, 0.0])
            }],
        };
        let poses = [PoseOverTime::new(&spin), PoseOverTime::new(&spin)];
        let cache = PoseCache::new(1, 0);
        // Instance 1 has no slot: computed every time.
        for (i, t) in [
            (0, 0.25f32),
            (0, 0.25),
            (1, 0.25),
            (0, 0.5),
            (0, -0.0),
            (0, 0.0),
        ] {
            assert_eq!(
                cache.at(i, &poses[i as usize], t),
                poses[0].at(t),
                "{i} at {t}"
            );
        }
        // -0.0 and 0.0 are distinct keys, and 0.25 again after 0.5 is recomputed.
        assert_eq!(cache.at(0, &poses[0], 0.25), poses[0].at(0.25));
        assert_ne!(poses[0].at(0.25), poses[0].at(0.5));
    }

    #[test]
    fn zero_velocity_is_fixed_and_identical_to_no_motion() {
        let still = Motion {
            layers: vec![layer([5000.0, 1.0, 2.0], [0.0; 3])],
        };
        let p = PoseOverTime::new(&still);
        assert!(p.is_fixed());
        assert_eq!(p.at(3.0), p.at(-1.0));
        let spin = Motion {
            layers: vec![MotionLayer {
                angular_velocity: Vec3::Y,
                ..layer([0.0; 3], [0.0; 3])
            }],
        };
        assert!(matches!(
            PoseOverTime::new(&spin),
            PoseOverTime::Spinning(_)
        ));
    }

    #[test]
    fn rays_and_normals_map_consistently() {
        let m = Motion {
            layers: vec![layer([1.0, 2.0, 3.0], [0.0; 3])],
        };
        let pose = PoseOverTime::new(&m).at(0.0);
        let w = m.world_from_object(0.0);
        let r = Ray::new(Vec3A::new(4.0, -1.0, 2.0), Vec3A::new(0.3, 0.2, -1.0), 0.0);
        let local = pose.ray_to_object(&r);
        // A point at parameter t maps to the object-space point at the same t.
        let back = w.transform_point3a(local.at(2.5));
        assert!((back - r.at(2.5)).abs().max_element() < 1e-5);
        // Normals stay perpendicular to transformed tangents.
        let (tangent, normal) = (Vec3A::X, Vec3A::Y);
        let wt = w.transform_vector3a(tangent);
        assert!(pose.normal_to_world(normal).dot(wt).abs() < 1e-5);
    }
}
