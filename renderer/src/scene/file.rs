//! The scene file as written on disk (`blurlab-scene/1`, JSON): the thesis's seven blocks
//! (Figure 13) — materials, objects, object instances, groups, lights, one camera, one settings
//! block. These types only parse; [`super::build`] checks them and turns them into a
//! [`super::Scene`]. Field by field documentation: `docs/scene-format.md`. The thesis's own
//! block text (`.scene`) reads into the same types ([`super::block_format`]).
//!
//! Kind-specific fields (a sphere's `radius`, a model's `file`) are optional fields of one struct
//! rather than an internally tagged enum, so that every parse error keeps its full field path
//! (serde buffers tagged enums and loses it) and a misplaced field gets a precise message.

use crate::sampling::SamplingConfig;
use serde::{Deserialize, Serialize};

/// Format tag of a scene file.
pub const SCENE_FORMAT: &str = "blurlab-scene/1";

/// A whole scene file.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    pub format: String,
    /// The scene's name for people (thesis: `scenename`); ignored by the renderer. Jobs name a
    /// scene by its file stem.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Free text for people; ignored by the renderer.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    #[serde(default)]
    pub materials: Vec<MaterialDesc>,
    #[serde(default)]
    pub objects: Vec<ObjectDesc>,
    #[serde(default)]
    pub instances: Vec<InstanceDesc>,
    #[serde(default)]
    pub groups: Vec<GroupDesc>,
    #[serde(default)]
    pub lights: Vec<LightDesc>,
    pub camera: CameraDesc,
    pub settings: SettingsDesc,
}

/// Whitted material (thesis Figure 13: diffusecolor, specularcolor, ambientcolor, fresnel*).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MaterialDesc {
    pub name: String,
    /// Lambert reflectance for point and directional lights.
    #[serde(default)]
    pub diffuse: [f32; 3],
    /// Phong highlight colour; also tints mirror reflections.
    #[serde(default)]
    pub specular: [f32; 3],
    /// Multiplies the scene's ambient light.
    #[serde(default)]
    pub ambient: [f32; 3],
    #[serde(default = "default_phong")]
    pub phong_exponent: f32,
    /// Mirror reflection weighted by `min + (max - min)(1 - cos θ)^exponent`; none without it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fresnel: Option<FresnelDesc>,
}

/// Phong exponent of a material that gives none.
pub const DEFAULT_PHONG_EXPONENT: f32 = 32.0;

fn default_phong() -> f32 {
    DEFAULT_PHONG_EXPONENT
}

#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FresnelDesc {
    pub min: f32,
    pub max: f32,
    pub exponent: f32,
}

/// What an object is.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum ObjectKind {
    /// A Wavefront OBJ file (`file`).
    Model,
    /// A sphere of `radius` around the object's origin.
    Sphere,
    /// The object-space plane y = 0 (normal +y), infinite or `half_extent` = [x, z].
    Plane,
}

/// A uniform scale or one per axis.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
#[serde(
    untagged,
    expecting = "expected a positive number or an array of 3 positive numbers"
)]
pub enum Scale {
    Uniform(f32),
    PerAxis([f32; 3]),
}

/// An object block (thesis: `type model`, `modelfilename`, `scale`, `location`, `velocity`).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ObjectDesc {
    pub name: String,
    #[serde(rename = "type")]
    pub kind: ObjectKind,
    pub material: String,
    /// `model`: the OBJ file, relative to the scene file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// `sphere`: radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f32>,
    /// `plane`: half sizes along object x and z; infinite without it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub half_extent: Option<[f32; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<Scale>,
    #[serde(default)]
    pub location: [f32; 3],
    #[serde(default)]
    pub velocity: [f32; 3],
    #[serde(default)]
    pub rotation: [f32; 3],
    #[serde(default)]
    pub angular_velocity: [f32; 3],
    /// Not drawn itself; only its instances are (a template).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub hidden: bool,
}

/// A copy of an object with its own placement and velocities, sharing its geometry.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct InstanceDesc {
    pub name: String,
    /// The object copied.
    pub object: String,
    /// Another material (default: the object's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// Default: the object's scale.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<Scale>,
    #[serde(default)]
    pub location: [f32; 3],
    #[serde(default)]
    pub velocity: [f32; 3],
    #[serde(default)]
    pub rotation: [f32; 3],
    #[serde(default)]
    pub angular_velocity: [f32; 3],
}

