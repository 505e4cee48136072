//! Axis-aligned boxes, and the padding that makes obvhs's box test conservative.

use glam::Vec3A;

/// Axis-aligned bounds in object space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    pub min: Vec3A,
    pub max: Vec3A,
}

impl Bounds {
    /// The empty box (min > max), the identity of [`Bounds::union`].
    pub const EMPTY: Bounds = Bounds {
        min: Vec3A::splat(f32::INFINITY),
        max: Vec3A::splat(f32::NEG_INFINITY),
    };

    pub fn union(self, o: Bounds) -> Bounds {
        Bounds {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    pub fn include(self, p: Vec3A) -> Bounds {
        Bounds {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// Whether every coordinate is finite (an unbounded shape has no finite bounds).
    pub fn is_finite(&self) -> bool {
        self.min.is_finite() && self.max.is_finite()
    }

    /// Whether the box holds no point (min > max on some axis).
    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// Length of the diagonal (0 for an empty box).
    pub fn diagonal(&self) -> f32 {
        if self.is_empty() {
            0.0
        } else {
            (self.max - self.min).length()
        }
    }

    /// The largest absolute coordinate of the box.
    pub fn magnitude(&self) -> f32 {
        self.min.abs().max(self.max.abs()).max_element()
    }

    /// The eight corners.
    pub fn corners(&self) -> [Vec3A; 8] {
        std::array::from_fn(|i| {
            Vec3A::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            )
        })
    }

    /// Whether `p` lies in the closed box.
    pub fn contains(&self, p: Vec3A) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// The box grown so that obvhs's slab test cannot reject a ray that truly touches the
    /// original box: every face moves out by `8 u M + slack`, `u = 2^-24` the unit roundoff and
    /// `M` the box's largest absolute coordinate.
    ///
    /// Why: obvhs computes a face's parameter as `(b - o) * (1 / d)`, three roundings, so the
    /// computed entry and exit parameters are each off by at most `3u |b - o| / |d|` (to first
    /// order). A ray aimed exactly at a vertex that is a box corner has entry = exit, and those
    /// errors can turn it into a miss (measured: `docs/geometry.md`). Moving a face out
    /// by `delta` moves its parameter by `delta / |d|`, so `delta >= 3u |b - o|` suffices:
    /// `8 u M` covers ray origins with coordinates up to about `1.6 M` (rays starting in or
    /// near the object), and `slack` (callers pass a tiny fraction of the object's diagonal)
    /// covers origins up to about `slack / (3u)` away. The padding is far above one ulp of
    /// every coordinate, so `min - delta` and `max + delta` round outwards.
    pub fn padded(self, slack: f32) -> Bounds {
        if self.is_empty() || !self.is_finite() {
            return self;
        }
        // 8u = 4 f32::EPSILON (f32::EPSILON is one ulp of 1.0, twice the unit roundoff).
        let delta = 4.0 * f32::EPSILON * self.magnitude() + slack;
        Bounds {
            min: self.min - Vec3A::splat(delta),
            max: self.max + Vec3A::splat(delta),
        }
    }

    /// The same box as obvhs's type.
    pub fn to_aabb(self) -> obvhs::aabb::Aabb {
        obvhs::aabb::Aabb::new(self.min, self.max)
    }
}

/// Slack for [`Bounds::padded`] as a fraction of an object's diagonal: 2^-16 covers ray origins
/// up to about 40 diagonals away (`2^-16 / (3 * 2^-24)`); the cost is boxes larger by 1.5e-5 of
/// the object's size, nothing next to a triangle of a 100k-triangle mesh (about 1e-2 of it).
pub const SLACK_PER_DIAGONAL: f32 = 1.0 / 65536.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn padding_grows_every_face_by_more_than_an_ulp_and_keeps_empty_boxes() {
        let b = Bounds {
            min: Vec3A::new(5000.0, -1e4, 0.0),
            max: Vec3A::new(5001.0, -9999.0, 0.0),
        };
        let p = b.padded(0.0);
        assert!(p.min.cmplt(b.min).all() && p.max.cmpgt(b.max).all());
        // The z extent is 0: padded by 8u * 1e4 on each side.
        assert_eq!(p.max.z, 4.0 * f32::EPSILON * 1e4);
        assert_eq!(b.padded(0.5).max.z, 4.0 * f32::EPSILON * 1e4 + 0.5);
        assert!(Bounds::EMPTY.padded(1.0).is_empty());
        assert_eq!(b.diagonal(), 2.0f32.sqrt());
        assert_eq!(b.magnitude(), 1e4);
        assert!(b.corners().iter().all(|&c| b.contains(c)));
    }
}
