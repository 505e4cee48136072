//! The errors of one scene file, each naming its field path and what was expected, and the
//! checks of the values every block shares (finite vectors, colours, ranges, scales, a
//! placement's motion layer).

use crate::motion::MotionLayer;
use crate::scene::file::Scale;
use crate::text::SourceMap;
use anyhow::Result;
use glam::{Quat, Vec3};
use std::path::Path;

/// Errors of one file.
pub(super) struct Check<'a> {
    pub(super) path: &'a Path,
    /// Lines of a text scene (`.scene`), so that errors name the line and key.
    pub(super) map: Option<&'a SourceMap>,
}

impl Check<'_> {
    pub(super) fn err(
        &self,
        field: impl std::fmt::Display,
        what: impl std::fmt::Display,
    ) -> anyhow::Error {
        SourceMap::error(self.map, self.path, &field.to_string(), what)
    }

    pub(super) fn finite3(&self, field: String, v: [f32; 3]) -> Result<Vec3> {
        let v = Vec3::from(v);
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.err(field, format!("is {v}; expected finite numbers")))
        }
    }

    pub(super) fn colour(&self, field: String, v: [f32; 3]) -> Result<Vec3> {
        let c = self.finite3(field.clone(), v)?;
        if c.min_element() < 0.0 {
            return Err(self.err(field, format!("is {c}; expected colour values >= 0")));
        }
        Ok(c)
    }

    pub(super) fn at_least(&self, field: String, v: f32, min: f32) -> Result<f32> {
        if v.is_finite() && v >= min {
            Ok(v)
        } else {
            Err(self.err(field, format!("is {v}; expected a number >= {min}")))
        }
    }

    pub(super) fn within(&self, field: String, v: f32, min: f32, max: f32) -> Result<f32> {
        if v.is_finite() && (min..=max).contains(&v) {
            Ok(v)
        } else {
            Err(self.err(
                field,
                format!("is {v}; expected a number in [{min}, {max:e}]"),
            ))
        }
    }

    pub(super) fn positive(&self, field: String, v: f32) -> Result<f32> {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(self.err(field, format!("is {v}; expected a number > 0")))
        }
    }

    /// A field that must (or must not) be present for this kind.
    pub(super) fn presence<T>(
        &self,
        field: String,
        v: &Option<T>,
        wanted: bool,
        kind: &str,
    ) -> Result<()> {
        match (v.is_some(), wanted) {
            (false, true) => Err(self.err(field, format!("is missing; a {kind} needs it"))),
            (true, false) => Err(self.err(field, format!("does not apply to a {kind}"))),
            _ => Ok(()),
        }
    }

    pub(super) fn scale(&self, field: String, s: Option<Scale>) -> Result<Option<Vec3>> {
        let v = match s {
            None => return Ok(None),
            Some(Scale::Uniform(k)) => Vec3::splat(k),
            Some(Scale::PerAxis(v)) => Vec3::from(v),
        };
        if v.is_finite() && v.min_element() > 0.0 {
            Ok(Some(v))
        } else {
            Err(self.err(field, format!("is {v}; expected positive scale factors")))
        }
    }

    /// One motion layer from a block's placement fields.
    pub(super) fn layer(&self, at: &str, p: Placement) -> Result<MotionLayer> {
        let f = |name: &str| format!("{at}.{name}");
        let rot = self.finite3(f("rotation"), p.rotation)?;
        let spin = self.finite3(f("angular_velocity"), p.angular_velocity)?;
        Ok(MotionLayer {
            location: self.finite3(f("location"), p.location)?,
            velocity: self.finite3(f("velocity"), p.velocity)?,
            rotation: Quat::from_rotation_z(rot.z.to_radians())
                * Quat::from_rotation_y(rot.y.to_radians())
                * Quat::from_rotation_x(rot.x.to_radians()),
            angular_velocity: spin * std::f32::consts::PI / 180.0,
            scale: p.scale.unwrap_or(Vec3::ONE),
        })
    }

    pub(super) fn name_list<'n>(names: impl Iterator<Item = &'n str>) -> String {
        let v: Vec<String> = names.map(|n| format!("`{n}`")).collect();
        if v.is_empty() {
            "none defined".into()
        } else {
            v.join(", ")
        }
    }
}

/// The placement fields every object, instance and group carries.
#[derive(Clone, Copy)]
pub(super) struct Placement {
    pub(super) location: [f32; 3],
    pub(super) velocity: [f32; 3],
    pub(super) rotation: [f32; 3],
    pub(super) angular_velocity: [f32; 3],
    pub(super) scale: Option<Vec3>,
}
