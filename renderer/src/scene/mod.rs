//! A loaded, validated scene (`blurlab-scene/1`): what the render loop needs — instances ready
//! for [`crate::accel::World::build`], materials, lights, camera, environment map, settings.
//! `docs/scene-format.md` describes the file; [`file`] parses it, [`build`] checks it.

pub mod build;
pub mod file;
pub mod graph;
pub mod model;

pub use file::{SCENE_FORMAT, SceneFile};

use crate::accel::Instance;
use crate::camera::Camera;
use crate::environment::Environment;
use crate::light::Light;
use crate::material::Material;
use crate::sampling::SamplingConfig;
use anyhow::{Context, Result};
use glam::Vec3;
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
    /// Read and check a scene file; models and maps resolve against its folder.
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read scene {}", path.display()))?;
        Self::from_json(&text, path)
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
}