/// Children (objects, instances, groups, by name) that move together: the group's placement is
/// applied on top of each child's own.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GroupDesc {
    pub name: String,
    pub children: Vec<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<Scale>,
    #[serde(default)]
    pub location: [f32; 3],
    #[serde(default)]
    pub velocity: [f32; 3],
    #[serde(default)]
    pub rotation: [f32; 3],
    #[serde(default)]
    pub angular_velocity: [f32; 3],
}

#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum LightKind {
    /// At `position`; irradiance falls off as 1 / distance².
    Point,
    /// From infinitely far, travelling along `direction`.
    Directional,
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LightDesc {
    #[serde(rename = "type")]
    pub kind: LightKind,
    #[serde(default = "white")]
    pub color: [f32; 3],
    #[serde(default = "one")]
    pub intensity: f32,
    /// `point`: where the light is.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<[f32; 3]>,
    /// `directional`: the direction the light travels in (`[0, -1, 0]` shines straight down).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<[f32; 3]>,
}

fn white() -> [f32; 3] {
    [1.0; 3]
}
fn one() -> f32 {
    1.0
}

/// The pinhole camera (thesis: location, locationvelocity, lookat, lookatvelocity, up,
/// upvelocity, fov). Each point is at `value + velocity * t` at scene time `t`.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    pub location: [f32; 3],
    #[serde(default)]
    pub location_velocity: [f32; 3],
    pub look_at: [f32; 3],
    #[serde(default)]
    pub look_at_velocity: [f32; 3],
    #[serde(default = "up")]
    pub up: [f32; 3],
    #[serde(default)]
    pub up_velocity: [f32; 3],
    /// Field of view across the image's shorter side, degrees.
    pub fov: f32,
}

/// The camera's up vector when none is given.
pub const DEFAULT_UP: [f32; 3] = [0.0, 1.0, 0.0];

fn up() -> [f32; 3] {
    DEFAULT_UP
}

/// The settings block (thesis: starttime, frametime, numframes, sizex, sizey,
/// ambientlightcolor, maxdepth, envmap, pointset, numsamples, timefilter).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SettingsDesc {
    /// Scene time at which frame 0's shutter opens, seconds.
    #[serde(default)]
    pub start_time: f32,
    /// Scene seconds between frames; frame i's shutter is
    /// `[start_time + i * frame_time, start_time + (i + 1) * frame_time]`.
    pub frame_time: f32,
    pub frames: u32,
    /// Playback frames per second (does not change any pixel).
    #[serde(default = "default_fps")]
    pub fps: f64,
    pub width: u32,
    pub height: u32,
    #[serde(default)]
    pub ambient_light: [f32; 3],
    /// Mirror bounces after the primary ray (0: no reflections).
    #[serde(default = "default_max_depth")]
    pub max_depth: u32,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub environment: Option<EnvironmentDesc>,
    /// Linear factor applied to radiance before clamping to [0, 1] and sRGB encoding.
    #[serde(default = "one")]
    pub exposure: f32,
    #[serde(default)]
    pub sampling: SamplingConfig,
}

/// Playback rate when a scene gives none.
pub const DEFAULT_FPS: f64 = 30.0;
/// Mirror bounces when a scene gives none.
pub const DEFAULT_MAX_DEPTH: u32 = 4;

fn default_fps() -> f64 {
    DEFAULT_FPS
}
fn default_max_depth() -> u32 {
    DEFAULT_MAX_DEPTH
}

/// A lat-long (equirectangular) environment map for rays that leave the scene.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentDesc {
    /// `.hdr` (Radiance) or `.exr`, relative to the scene file.
    pub file: String,
    #[serde(default = "one")]
    pub intensity: f32,
    /// Turns the map about +y, degrees.
    #[serde(default)]
    pub rotation: f32,
    /// What to do with negative texels (unphysical; lossy compression leaves them). Absent:
    /// clamp them to 0 while they carry at most
    /// [`crate::environment::MAX_NEGATIVE_SHARE`] of the map's energy, refuse the map above.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub negatives: Option<NegativeTexels>,
}

/// How a scene asks negative environment-map texels to be treated.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum NegativeTexels {
    /// Set them to 0 whatever energy they carry (the map gains that energy).
    Clamp,
    /// Refuse a map with any negative texel.
    Refuse,
}

crate::named!(NegativeTexels, "negative texel policy", [Clamp => "clamp", Refuse => "refuse"]);
