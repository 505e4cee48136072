//! A loaded, validated scene (`blurlab-scene/1`): what the render loop needs — instances ready
//! for [`crate::accel::World::build`], materials, lights, camera, environment map, settings.
//! `docs/scene-format.md` describes the file; [`file`] parses it, [`build`] checks it (models
//! load through [`crate::geometry::TriangleMesh::from_obj`]). The thesis's own block text
//! (Figure 13, `.scene`) reads into the same file model ([`block_format`],
//! `docs/thesis-formats.md`).

pub mod block_format;
pub mod build;
pub mod file;
pub mod graph;
mod magnitude;

pub use file::{SCENE_FORMAT, SceneFile};

use crate::accel::Instance;
use crate::assets::Assets;
use crate::camera::{Camera, Moving};
use crate::environment::Environment;
use crate::light::Light;
use crate::material::Material;
use crate::motion::MotionLayer;
use crate::sampling::SamplingConfig;
use anyhow::Result;
use glam::{Quat, Vec3};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The settings block, checked.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    pub start_time: f64,
    pub frame_time: f64,
    pub frames: u32,
    pub fps: f64,
    pub width: u32,
    pub height: u32,
    pub ambient_light: Vec3,
    /// Mirror bounces after the primary ray.
    pub max_depth: u32,
    pub exposure: f32,
    pub sampling: SamplingConfig,
}

impl Settings {
    /// Scene-time interval during which frame `frame`'s shutter is open:
    /// `[start + frame * frame_time, start + (frame + 1) * frame_time]`.
    pub fn shutter(&self, frame: u32) -> (f32, f32) {
        let t0 = self.start_time + frame as f64 * self.frame_time;
        (t0 as f32, (t0 + self.frame_time) as f32)
    }
}

/// Everything the renderer draws.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The file it came from (for messages).
    pub path: PathBuf,
    pub materials: Vec<Material>,
    /// One per drawn object and instance, with its whole motion chain.
    pub instances: Vec<Instance>,
    pub lights: Vec<Light>,
    pub camera: Camera,
    pub environment: Option<Arc<Environment>>,
    pub settings: Settings,
    /// Problems that did not stop loading (repaired environment texels), one line each.
    pub warnings: Vec<String>,
}

impl Scene {
    /// Read and check a scene file, JSON or (by the extension `.scene`) the thesis's block
    /// text; models and maps resolve against its folder.
    pub fn load(path: &Path) -> Result<Self> {
        Self::load_with(path, &Assets::default())
    }

    /// [`Scene::load`], with the files `assets` names read from the user's copies.
    pub fn load_with(path: &Path, assets: &Assets) -> Result<Self> {
        let text = crate::utf8::read(path, "scene file")?;
        Self::from_text_with(&text, path, assets)
    }

    /// Parse and check scene text read from `path`, JSON or (by the extension `.scene`) the
    /// thesis's block text, with the files `assets` names read from the user's copies.
    pub fn from_text_with(text: &str, path: &Path, assets: &Assets) -> Result<Self> {
        if block_format::is_block_scene(path) {
            let (file, map) = block_format::read(text, path)?;
            build::build_with(file, path, Some(&map), assets)
        } else {
            build::build_with(build::parse(text, path)?, path, None, assets)
        }
    }

    /// Parse and check scene text in the thesis's block format as if read from `path`; errors
    /// name its lines and keys.
    pub fn from_block_text(text: &str, path: &Path) -> Result<Self> {
        let (file, map) = block_format::read(text, path)?;
        build::build_mapped(file, path, Some(&map))
    }

    /// Parse and check scene text as if read from `path`.
    pub fn from_json(text: &str, path: &Path) -> Result<Self> {
        build::build(build::parse(text, path)?, path)
    }

    /// Whether any material casts reflection rays.
    pub fn has_reflections(&self) -> bool {
        self.settings.max_depth > 0 && self.materials.iter().any(Material::reflective)
    }

    /// Whether anything moves (objects or camera).
    pub fn has_motion(&self) -> bool {
        self.camera.is_moving() || self.instances.iter().any(|i| !i.motion.is_static())
    }

    /// The same scene held still where it is at scene time `t`: every velocity and angular
    /// velocity zero, every pose and the camera as they are at `t`. What motion costs is the
    /// difference between rendering a frame of this scene and of the frozen one at the frame's
    /// mid-shutter time (the same picture without the blur).
    pub fn frozen_at(&self, t: f32) -> Self {
        let mut s = self.clone();
        for inst in &mut s.instances {
            for layer in &mut inst.motion.layers {
                *layer = MotionLayer {
                    location: layer.location + layer.velocity * t,
                    velocity: Vec3::ZERO,
                    rotation: Quat::from_scaled_axis(layer.angular_velocity * t) * layer.rotation,
                    angular_velocity: Vec3::ZERO,
                    scale: layer.scale,
                };
            }
        }
        let c = &self.camera;
        let still = |m: Moving| Moving::still(Vec3::from(m.at(t)));
        s.camera = Camera::new(
            still(c.location),
            still(c.look_at),
            still(c.up),
            c.fov_degrees,
        )
        .unwrap_or_else(|| c.clone());
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frozen_scene_stands_where_the_moving_one_was() {
        let text = r#"{
            "format": "blurlab-scene/1",
            "materials": [{"name": "m"}],
            "objects": [{"name": "b", "type": "sphere", "radius": 1, "material": "m",
                         "velocity": [1, 2, 0], "angular_velocity": [0, 45, 0]}],
            "groups": [{"name": "g", "children": ["b"], "angular_velocity": [10, 0, 0],
                        "velocity": [0, 0, -3]}],
            "camera": {"location": [0, 0, 9], "location_velocity": [1, 0, 0],
                       "look_at": [0, 0, 0], "fov": 40},
            "settings": {"frame_time": 0.1, "frames": 3, "width": 8, "height": 8}
        }"#;
        let scene = Scene::from_json(text, Path::new("s.json")).unwrap();
        assert!(scene.has_motion());
        let t = 1.7;
        let frozen = scene.frozen_at(t);
        assert!(!frozen.has_motion());
        let a = scene.instances[0].motion.world_from_object(t);
        let b = frozen.instances[0].motion.world_from_object(-5.0);
        assert!(a.abs_diff_eq(b, 1e-5), "{a:?} vs {b:?}");
        let (ca, cb) = (scene.camera.frame_at(t), frozen.camera.frame_at(0.0));
        assert_eq!(ca.unwrap().eye, cb.unwrap().eye);
    }

    #[test]
    fn the_sampling_block_reads_the_randomization_and_refuses_unknown_ones() {
        let text = |r: &str| {
            format!(
                r#"{{"format": "blurlab-scene/1", "materials": [{{"name": "m"}}],
                "objects": [{{"name": "b", "type": "sphere", "radius": 1, "material": "m"}}],
                "camera": {{"location": [0, 0, 9], "look_at": [0, 0, 0], "fov": 40}},
                "settings": {{"frame_time": 0.1, "frames": 3, "width": 8, "height": 8,
                              "sampling": {{"point_set": "sobol", "randomization": "{r}"}}}}}}"#
            )
        };
        let scene = Scene::from_json(&text("scramble"), Path::new("s.json")).unwrap();
        assert_eq!(
            scene.settings.sampling.randomization(),
            crate::sampling::Randomization::Scramble
        );
        let e = format!(
            "{:#}",
            Scene::from_json(&text("owen"), Path::new("s.json")).unwrap_err()
        );
        assert!(
            e.contains("s.json") && e.contains("randomization") && e.contains("scramble"),
            "{e}"
        );
    }
}
