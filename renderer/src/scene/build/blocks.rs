//! The scene's blocks other than its objects: materials, lights, settings and camera, each
//! checked field by field into what the renderer draws with.

use super::check::Check;
use crate::camera::{Camera, Moving};
use crate::light::Light;
use crate::limits::MAX_IMAGE_SIDE as MAX_SIZE;
use crate::material::{Fresnel, Material};
use crate::sampling::FrameSampler;
use crate::scene::Settings;
use crate::scene::file::{CameraDesc, LightDesc, LightKind, MaterialDesc, SettingsDesc};
use anyhow::Result;
use glam::Vec3A;
use std::collections::HashMap;

/// The largest Phong exponent a scene may ask for. `(r·v)^p` falls to 1/e at
/// `r·v = 1 - 1/p`; above ~1.7e7 that is less than one f32 step below 1 (6e-8), so the
/// highlight is a single representable value and the exponent has no meaning left. 1e6 keeps
/// the lobe at least ~17 steps wide; sharper highlights are mirrors (`fresnel`).
pub const MAX_PHONG_EXPONENT: f32 = 1e6;

pub(super) fn materials(c: &Check, list: &[MaterialDesc]) -> Result<Vec<Material>> {
    let mut seen = HashMap::new();
    list.iter()
        .enumerate()
        .map(|(i, m)| {
            let at = format!("materials[{i}]");
            if let Some(j) = seen.insert(m.name.as_str(), i) {
                return Err(c.err(
                    format!("{at}.name"),
                    format!("repeats `{}` (already materials[{j}])", m.name),
                ));
            }
            let fresnel = match m.fresnel {
                None => None,
                Some(fr) => {
                    let ok = |v: f32| v.is_finite() && (0.0..=1.0).contains(&v);
                    if !(ok(fr.min) && ok(fr.max) && fr.min <= fr.max) {
                        return Err(c.err(
                            format!("{at}.fresnel"),
                            format!(
                                "has min {} and max {}; expected 0 <= min <= max <= 1",
                                fr.min, fr.max
                            ),
                        ));
                    }
                    Some(Fresnel {
                        min: fr.min,
                        max: fr.max,
                        exponent: c.at_least(format!("{at}.fresnel.exponent"), fr.exponent, 0.0)?,
                    })
                }
            };
            Ok(Material {
                ambient: c.colour(format!("{at}.ambient"), m.ambient)?,
                diffuse: c.colour(format!("{at}.diffuse"), m.diffuse)?,
                specular: c.colour(format!("{at}.specular"), m.specular)?,
                phong_exponent: c.within(
                    format!("{at}.phong_exponent"),
                    m.phong_exponent,
                    0.0,
                    MAX_PHONG_EXPONENT,
                )?,
                fresnel,
            })
        })
        .collect()
}

pub(super) fn light(c: &Check, at: &str, l: &LightDesc) -> Result<Light> {
    let f = |name: &str| format!("{at}.{name}");
    let colour = c.colour(f("color"), l.color)?;
    let power = colour * c.at_least(f("intensity"), l.intensity, 0.0)?;
    Ok(match l.kind {
        LightKind::Point => {
            c.presence(f("position"), &l.position, true, "point light")?;
            c.presence(f("direction"), &l.direction, false, "point light")?;
            Light::Point {
                position: Vec3A::from(c.finite3(f("position"), l.position.unwrap_or_default())?),
                power,
            }
        }
        LightKind::Directional => {
            c.presence(f("direction"), &l.direction, true, "directional light")?;
            c.presence(f("position"), &l.position, false, "directional light")?;
            let d = c.finite3(f("direction"), l.direction.unwrap_or_default())?;
            let towards = Vec3A::from(-d)
                .try_normalize()
                .ok_or_else(|| c.err(f("direction"), "is the zero vector; expected a direction"))?;
            Light::Directional {
                towards,
                irradiance: power,
            }
        }
    })
}

pub(super) fn settings(c: &Check, s: &SettingsDesc) -> Result<Settings> {
    let f = |name: &str| format!("settings.{name}");
    if !s.start_time.is_finite() {
        return Err(c.err(f("start_time"), "is not a finite number of seconds"));
    }
    c.positive(f("frame_time"), s.frame_time)?;
    for (name, v) in [("width", s.width), ("height", s.height)] {
        if v == 0 || v > MAX_SIZE {
            return Err(c.err(f(name), format!("is {v}; expected 1 to {MAX_SIZE} pixels")));
        }
    }
    if s.frames == 0 {
        return Err(c.err(f("frames"), "is 0; expected at least 1 frame"));
    }
    if !(s.fps.is_finite() && s.fps > 0.0) {
        return Err(c.err(f("fps"), format!("is {}; expected a number > 0", s.fps)));
    }
    if s.max_depth > 64 {
        return Err(c.err(
            f("max_depth"),
            format!("is {}; expected at most 64 bounces", s.max_depth),
        ));
    }
    FrameSampler::new(&s.sampling, 0, 0).map_err(|e| c.err(f("sampling"), format!("{e:#}")))?;
    Ok(Settings {
        start_time: s.start_time as f64,
        frame_time: s.frame_time as f64,
        frames: s.frames,
        fps: s.fps,
        width: s.width,
        height: s.height,
        ambient_light: c.colour(f("ambient_light"), s.ambient_light)?,
        max_depth: s.max_depth,
        exposure: c.positive(f("exposure"), s.exposure)?,
        sampling: s.sampling.clone(),
    })
}

pub(super) fn camera(c: &Check, d: &CameraDesc, s: &Settings) -> Result<Camera> {
    let moving = |name: &str, p: [f32; 3], v_name: &str, v: [f32; 3]| -> Result<Moving> {
        Ok(Moving {
            at_zero: c.finite3(format!("camera.{name}"), p)?,
            velocity: c.finite3(format!("camera.{v_name}"), v)?,
        })
    };
    if !(d.fov.is_finite() && d.fov > 0.0 && d.fov < 180.0) {
        return Err(c.err(
            "camera.fov",
            format!("is {}; expected degrees between 0 and 180", d.fov),
        ));
    }
    let location = moving(
        "location",
        d.location,
        "location_velocity",
        d.location_velocity,
    )?;
    let look_at = moving("look_at", d.look_at, "look_at_velocity", d.look_at_velocity)?;
    let up = moving("up", d.up, "up_velocity", d.up_velocity)?;
    let bad = || {
        c.err(
            "camera",
            "has no view direction at some frame: `look_at` meets `location` or `up` is \
             parallel to the view; expected distinct points and an up vector across the view",
        )
    };
    let cam = Camera::new(location, look_at, up, d.fov).ok_or_else(bad)?;
    // A moving camera must have a frame at every shutter boundary of the animation.
    for frame in 0..=s.frames {
        let t = s.shutter(frame.min(s.frames - 1));
        let t = if frame == s.frames { t.1 } else { t.0 };
        cam.frame_at(t).ok_or_else(bad)?;
    }
    Ok(cam)
}
