//! Point and directional lights. A light delivers irradiance `color * intensity` (a
//! directional light) or `color * intensity / d²` (a point light at distance d); a surface
//! turns it into radiance through its Lambert and Phong terms (see [`crate::shading`]).

use glam::{Vec3, Vec3A};

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    Point {
        position: Vec3A,
        power: Vec3,
    },
    /// `towards`: unit vector from the scene towards the light (opposite to its travel).
    Directional {
        towards: Vec3A,
        irradiance: Vec3,
    },
}

/// What a light offers a point: the unit direction towards it, how far a shadow ray must
/// stay clear (in units of the returned unnormalised direction), and the irradiance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    pub towards: Vec3A,
    pub distance: f32,
    pub irradiance: Vec3,
}

impl Light {
    /// The light as seen from `point`; `None` when the point sits on a point light.
    #[inline]
    pub fn sample(&self, point: Vec3A) -> Option<LightSample> {
        match *self {
            Light::Point { position, power } => {
                let d = position - point;
                let d2 = d.length_squared();
                if !(d2 > 0.0 && d2.is_finite()) {
                    return None;
                }
                let dist = d2.sqrt();
                Some(LightSample {
                    towards: d / dist,
                    distance: dist,
                    irradiance: power / d2,
                })
            }
            Light::Directional {
                towards,
                irradiance,
            } => Some(LightSample {
                towards,
                distance: f32::INFINITY,
                irradiance,
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_light_falls_off_with_the_square_of_distance() {
        let l = Light::Point {
            position: Vec3A::new(0.0, 4.0, 0.0),
            power: Vec3::splat(32.0),
        };
        let s = l.sample(Vec3A::ZERO).unwrap();
        assert_eq!(s.irradiance, Vec3::splat(2.0));
        assert_eq!(s.towards, Vec3A::Y);
        assert_eq!(s.distance, 4.0);
        assert!(l.sample(Vec3A::new(0.0, 4.0, 0.0)).is_none());
    }
}
