//! Whitted materials (thesis Figure 13): ambient, Lambert diffuse and Phong specular colours,
//! and a Fresnel-weighted mirror reflection.

use glam::Vec3;

/// Reflectance of a mirror reflection against the angle θ between the view ray and the
/// normal: `min + (max - min)(1 - cos θ)^exponent` (the Schlick-style curve of the thesis's
/// `fresnelminimum`, `fresnelmaximum`, `fresnelexponent`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fresnel {
    pub min: f32,
    pub max: f32,
    pub exponent: f32,
}

impl Fresnel {
    /// Reflectance for `cos_theta` (clamped to [0, 1], so grazing and back-facing rays get `max`).
    #[inline]
    pub fn reflectance(&self, cos_theta: f32) -> f32 {
        let c = cos_theta.clamp(0.0, 1.0);
        // The suite's exponents are whole (5): f64 products, not libm's `powf` (`math::pow`).
        self.min + (self.max - self.min) * crate::math::pow_whole(1.0 - c, self.exponent)
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Multiplies the scene's ambient light.
    pub ambient: Vec3,
    /// Lambert reflectance under point and directional lights.
    pub diffuse: Vec3,
    /// Phong highlight colour; also tints the mirror reflection.
    pub specular: Vec3,
    pub phong_exponent: f32,
    /// Mirror reflection; `None` casts no reflection rays.
    pub fresnel: Option<Fresnel>,
}

impl Material {
    /// Whether direct light (and so a shadow ray) can change this material's colour.
    pub fn lit(&self) -> bool {
        self.diffuse != Vec3::ZERO || self.specular != Vec3::ZERO
    }

    /// Whether it casts reflection rays.
    pub fn reflective(&self) -> bool {
        self.specular != Vec3::ZERO && self.fresnel.is_some_and(|f| f.max > 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_runs_from_min_at_normal_incidence_to_max_at_grazing() {
        let f = Fresnel {
            min: 0.3,
            max: 1.0,
            exponent: 2.0,
        };
        assert_eq!(f.reflectance(1.0), 0.3);
        assert_eq!(f.reflectance(0.0), 1.0);
        // (1 - 0.5)^2 = 0.25 of the way from min to max.
        assert!((f.reflectance(0.5) - (0.3 + 0.7 * 0.25)).abs() < 1e-6);
        assert_eq!(f.reflectance(-0.2), 1.0);
    }
}
