//! [`Environment::radiance`] for [`LANES`] directions at once: the lookups of the camera rays
//! that leave the scene, eight at a time.
//!
//! Why: in the thesis's plane scene nearly every camera ray sees the sky, and one lookup at a
//! time cost more than the mesh it misses (`perf`, `sample_cost` frame 93: the bilinear
//! filter 18%, its square root, division, floors, column wrap and twelve products one lane at
//! a time). Here the direction's length and angle cosine, `atan2` and `acos`
//! ([`crate::math`]'s polynomials, which the scalar lookup uses too), the texel coordinates,
//! the floors, the weights and the three interpolations run in lanes; only the four texel
//! loads stay per lane.
//!
//! Bit identity with [`Environment::radiance`]: each lane does its f32 operations in its
//! order (the length is glam's SSE2 `sqrt((x x + y y) + z z)`, [`dot`]; `Vec3::lerp` is
//! `a (1 - s) + b s`; Rust never fuses a multiply-add), the same [`crate::math`] functions
//! (the scalar lookup runs their lane form on one value), and the floor of [`super::floor`]
//! (the same value for every f32, tested). The tests compare both over many directions,
//! degenerate ones included.

use super::{Environment, PI, wrap_column};
#[cfg(test)]
use crate::accel::lanes::Lane;
use crate::accel::lanes::{LANES, Lanes, dot, each};
use crate::math;

/// A vector per lane.
type V3<L> = [L; 3];

impl Environment {
    /// [`Environment::radiance`] of lane `i`'s direction `d` for each lane `i` whose bit is set
    /// in `live`; zero in the others.
    #[inline(always)]
    pub fn radiance_lanes<L: Lanes>(&self, d: &V3<L>, live: u32) -> V3<L> {
        let (c, s) = (L::splat(self.turn.0), L::splat(self.turn.1));
        // Undo the map's turn about +y.
        let x = d[0] * c - d[2] * s;
        let z = d[0] * s + d[2] * c;
        let len = dot(d, d).sqrt();
        let defined = (len.simd_gt(L::ZERO) & len.is_finite()).to_bitmask();
        let live = live & defined;
        // Where `len` is positive and finite every component is finite: no NaN to clamp.
        let cos = (d[1] / len).fast_max(-L::ONE).fast_min(L::ONE);
        // The other lanes' angles are 0, so their weights stay finite and their zero texels
        // interpolate to zero.
        let keep = L::lane_mask(live);
        let azimuth = keep.bitselect(math::atan2_lanes(x, -z), L::ZERO);
        let polar = keep.bitselect(math::acos_lanes(cos), L::ZERO);
        let u = azimuth * L::splat(0.5 / PI) + L::splat(0.5);
        let v = polar * L::splat(1.0 / PI);
        let rgb = self.bilinear_lanes(u, v, live);
        each(|k| rgb[k] * L::splat(self.intensity))
    }

    /// [`Environment::bilinear`] in lanes, for the lanes of `live` (zero in the others).
    #[inline(always)]
    fn bilinear_lanes<L: Lanes>(&self, u: L, v: L, live: u32) -> V3<L> {
        let (w, h) = (self.width as f32, self.height as f32);
        let fx = u * L::splat(w) - L::splat(0.5);
        let fy = (v * L::splat(h) - L::splat(0.5))
            .fast_max(L::ZERO)
            .fast_min(L::splat((self.height - 1) as f32));
        let (x0, y0) = (floor(fx), floor(fy));
        let (ax, ay) = (fx - x0, fy - y0);
        let texels = self.corner_texels(&x0.to_array(), &y0.to_array(), live);
        let [t00, t01, t10, t11] = &texels;
        let top = lerp(t00, t01, ax);
        let bottom = lerp(t10, t11, ax);
        lerp(&top, &bottom, ay)
    }

    /// The four texels around each live lane's point (columns `x0`, `x0 + 1` wrapped around,
    /// rows `y0`, `y0 + 1` clamped): top left, top right, bottom left, bottom right, per
    /// channel in lanes; zero in the other lanes.
    #[inline(always)]
    fn corner_texels<L: Lanes>(
        &self,
        x0: &[f32; LANES],
        y0: &[f32; LANES],
        live: u32,
    ) -> [V3<L>; 4] {
        let mut at = [[0usize; LANES]; 4];
        let col = |x: i64| wrap_column(x, self.width);
        for i in (0..LANES).filter(|i| live & (1 << i) != 0) {
            let (c0, c1) = (col(x0[i] as i64), col(x0[i] as i64 + 1));
            let r0 = y0[i] as usize;
            let r1 = (r0 + 1).min(self.height - 1);
            for (k, (r, c)) in [(r0, c0), (r0, c1), (r1, c0), (r1, c1)]
                .into_iter()
                .enumerate()
            {
                at[k][i] = r * self.width + c;
            }
        }
        self.texels.gather(&at, live)
    }
}

