//! A spinning motion chain compiled for evaluation per ray.
//!
//! Each layer maps its child by `x -> l + v t + Spin(w t) Q S x`. Layers that do not spin
//! compose to one affine map whose translation is linear in time, a [`Block`]
//! `x -> p + u t + L x`; a spinning layer splits the chain there. So every chain is
//!
//! ```text
//! world_from_object(t) = B_0(t) ∘ R_1(t) ∘ B_1(t) ∘ … ∘ R_n(t) ∘ B_n(t)
//! ```
//!
//! with `R_k(t)` the rotation by `|w_k| t` about the fixed unit axis `a_k`. Its inverse is
//! written down, not computed: `B^-1 y = L^-1 (y - p - u t)` with `L^-1 = S^-1 Q^T` kept from
//! the build, and `R_k^-1 = R_k^T`. Per ray and spin that is one sine and cosine and a few
//! 3x3 products, instead of evaluating every layer's quaternion, multiplying the affine maps
//! and inverting the result.

use super::instant::Pose;
use super::lanes::{Lane, Lanes};
use crate::math;
use crate::motion::{Motion, MotionLayer};
use glam::{Mat3A, Vec3, Vec3A};

/// `x -> offset + velocity t + linear x`, with `inverse = linear^-1`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Block {
    offset: Vec3A,
    velocity: Vec3A,
    linear: Mat3A,
    inverse: Mat3A,
}

impl Block {
    const IDENTITY: Block = Block {
        offset: Vec3A::ZERO,
        velocity: Vec3A::ZERO,
        linear: Mat3A::IDENTITY,
        inverse: Mat3A::IDENTITY,
    };

    /// `self ∘ (x -> offset + velocity t + linear x)`.
    fn then(self, offset: Vec3A, velocity: Vec3A, linear: Mat3A, inverse: Mat3A) -> Block {
        Block {
            offset: self.offset + self.linear * offset,
            velocity: self.velocity + self.linear * velocity,
            linear: self.linear * linear,
            inverse: inverse * self.inverse,
        }
    }
}

/// A rotation about a fixed unit axis at a constant rate (radians per second).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spin {
    axis: Vec3,
    rate: f32,
}

impl Spin {
    /// The unit axis it turns about.
    pub fn axis(&self) -> Vec3 {
        self.axis
    }

    /// The rotation at time `t`: [`Spin::at_lanes`] on a splat, the one formula of the poses,
    /// the spheres' centres and their lanes (`accel::orbits`), so that all give the same bits
    /// for the same time.
    #[inline]
    pub fn at(&self, t: f32) -> Mat3A {
        let r = self
            .at_lanes(Lane::splat(t))
            .map(|c| c.map(|x| x.as_array()[0]));
        Mat3A::from_cols_array_2d(&r)
    }

    /// The rotation at eight times, as columns in lanes: glam's `Mat3A::from_axis_angle`
    /// (Rodrigues' formula, its operations in its order) with the sine and cosine of
    /// [`math::sin_cos_lanes`] (one call for the eight lanes instead of eight libm `sincosf`:
    /// 2-3% of the spheres scene, `perf` at 5f1035d).
    #[inline(always)]
    pub fn at_lanes<L: Lanes>(&self, t: L) -> [[L; 3]; 3] {
        let (sin, cos) = math::sin_cos_lanes(L::splat(self.rate) * t);
        let [x, y, z] = self.axis.to_array();
        let [xs, ys, zs] = [L::splat(x) * sin, L::splat(y) * sin, L::splat(z) * sin];
        let omc = L::ONE - cos;
        let [xy, xz, yz] = [x * y, x * z, y * z];
        let [xy, xz, yz] = [L::splat(xy) * omc, L::splat(xz) * omc, L::splat(yz) * omc];
        let diagonal = |a: f32| L::splat(a * a) * omc + cos;
        [
            [diagonal(x), xy + zs, xz - ys],
            [xy - zs, diagonal(y), yz + xs],
            [xz + ys, yz - xs, diagonal(z)],
        ]
    }
}

/// A layer's rest orientation and scale `Q S`, and its inverse `S^-1 Q^T` (`Q` is a unit
/// quaternion's rotation, so its inverse is its transpose).
fn rest_linear(l: &MotionLayer) -> (Mat3A, Mat3A) {
    let q = Mat3A::from_quat(l.rotation);
    (
        l.linear_at_rest(),
        Mat3A::from_diagonal(l.scale.recip()) * q.transpose(),
    )
}

/// A chain with at least one spinning layer, as `B_0` and the pairs `(R_k, B_k)`.
#[derive(Clone, Debug, PartialEq)]
pub struct SpinChain {
    head: Block,
    tail: Vec<(Spin, Block)>,
}

