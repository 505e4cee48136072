//! Checking a parsed scene file and turning it into a [`Scene`]. Every error names the file,
//! the field path (`objects[2].velocity`) and what was expected.

use super::file::{
    CameraDesc, LightDesc, LightKind, MaterialDesc, ObjectDesc, ObjectKind, SCENE_FORMAT, Scale,
    SceneFile, SettingsDesc,
};
use super::graph::{Graph, Node};
use super::{Scene, Settings};
use crate::accel::Instance;
use crate::assets::Assets;
use crate::camera::{Camera, Moving};
use crate::environment::Environment;
use crate::geometry::{Plane, Shape, Sphere, TriangleMesh};
use crate::light::Light;
use crate::material::{Fresnel, Material};
use crate::motion::{Motion, MotionLayer};
use crate::sampling::FrameSampler;
use crate::text::SourceMap;
use anyhow::Result;
use glam::{Quat, Vec2, Vec3, Vec3A};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::limits::MAX_IMAGE_SIDE as MAX_SIZE;

/// Parse scene text; a syntax or type error names the field path where it happened
/// ([`crate::json::from_str`]: a byte-order mark is skipped, trailing text refused).
pub fn parse(text: &str, path: &Path) -> Result<SceneFile> {
    let file = crate::json::from_str(text, path, "scene file")?;
    super::magnitude::check_tiny(text)
        .map_err(|(field, what)| anyhow::anyhow!("{}: field `{field}` {what}", path.display()))?;
    Ok(file)
}

/// Errors of one file.
struct Check<'a> {
    path: &'a Path,
    /// Lines of a text scene (`.scene`), so that errors name the line and key.
    map: Option<&'a SourceMap>,
}