/// [`super::floor`] in lanes: truncation through an integer below 2^23 in magnitude (one
/// less where it rounded up, the sign of a zero kept), the value itself above (every f32
/// there is an integer already; infinity and NaN stay what they are).
#[inline(always)]
fn floor<L: Lanes>(x: L) -> L {
    let t = x.trunc_through_int();
    let t = t.simd_gt(x).bitselect(t - L::ONE, t);
    let t = t.simd_eq(L::ZERO).bitselect(x * L::ZERO, t);
    x.abs().simd_lt(L::splat(8_388_608.0)).bitselect(t, x)
}

/// `Vec3::lerp` lane by lane: `a (1 - s) + b s`.
#[inline(always)]
fn lerp<L: Lanes>(a: &V3<L>, b: &V3<L>, s: L) -> V3<L> {
    each(|k| a[k] * (L::ONE - s) + b[k] * s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hash::{hash, unit_f32};
    use glam::{Vec3, Vec3A};

    /// 64 x 32 maps of distinct texels, turned by 30 degrees, intensity 1.5: any floats (kept
    /// as floats), and the 8-bit mantissas of a Radiance map (packed).
    fn maps() -> [Environment; 2] {
        let (w, h) = (64, 32);
        let texels = |packed: bool| {
            (0..w * h)
                .map(|i| {
                    let f = |k: u64| unit_f32(hash(9, &[i as u64, k])) * 10.0;
                    let v = Vec3::new(f(0), f(1), f(2));
                    match packed {
                        false => v,
                        true => (v * 16.0).floor() / 16.0,
                    }
                })
                .collect()
        };
        [false, true].map(|packed| {
            let env = Environment::new(w, h, texels(packed), 1.5, 30.0).0;
            assert_eq!(
                matches!(env.texels, super::super::Texels::Packed(_)),
                packed
            );
            env
        })
    }

    /// Directions of every kind: random ones of any length, the poles, the seam (u = 0 and 1,
    /// where the column wraps), the axes, zero, infinite and NaN.
    fn directions() -> Vec<Vec3A> {
        let mut d = vec![
            Vec3A::Y,
            Vec3A::NEG_Y,
            Vec3A::Z,
            Vec3A::NEG_Z,
            Vec3A::X,
            Vec3A::NEG_X,
            Vec3A::new(-0.0, 1.0, -0.0),
            Vec3A::new(0.0, 0.0, 1e-30),
            Vec3A::new(-1e-30, 0.5, 1.0),
            Vec3A::new(1e-30, 0.5, 1.0),
            Vec3A::ZERO,
            Vec3A::new(f32::INFINITY, 0.0, 1.0),
            Vec3A::new(0.0, f32::NAN, 1.0),
            Vec3A::splat(1e30),
            Vec3A::splat(1e-30),
        ];
        for i in 0..20_000u64 {
            let c = |k: u64| unit_f32(hash(10, &[i, k])) * 2.0 - 1.0;
            let scale = 10f32.powf(c(3) * 3.0);
            d.push(Vec3A::new(c(0), c(1), c(2)) * scale);
        }
        d
    }

    #[test]
    fn lanes_are_the_scalar_lookup_to_the_bit() {
        let dirs = directions();
        for env in maps() {
            lookups_in_lanes_are_scalar_lookups(&env, &dirs);
        }
    }

    fn lookups_in_lanes_are_scalar_lookups(env: &Environment, dirs: &[Vec3A]) {
        for (n, group) in dirs.chunks(LANES).enumerate() {
            let axis = |k: usize| Lane::new(std::array::from_fn(|i| group[i % group.len()][k]));
            // Every other group leaves a lane out, which must come back zero.
            let live = if n % 2 == 0 { 0xff } else { 0xfe };
            let out = env.radiance_lanes(&[axis(0), axis(1), axis(2)], live);
            for i in 0..LANES {
                let d = group[i % group.len()];
                let expected = if live & (1 << i) != 0 {
                    env.radiance(d)
                } else {
                    Vec3::ZERO
                };
                let got = Vec3::new(
                    out[0].as_array()[i],
                    out[1].as_array()[i],
                    out[2].as_array()[i],
                );
                assert_eq!(
                    got.to_array().map(f32::to_bits),
                    expected.to_array().map(f32::to_bits),
                    "direction {d}: {got} against {expected}"
                );
            }
        }
    }

    #[test]
    fn floor_in_lanes_is_the_scalar_floor_to_the_bit() {
        let mut values = vec![0.0f32, -0.0, 0.5, -0.5, -1.0, 8_388_607.5, -8_388_607.5];
        values.extend([
            8_388_608.0,
            1e30,
            -1e30,
            f32::INFINITY,
            f32::NEG_INFINITY,
            1e-45,
        ]);
        for i in 0..40_000u64 {
            values.push(f32::from_bits(hash(11, &[i]) as u32));
            values.push(unit_f32(hash(12, &[i])) * 4096.0 - 2048.0);
        }
        for group in values.chunks(LANES) {
            let x = Lane::new(std::array::from_fn(|i| group[i % group.len()]));
            for (i, got) in floor(x).to_array().into_iter().enumerate() {
                let want = super::super::floor(group[i % group.len()]);
                assert!(
                    got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
                    "floor({:e}): {got:e} against {want:e}",
                    group[i % group.len()]
                );
            }
        }
    }
}