impl SpinChain {
    /// The compiled chain; `None` when no layer spins (then the pose only translates).
    pub fn new(motion: &Motion) -> Option<Self> {
        let mut head = Block::IDENTITY;
        let mut tail: Vec<(Spin, Block)> = Vec::new();
        for l in &motion.layers {
            let (linear, inverse) = rest_linear(l);
            let (location, velocity) = (Vec3A::from(l.location), Vec3A::from(l.velocity));
            let last = tail.last_mut().map_or(&mut head, |(_, b)| b);
            // As `Quat::from_scaled_axis` (which `MotionLayer::pose` uses): a spin whose length
            // rounds to zero (|w| below ~1e-19, whose square underflows) is no spin, and would
            // otherwise give a NaN axis.
            let rate = l.angular_velocity.length();
            if rate == 0.0 {
                *last = last.then(location, velocity, linear, inverse);
            } else {
                *last = last.then(location, velocity, Mat3A::IDENTITY, Mat3A::IDENTITY);
                let spin = Spin {
                    axis: l.angular_velocity / rate,
                    rate,
                };
                let block = Block::IDENTITY.then(Vec3A::ZERO, Vec3A::ZERO, linear, inverse);
                tail.push((spin, block));
            }
        }
        (!tail.is_empty()).then_some(SpinChain { head, tail })
    }

    /// The pose at time `t`: the world position of the object's origin,
    /// `p_0 + u_0 t + L_0 R_1 (p_1 + u_1 t + L_1 R_2 (…))`, and
    /// `object_from_world = L_n^-1 R_n^T … L_1^-1 R_1^T L_0^-1`.
    ///
    /// Kept out of line (and out of the hot code's layout) so the leaf test of the traversal
    /// stays small for the fixed and translating poses ([`super::pose::PoseOverTime::at`]).
    #[cold]
    #[inline(never)]
    pub fn at(&self, t: f32) -> Pose {
        let mut translation = self.head.offset + self.head.velocity * t;
        // World-from-(current block's input) linear part, and its inverse.
        let mut forward = self.head.linear;
        let mut inverse = self.head.inverse;
        for (k, (spin, b)) in self.tail.iter().enumerate() {
            let r = spin.at(t);
            translation += forward * (r * (b.offset + b.velocity * t));
            inverse = b.inverse * (r.transpose() * inverse);
            // Matrix-vector products where they do, and no forward part after the innermost
            // spin: most chains spin once, and this halves their matrix-matrix products.
            if k + 1 < self.tail.len() {
                forward = forward * r * b.linear;
            }
        }
        Pose::new(translation, inverse)
    }

    /// The world position of the object's origin at time `t`, [`SpinChain::at`]'s translation
    /// (the same values; a still offset skips `0 t` and an identity linear part its product,
    /// which changes at most the sign of a zero) without its inverse, with the rotation of
    /// spin `k` given by `rotation(k, spin)` (which must be `spin.at(t)`: a cache may give it).
    /// For a sphere, whose pose is its centre ([`super::pose::PoseOverTime::Orbiting`]); the
    /// lanes do the same operations (`accel::orbits`).
    #[inline(never)]
    pub fn centre(&self, t: f32, mut rotation: impl FnMut(usize, &Spin) -> Mat3A) -> Vec3A {
        let mut translation = moving(self.head.offset, self.head.velocity, t);
        let mut forward = self.head.linear;
        for (k, (spin, b)) in self.tail.iter().enumerate() {
            let r = rotation(k, spin);
            let turned = r * moving(b.offset, b.velocity, t);
            translation += match forward == Mat3A::IDENTITY {
                true => turned,
                false => forward * turned,
            };
            if k + 1 < self.tail.len() {
                forward = forward * r * b.linear;
            }
        }
        translation
    }

    /// The chain's spins, outermost first.
    pub fn spins(&self) -> impl Iterator<Item = &Spin> {
        self.tail.iter().map(|(s, _)| s)
    }

    /// A chain of one spin as the lanes evaluate it: the centre at `t` is
    /// `(p_0 + u_0 t) + L_0 (R(t) (p_1 + u_1 t))` ([`SpinChain::centre`]'s operations).
    pub fn single(&self) -> Option<OneSpin> {
        match self.tail.as_slice() {
            [(spin, b)] => Some(OneSpin {
                spin: *spin,
                offset: self.head.offset,
                velocity: self.head.velocity,
                forward: self.head.linear,
                inner_offset: b.offset,
                inner_velocity: b.velocity,
            }),
            _ => None,
        }
    }
}

/// `p + v t`, or `p` for a still `v` ([`SpinChain::centre`]).
#[inline(always)]
pub fn moving(p: Vec3A, v: Vec3A, t: f32) -> Vec3A {
    match v == Vec3A::ZERO {
        true => p,
        false => p + v * t,
    }
}