impl Check<'_> {
    fn err(&self, field: impl std::fmt::Display, what: impl std::fmt::Display) -> anyhow::Error {
        SourceMap::error(self.map, self.path, &field.to_string(), what)
    }

    fn finite3(&self, field: String, v: [f32; 3]) -> Result<Vec3> {
        let v = Vec3::from(v);
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.err(field, format!("is {v}; expected finite numbers")))
        }
    }

    fn colour(&self, field: String, v: [f32; 3]) -> Result<Vec3> {
        let c = self.finite3(field.clone(), v)?;
        if c.min_element() < 0.0 {
            return Err(self.err(field, format!("is {c}; expected colour values >= 0")));
        }
        Ok(c)
    }

    fn at_least(&self, field: String, v: f32, min: f32) -> Result<f32> {
        if v.is_finite() && v >= min {
            Ok(v)
        } else {
            Err(self.err(field, format!("is {v}; expected a number >= {min}")))
        }
    }

    fn within(&self, field: String, v: f32, min: f32, max: f32) -> Result<f32> {
        if v.is_finite() && (min..=max).contains(&v) {
            Ok(v)
        } else {
            Err(self.err(
                field,
                format!("is {v}; expected a number in [{min}, {max:e}]"),
            ))
        }
    }

    fn positive(&self, field: String, v: f32) -> Result<f32> {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(self.err(field, format!("is {v}; expected a number > 0")))
        }
    }

    /// A field that must (or must not) be present for this kind.
    fn presence<T>(&self, field: String, v: &Option<T>, wanted: bool, kind: &str) -> Result<()> {
        match (v.is_some(), wanted) {
            (false, true) => Err(self.err(field, format!("is missing; a {kind} needs it"))),
            (true, false) => Err(self.err(field, format!("does not apply to a {kind}"))),
            _ => Ok(()),
        }
    }

    fn scale(&self, field: String, s: Option<Scale>) -> Result<Option<Vec3>> {
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
    fn layer(&self, at: &str, p: Placement) -> Result<MotionLayer> {
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

    fn name_list<'n>(names: impl Iterator<Item = &'n str>) -> String {
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
struct Placement {
    location: [f32; 3],
    velocity: [f32; 3],
    rotation: [f32; 3],
    angular_velocity: [f32; 3],
    scale: Option<Vec3>,
}

/// Check `f` (read from `path`) and load what it names.
pub fn build(f: SceneFile, path: &Path) -> Result<Scene> {
    build_mapped(f, path, None)
}

/// [`build`], with errors located by `map` (the lines of a text scene).
pub fn build_mapped(f: SceneFile, path: &Path, map: Option<&SourceMap>) -> Result<Scene> {
    build_with(f, path, map, &Assets::default())
}

/// [`build_mapped`], reading the files `assets` names from the user's copies
/// ([`crate::assets`]).
pub fn build_with(
    f: SceneFile,
    path: &Path,
    map: Option<&SourceMap>,
    assets: &Assets,
) -> Result<Scene> {
    let c = Check { path, map };
    if f.format != SCENE_FORMAT {
        return Err(c.err(
            "format",
            format!("is {:?}; this version reads {SCENE_FORMAT:?}", f.format),
        ));
    }
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    // The sky's map is read while the rest is built: decoding it is most of a thesis scene's
    // load (0.03 of 0.05 s for the plane), which no thread could share with the frames. With
    // one rayon thread the two run in turn. The errors keep their order: the rest's first.
    let (sky, scene) = rayon::join(
        || read_sky(&f, &dir, assets),
        || build_without_sky(&c, &f, &dir),
    );
    let mut scene = scene?;
    // `read_sky` read a map exactly where the settings name one.
    if let (Some(e), Some(sky)) = (&f.settings.environment, sky) {
        // Checked here, not before the map is read, so that its error keeps its place; the map
        // was made with the same value.
        c.at_least("settings.environment.intensity".into(), e.intensity, 0.0)?;
        if !e.rotation.is_finite() {
            return Err(c.err(
                "settings.environment.rotation",
                "is not a finite number of degrees",
            ));
        }
        let (env, warning) =
            sky.map_err(|err| c.err("settings.environment.file", format!("{err:#}")))?;
        scene.warnings.extend(warning);
        scene.environment = Some(Arc::new(env));
    }
    Ok(scene)
}

/// The environment map the settings name, read with the raw fields (checked by the caller).
fn read_sky(
    f: &SceneFile,
    dir: &Path,
    assets: &Assets,
) -> Option<Result<(Environment, Option<String>)>> {
    let e = f.settings.environment.as_ref()?;
    let file = assets.resolve(dir, Path::new(&e.file));
    Some(Environment::load(
        &file,
        e.intensity,
        e.rotation,
        e.negatives,
    ))
}

/// Everything of the scene but its environment map (`environment` None, no warnings).
fn build_without_sky(c: &Check, f: &SceneFile, dir: &Path) -> Result<Scene> {
    let materials = materials(c, &f.materials)?;
    let material_index: HashMap<&str, u32> = f
        .materials
        .iter()
        .enumerate()
        .map(|(i, m)| (m.name.as_str(), i as u32))
        .collect();
    let find_material = |field: String, name: &str| -> Result<u32> {
        material_index.get(name).copied().ok_or_else(|| {
            c.err(
                field,
                format!(
                    "names material `{name}`, which is not defined (materials: {})",
                    Check::name_list(f.materials.iter().map(|m| m.name.as_str()))
                ),
            )
        })
    };
    let nodes = node_names(c, f)?;
    let graph = Graph::new(&f.groups, |n| nodes.get(n).copied())
        .map_err(|(field, what)| c.err(field, what))?;
    let group_layers = f
        .groups
        .iter()
        .enumerate()
        .map(|(i, g)| {
            let at = format!("groups[{i}]");
            let scale = c.scale(format!("{at}.scale"), g.scale)?;
            c.layer(
                &at,
                Placement {
                    location: g.location,
                    velocity: g.velocity,
                    rotation: g.rotation,
                    angular_velocity: g.angular_velocity,
                    scale,
                },
            )
        })
        .collect::<Result<Vec<_>>>()?;
    let motion = |name: &str, own: MotionLayer| Motion {
        layers: graph
            .chain(name)
            .into_iter()
            .map(|g| group_layers[g])
            .chain(std::iter::once(own))
            .collect(),
    };

    let mut meshes = MeshCache::default();
    let mut shapes = Vec::new();
    let mut instances = Vec::new();
    for (i, o) in f.objects.iter().enumerate() {
        let at = format!("objects[{i}]");
        let shape = object_shape(c, &at, o, dir, &mut meshes)?;
        let scale = c.scale(format!("{at}.scale"), o.scale)?;
        let material = find_material(format!("{at}.material"), &o.material)?;
        let own = c.layer(
            &at,
            Placement {
                location: o.location,
                velocity: o.velocity,
                rotation: o.rotation,
                angular_velocity: o.angular_velocity,
                scale,
            },
        )?;
        if !o.hidden {
            instances.push(Instance {
                shape: shape.clone(),
                motion: motion(&o.name, own),
                material,
            });
        }
        shapes.push((shape, material, scale));
    }
    for (i, d) in f.instances.iter().enumerate() {
        let at = format!("instances[{i}]");
        let Some(o) = f.objects.iter().position(|o| o.name == d.object) else {
            return Err(c.err(
                format!("{at}.object"),
                format!(
                    "names object `{}`, which is not defined (objects: {})",
                    d.object,
                    Check::name_list(f.objects.iter().map(|o| o.name.as_str()))
                ),
            ));
        };
        let (shape, object_material, object_scale) = &shapes[o];
        let material = match &d.material {
            Some(m) => find_material(format!("{at}.material"), m)?,
            None => *object_material,
        };
        let scale = c.scale(format!("{at}.scale"), d.scale)?.or(*object_scale);
        let own = c.layer(
            &at,
            Placement {
                location: d.location,
                velocity: d.velocity,
                rotation: d.rotation,
                angular_velocity: d.angular_velocity,
                scale,
            },
        )?;
        instances.push(Instance {
            shape: shape.clone(),
            motion: motion(&d.name, own),
            material,
        });
    }
    let lights = f
        .lights
        .iter()
        .enumerate()
        .map(|(i, l)| light(c, &format!("lights[{i}]"), l))
        .collect::<Result<Vec<_>>>()?;
    let settings = settings(c, &f.settings)?;
    // After the fields with their own range (Phong exponent, sizes), which name it first;
    // before the camera's frames are checked (a frame_time of 3e38 is named as such) and the
    // environment map is read.
    super::magnitude::check(f).map_err(|(field, what)| c.err(field, what))?;
    let camera = camera(c, &f.camera, &settings)?;
    Ok(Scene {
        path: c.path.to_path_buf(),
        materials,
        instances,
        lights,
        camera,
        environment: None,
        settings,
        warnings: Vec::new(),
    })
}

/// The largest Phong exponent a scene may ask for. `(r·v)^p` falls to 1/e at
/// `r·v = 1 - 1/p`; above ~1.7e7 that is less than one f32 step below 1 (6e-8), so the
/// highlight is a single representable value and the exponent has no meaning left. 1e6 keeps
/// the lobe at least ~17 steps wide; sharper highlights are mirrors (`fresnel`).
pub const MAX_PHONG_EXPONENT: f32 = 1e6;

fn materials(c: &Check, list: &[MaterialDesc]) -> Result<Vec<Material>> {
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

/// Every object, instance and group name, checked to be unique and non-empty.
fn node_names<'f>(c: &Check, f: &'f SceneFile) -> Result<HashMap<&'f str, Node>> {
    let mut nodes: HashMap<&str, (Node, String)> = HashMap::new();
    let all = f
        .objects
        .iter()
        .enumerate()
        .map(|(i, o)| {
            (
                format!("objects[{i}]"),
                o.name.as_str(),
                Node::Object { hidden: o.hidden },
            )
        })
        .chain(
            f.instances
                .iter()
                .enumerate()
                .map(|(i, d)| (format!("instances[{i}]"), d.name.as_str(), Node::Instance)),
        )
        .chain(
            f.groups
                .iter()
                .enumerate()
                .map(|(i, g)| (format!("groups[{i}]"), g.name.as_str(), Node::Group)),
        );
    for (at, name, node) in all {
        if name.is_empty() {
            return Err(c.err(format!("{at}.name"), "is empty; expected a name"));
        }
        if let Some((_, other)) = nodes.get(name) {
            return Err(c.err(
                format!("{at}.name"),
                format!(
                    "repeats `{name}` (already {other}); objects, instances and groups share \
                     one set of names"
                ),
            ));
        }
        nodes.insert(name, (node, at));
    }
    Ok(nodes.into_iter().map(|(k, (n, _))| (k, n)).collect())
}

/// Meshes already loaded, by resolved path: objects naming the same file share one mesh.
#[derive(Default)]
struct MeshCache {
    loaded: HashMap<PathBuf, Arc<TriangleMesh>>,
}

fn object_shape(
    c: &Check,
    at: &str,
    o: &ObjectDesc,
    dir: &Path,
    meshes: &mut MeshCache,
) -> Result<Shape> {
    let kind = match o.kind {
        ObjectKind::Model => "model",
        ObjectKind::Sphere => "sphere",
        ObjectKind::Plane => "plane",
    };
    let f = |name: &str| format!("{at}.{name}");
    c.presence(f("file"), &o.file, o.kind == ObjectKind::Model, kind)?;
    c.presence(f("radius"), &o.radius, o.kind == ObjectKind::Sphere, kind)?;
    if o.kind != ObjectKind::Plane {
        c.presence(f("half_extent"), &o.half_extent, false, kind)?;
    }
    Ok(match o.kind {
        ObjectKind::Model => {
            let file = dir.join(o.file.as_deref().unwrap_or_default());
            let mesh = match meshes.loaded.get(&file) {
                Some(m) => m.clone(),
                None => {
                    let m = Arc::new(
                        TriangleMesh::from_obj(&file)
                            .map_err(|e| c.err(f("file"), e.to_string()))?,
                    );
                    meshes.loaded.insert(file, m.clone());
                    m
                }
            };
            Shape::Mesh(mesh)
        }
        ObjectKind::Sphere => Shape::Sphere(Sphere {
            radius: c.positive(f("radius"), o.radius.unwrap_or_default())?,
        }),
        ObjectKind::Plane => Shape::Plane(Plane {
            half_extent: match o.half_extent {
                None => None,
                Some([x, z]) => Some(Vec2::new(
                    c.positive(f("half_extent[0]"), x)?,
                    c.positive(f("half_extent[1]"), z)?,
                )),
            },
        }),
    })
}

fn light(c: &Check, at: &str, l: &LightDesc) -> Result<Light> {
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

fn settings(c: &Check, s: &SettingsDesc) -> Result<Settings> {
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

fn camera(c: &Check, d: &CameraDesc, s: &Settings) -> Result<Camera> {
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