/// A chain of one spin, laid out for the lanes ([`SpinChain::single`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OneSpin {
    pub spin: Spin,
    pub offset: Vec3A,
    pub velocity: Vec3A,
    pub forward: Mat3A,
    pub inner_offset: Vec3A,
    pub inner_velocity: Vec3A,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hash::HashRng;
    use glam::{Affine3A, Quat};
    use rand::Rng;

    const U: f32 = f32::EPSILON / 2.0;

    fn vec3(rng: &mut HashRng, r: f32) -> Vec3 {
        Vec3::from_array(std::array::from_fn(|_| rng.random_range(-r..r)))
    }

    /// A random layer: location within 50, velocity within 20, any rest orientation,
    /// non-uniform scale in [0.2, 3) per axis, and a spin (up to 7 rad/s) half of the time.
    fn layer(rng: &mut HashRng) -> MotionLayer {
        MotionLayer {
            location: vec3(rng, 50.0),
            velocity: vec3(rng, 20.0),
            rotation: Quat::from_scaled_axis(vec3(rng, 3.0)),
            angular_velocity: if rng.random_bool(0.5) {
                vec3(rng, 4.0)
            } else {
                Vec3::ZERO
            },
            scale: Vec3::from_array(std::array::from_fn(|_| rng.random_range(0.2..3.0))),
        }
    }

    /// Rounding scales of a chain at time `t` (s_max, s_min the largest and smallest scale of
    /// a layer):
    /// - `term`: the largest world-space term of the translation,
    ///   `Σ_k (Π_{j<k} s_max,j) (|l_k| + |v_k| |t|)`;
    /// - `inv`: a bound on the inverse's norm, `Π_k 1/s_min,k`;
    /// - `cond`: a bound on the linear part's condition number, `Π_k s_max,k / s_min,k`;
    /// - `angle`: the total spin angle `Σ_k |w_k| |t|`.
    struct Scales {
        term: f32,
        inv: f32,
        cond: f32,
        angle: f32,
    }

    fn scales(m: &Motion, t: f32) -> Scales {
        let mut s = Scales {
            term: 0.0,
            inv: 1.0,
            cond: 1.0,
            angle: 0.0,
        };
        let mut outer = 1.0;
        for l in &m.layers {
            s.term += outer * (l.location.length() + l.velocity.length() * t.abs());
            outer *= l.scale.max_element();
            s.inv /= l.scale.min_element();
            s.cond *= l.scale.max_element() / l.scale.min_element();
            s.angle += l.angular_velocity.length() * t.abs();
        }
        s
    }

    fn max_abs(m: Mat3A) -> f32 {
        m.to_cols_array().iter().fold(0.0, |a, e| a.max(e.abs()))
    }

    /// Compare the compiled pose at `t` with the layer-by-layer chain and its general inverse.
    ///
    /// Tolerances, u = 2^-24. Each side builds every rotation from the angle `|w| t` (rounded
    /// on each side in a different order: ~2u relative, so an absolute angle error of ~2u|w t|,
    /// and another few u from sin/cos and the quaternion), and multiplies at most 4 matrices
    /// and 4 translation terms (each product entry ~3 roundings). So the rotations differ by
    /// e_R = u (16 + 4 Θ) (Θ the total angle), the linear parts and their inverses relatively
    /// by ~ n e_R; the translations absolutely by e_R T (T the largest term). The general
    /// inverse of the evaluated chain adds ~10 u cond (Cramer's rule on a matrix of condition
    /// number cond), scaled by |L^-1| <= inv; a factor 2 over the sum is headroom for the
    /// constants (the largest error seen over the random cases is a third of its bound). A wrong
    /// factor order, transpose or sign gives errors of order 1.
    fn check(motion: &Motion, chain: &SpinChain, t: f32) {
        let s = scales(motion, t);
        let e_r = U * (16.0 + 4.0 * s.angle);
        let pose = chain.at(t);
        let exact = motion.world_from_object(t);
        let what = format!("{motion:?} at t = {t}");

        let err = (exact.translation - pose.translation).abs().max_element();
        assert!(
            err <= e_r * s.term.max(1.0),
            "translation off by {err}: {what}"
        );

        let exact_inverse = exact.matrix3.inverse();
        let tol = 2.0 * (4.0 * e_r + 10.0 * U * s.cond) * s.inv;
        let err = max_abs(pose.object_from_world - exact_inverse);
        assert!(err <= tol, "inverse off by {err} > {tol}: {what}");
        // The same as a map: L^-1 L = I (relative to the condition number).
        let err = max_abs(pose.object_from_world * exact.matrix3 - Mat3A::IDENTITY);
        let tol = 2.0 * (4.0 * e_r * s.cond + 10.0 * U * s.cond);
        assert!(err <= tol, "L^-1 L - I has an entry {err} > {tol}: {what}");
    }

    /// Times used for every chain: t = 0 exactly (no spin yet), small and shutter-sized
    /// times, and large ones of both signs (many turns).
    fn times(rng: &mut HashRng) -> [f32; 5] {
        [
            0.0,
            rng.random_range(-0.05..0.05),
            rng.random_range(0.0..5.0),
            rng.random_range(-13.0..13.0),
            13.0,
        ]
    }

    #[test]
    fn a_chain_without_spin_is_not_compiled() {
        let m = Motion {
            layers: vec![MotionLayer {
                velocity: Vec3::X,
                ..MotionLayer::default()
            }],
        };
        assert_eq!(SpinChain::new(&m), None);
        assert_eq!(SpinChain::new(&Motion::default()), None);
    }

    /// 2000 random chains of 1 to 4 layers (fixed seed): the compiled pose is the evaluated
    /// chain and its inverse. Chains with two or more spinning layers and spins between
    /// still layers are counted so the test cannot pass by never meeting them.
    #[test]
    fn random_chains_match_the_evaluated_chain() {
        let (mut nested, mut mixed) = (0, 0);
        for case in 0..2000u64 {
            let mut rng = HashRng::new(0xc4a1, &[case]);
            let n = rng.random_range(1..=4);
            let motion = Motion {
                layers: (0..n).map(|_| layer(&mut rng)).collect(),
            };
            let Some(chain) = SpinChain::new(&motion) else {
                assert!(motion.is_translation_only());
                continue;
            };
            let spinning = motion.layers.iter().filter(|l| !l.is_static()).count();
            nested += usize::from(chain.tail.len() >= 2);
            mixed += usize::from(chain.tail.len() < n && spinning > 0);
            for t in times(&mut rng) {
                check(&motion, &chain, t);
            }
        }
        assert!(
            nested > 300 && mixed > 300,
            "{nested} nested, {mixed} mixed"
        );
    }

    /// Hand-made cases: a carousel (spinning group, still offset, scaled template), two nested
    /// spins about different axes with strongly non-uniform scale, a zero-rate layer between
    /// spins, and a spin too small to have a direction (|w|^2 underflows; the chain must treat
    /// it as no spin, as `Quat::from_scaled_axis` does, not produce NaN).
    #[test]
    fn chosen_chains_match_the_evaluated_chain() {
        let spin = |w: Vec3, l: Vec3, s: Vec3| MotionLayer {
            location: l,
            angular_velocity: w,
            scale: s,
            rotation: Quat::from_rotation_x(0.3),
            ..MotionLayer::default()
        };
        let still = |l: Vec3, s: Vec3| spin(Vec3::ZERO, l, s);
        let chains = [
            vec![
                spin(
                    Vec3::new(0.0, 2.0, 0.0),
                    Vec3::new(0.0, 0.5, -3.0),
                    Vec3::ONE,
                ),
                still(Vec3::new(1.8, -0.12, 0.0), Vec3::ONE),
                still(Vec3::ZERO, Vec3::splat(0.28)),
            ],
            vec![
                spin(Vec3::new(0.0, 0.0, 6.0), Vec3::X, Vec3::new(0.2, 3.0, 1.0)),
                spin(Vec3::new(5.0, 1.0, 0.0), Vec3::Y, Vec3::new(2.5, 0.25, 1.0)),
            ],
            vec![
                spin(Vec3::Y, Vec3::X, Vec3::new(1.0, 2.0, 0.5)),
                still(Vec3::Z, Vec3::new(0.5, 1.0, 2.0)),
                spin(-Vec3::Z, Vec3::ZERO, Vec3::ONE),
            ],
        ];
        for layers in chains {
            let motion = Motion { layers };
            let chain = SpinChain::new(&motion).expect("spins");
            for t in [0.0, 1e-3, 0.5, -2.0, 13.0] {
                check(&motion, &chain, t);
            }
        }

        let tiny = Motion {
            layers: vec![MotionLayer {
                angular_velocity: Vec3::new(1e-30, 0.0, 0.0),
                velocity: Vec3::X,
                ..MotionLayer::default()
            }],
        };
        assert_eq!(
            tiny.world_from_object(2.0),
            Affine3A::from_translation(Vec3::X * 2.0)
        );
        assert_eq!(SpinChain::new(&tiny), None);
        let tiny_inside = Motion {
            layers: vec![tiny.layers[0], spin(Vec3::Y, Vec3::Z, Vec3::ONE)],
        };
        let chain = SpinChain::new(&tiny_inside).expect("spins");
        assert_eq!(chain.tail.len(), 1);
        check(&tiny_inside, &chain, 2.0);
    }
}
