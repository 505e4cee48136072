//! Reading a `.scene` file into a [`SceneFile`], with the [`SourceMap`] that lets the scene's
//! checks name lines and keys.

use super::BLOCKS;
use crate::environment::NegativeTexels;
use crate::sampling::SamplingConfig;
use crate::scene::SCENE_FORMAT;
use crate::scene::file::{
    CameraDesc, DEFAULT_FPS, DEFAULT_MAX_DEPTH, DEFAULT_PHONG_EXPONENT, DEFAULT_UP,
    EnvironmentDesc, FresnelDesc, GroupDesc, InstanceDesc, LightDesc, LightKind, MaterialDesc,
    ObjectDesc, ObjectKind, Scale, SceneFile, SettingsDesc,
};
use crate::text::sampling::{self as options, Host};
use crate::text::{self, Entries, Entry, SourceMap, at_line, names};
use anyhow::Result;
use std::path::Path;

/// One `keyword ... end` block.
struct Block {
    kind: &'static str,
    line: usize,
    entries: Vec<Entry>,
}

/// Read scene text as if from `path` (for messages).
pub fn read(text: &str, path: &Path) -> Result<(SceneFile, SourceMap)> {
    let mut map = SourceMap::default();
    let mut materials = Vec::new();
    let mut objects = Vec::new();
    let mut instances = Vec::new();
    let mut groups = Vec::new();
    let mut lights = Vec::new();
    let mut camera: Option<(CameraDesc, usize)> = None;
    let mut settings: Option<(Settings, usize)> = None;
    for b in blocks(text, path)? {
        let one_of = |first: Option<usize>| match first {
            Some(l) => Err(at_line(
                path,
                b.line,
                format!(
                    "a second `{}` block (the first is on line {l}); a scene has exactly one",
                    b.kind
                ),
            )),
            None => Ok(()),
        };
        let prefix = match b.kind {
            "material" => format!("materials[{}]", materials.len()),
            "object" => format!("objects[{}]", objects.len()),
            "objectinstance" => format!("instances[{}]", instances.len()),
            "group" => format!("groups[{}]", groups.len()),
            "light" => format!("lights[{}]", lights.len()),
            "camera" => "camera".into(),
            _ => String::new(), // settings: its keys fill `settings.*`, `name` and `description`
        };
        let block_field = if prefix.is_empty() {
            "settings"
        } else {
            &prefix
        };
        map.add(block_field, Some(b.line), format!("block `{}`", b.kind));
        let context = format!("block `{}` (line {})", b.kind, b.line);
        let mut e = Entries::new(path, context, b.line, &prefix, b.entries, &[], &mut map)?;
        match b.kind {
            "material" => materials.push(material(&mut e)?),
            "object" => objects.push(object(&mut e, objects.len())?),
            "objectinstance" => instances.push(instance(&mut e, instances.len())?),
            "group" => groups.push(group(&mut e, groups.len())?),
            "light" => lights.push(light(&mut e)?),
            "camera" => {
                one_of(camera.as_ref().map(|c| c.1))?;
                camera = Some((camera_block(&mut e)?, b.line));
            }
            _ => {
                one_of(settings.as_ref().map(|s| s.1))?;
                settings = Some((settings_block(&mut e)?, b.line));
            }
        }
        e.finish()?;
    }
    let missing = |kind: &str| {
        anyhow::anyhow!(
            "{}: no `{kind}` block; a scene has exactly one (`{kind}` ... `end`, thesis Figure 13)",
            path.display()
        )
    };
    let (camera, _) = camera.ok_or_else(|| missing("camera"))?;
    let (s, _) = settings.ok_or_else(|| missing("settings"))?;
    Ok((
        SceneFile {
            format: SCENE_FORMAT.into(),
            name: s.name,
            description: s.description,
            materials,
            objects,
            instances,
            groups,
            lights,
            camera,
            settings: s.desc,
        },
        map,
    ))
}

/// The file's blocks, in order.
fn blocks(text: &str, path: &Path) -> Result<Vec<Block>> {
    let mut out = Vec::new();
    let mut open: Option<Block> = None;
    let keywords = BLOCKS.join(", ");
    for l in text::lines(text, path)? {
        let first = l.words[0].as_str();
        let alone = l.words.len() == 1;
        let keyword = BLOCKS.iter().find(|b| **b == first).copied();
        let err = |what: String| Err(at_line(path, l.number, what));
        match (open.as_mut(), keyword) {
            (None, Some(kind)) if alone => {
                open = Some(Block {
                    kind,
                    line: l.number,
                    entries: Vec::new(),
                })
            }
            (None, Some(kind)) => {
                return err(format!(
                    "block keyword `{kind}` stands alone on its line; found `{}`",
                    l.words.join(" ")
                ));
            }
            (None, None) if first == "end" => return err("`end` without an open block".into()),
            (None, None) => {
                return err(format!(
                    "`{first}` outside a block; expected a block keyword ({keywords}) on its \
                     own line, then its keys, then `end`"
                ));
            }
            (Some(_), _) if first == "end" && alone => out.extend(open.take()),
            (Some(_), _) if first == "end" => {
                return err(format!(
                    "`end` stands alone on its line; found `{}`",
                    l.words.join(" ")
                ));
            }
            (Some(b), Some(kind)) if alone => {
                return err(format!(
                    "block `{}` opened on line {} is not closed by `end` before block `{kind}`",
                    b.kind, b.line
                ));
            }
            (Some(b), _) => b.entries.push(Entry::of(&l)),
        }
    }
    if let Some(b) = open {
        return Err(at_line(
            path,
            b.line,
            format!(
                "block `{}` is not closed by `end` before the end of the file",
                b.kind
            ),
        ));
    }
    Ok(out)
}

/// A name given by `key`, or `<stem><n>` (n counts the blocks of the kind from 1) when the block gives none: Figure 13's
/// object has no name, and names matter only to instances and groups that refer to it.
fn name_or_derived(e: &mut Entries, key: &'static str, stem: &str, index: usize) -> Result<String> {
    Ok(match e.word(key, "name")? {
        Some(n) => n,
        None => {
            let n = format!("{stem}{}", index + 1);
            e.note("name", format!("the block (no `{key}`: named `{n}`)"));
            n
        }
    })
}

fn material(e: &mut Entries) -> Result<MaterialDesc> {
    let name = e.word("materialname", "name")?;
    let name = e.require(name, "materialname", "<name>")?;
    let diffuse = e.colour("diffusecolor", "diffuse")?.unwrap_or_default();
    let specular = e.colour("specularcolor", "specular")?.unwrap_or_default();
    let ambient = e.colour("ambientcolor", "ambient")?.unwrap_or_default();
    let phong_exponent = e
        .f32("phongexponent", "phong_exponent")?
        .unwrap_or(DEFAULT_PHONG_EXPONENT);
    let keys = ["fresnelminimum", "fresnelmaximum", "fresnelexponent"];
    let min = e.f32(keys[0], "fresnel.min")?;
    let max = e.f32(keys[1], "fresnel.max")?;
    let exponent = e.f32(keys[2], "fresnel.exponent")?;
    let fresnel = match (min, max, exponent) {
        (None, None, None) => None,
        (Some(min), Some(max), Some(exponent)) => Some(FresnelDesc { min, max, exponent }),
        given => {
            let absent: Vec<String> = [given.0.is_none(), given.1.is_none(), given.2.is_none()]
                .iter()
                .zip(keys)
                .filter(|(a, _)| **a)
                .map(|(_, k)| format!("`{k}`"))
                .collect();
            return Err(e.block_error(format!(
                "lacks {}; a reflective material gives all three Fresnel keys (none: no \
                 reflection)",
                absent.join(" and ")
            )));
        }
    };
    Ok(MaterialDesc {
        name,
        diffuse,
        specular,
        ambient,
        phong_exponent,
        fresnel,
    })
}

/// `scale s` (uniform) or `scale sx sy sz`.
fn scale(e: &mut Entries) -> Result<Option<Scale>> {
    let Some(entry) = e.take("scale", "scale") else {
        return Ok(None);
    };
    let v = entry
        .values
        .iter()
        .map(|w| e.finite::<f32>(&entry, w))
        .collect::<Result<Vec<f32>>>()?;
    match v[..] {
        [s] => Ok(Some(Scale::Uniform(s))),
        [x, y, z] => Ok(Some(Scale::PerAxis([x, y, z]))),
        _ => Err(e.error(
            &entry,
            format!(
                "expects 1 number (uniform) or 3 (x y z), found {} value(s)",
                v.len()
            ),
        )),
    }
}

/// Location, velocity, rotation and angular velocity (all default zero).
fn placement(e: &mut Entries) -> Result<[[f32; 3]; 4]> {
    Ok([
        e.vec3("location", "location")?.unwrap_or_default(),
        e.vec3("velocity", "velocity")?.unwrap_or_default(),
        e.vec3("rotation", "rotation")?.unwrap_or_default(),
        e.vec3("angularvelocity", "angular_velocity")?
            .unwrap_or_default(),
    ])
}

fn object(e: &mut Entries, index: usize) -> Result<ObjectDesc> {
    let name = name_or_derived(e, "objectname", "object", index)?;
    let kind = e.choice("type", "type", &["model", "sphere", "plane"])?;
    let kind = match e.require(kind, "type", "model|sphere|plane")?.as_str() {
        "model" => ObjectKind::Model,
        "sphere" => ObjectKind::Sphere,
        _ => ObjectKind::Plane,
    };
    let material = e.word("materialname", "material")?;
    let material = e.require(material, "materialname", "<material name>")?;
    let file = e.word("modelfilename", "file")?;
    let radius = e.f32("radius", "radius")?;
    let half_extent = e.numbers::<2>("halfextent", "half_extent", "2 numbers (x z)")?;
    let scale = scale(e)?;
    let [location, velocity, rotation, angular_velocity] = placement(e)?;
    let hidden = e.boolean("hidden", "hidden")?.unwrap_or(false);
    Ok(ObjectDesc {
        name,
        kind,
        material,
        file,
        radius,
        half_extent,
        scale,
        location,
        velocity,
        rotation,
        angular_velocity,
        hidden,
    })
}

fn instance(e: &mut Entries, index: usize) -> Result<InstanceDesc> {
    let name = name_or_derived(e, "instancename", "instance", index)?;
    let object = e.word("objectname", "object")?;
    let object = e.require(object, "objectname", "<name of the object copied>")?;
    let material = e.word("materialname", "material")?;
    let scale = scale(e)?;
    let [location, velocity, rotation, angular_velocity] = placement(e)?;
    Ok(InstanceDesc {
        name,
        object,
        material,
        scale,
        location,
        velocity,
        rotation,
        angular_velocity,
    })
}

fn group(e: &mut Entries, index: usize) -> Result<GroupDesc> {
    let name = name_or_derived(e, "groupname", "group", index)?;
    let children = e.words("children", "children").unwrap_or_default();
    let scale = scale(e)?;
    let [location, velocity, rotation, angular_velocity] = placement(e)?;
    Ok(GroupDesc {
        name,
        children,
        scale,
        location,
        velocity,
        rotation,
        angular_velocity,
    })
}

fn light(e: &mut Entries) -> Result<LightDesc> {
    let kind = e.choice("type", "type", &["point", "directional"])?;
    let kind = match e.require(kind, "type", "point|directional")?.as_str() {
        "point" => LightKind::Point,
        _ => LightKind::Directional,
    };
    Ok(LightDesc {
        kind,
        color: e.colour("color", "color")?.unwrap_or([1.0; 3]),
        intensity: e.f32("intensity", "intensity")?.unwrap_or(1.0),
        position: e.vec3("position", "position")?,
        direction: e.vec3("direction", "direction")?,
    })
}

fn camera_block(e: &mut Entries) -> Result<CameraDesc> {
    let location = e.vec3("location", "location")?;
    let look_at = e.vec3("lookat", "look_at")?;
    let fov = e.f32("fov", "fov")?;
    Ok(CameraDesc {
        location: e.require(location, "location", "<x> <y> <z>")?,
        location_velocity: e
            .vec3("locationvelocity", "location_velocity")?
            .unwrap_or_default(),
        look_at: e.require(look_at, "lookat", "<x> <y> <z>")?,
        look_at_velocity: e
            .vec3("lookatvelocity", "look_at_velocity")?
            .unwrap_or_default(),
        up: e.vec3("up", "up")?.unwrap_or(DEFAULT_UP),
        up_velocity: e.vec3("upvelocity", "up_velocity")?.unwrap_or_default(),
        fov: e.require(fov, "fov", "<degrees>")?,
    })
}

/// The settings block: the settings, and the scene's name and description.
struct Settings {
    desc: SettingsDesc,
    name: Option<String>,
    description: Option<String>,
}

fn settings_block(e: &mut Entries) -> Result<Settings> {
    let frame_time = e.f32("frametime", "settings.frame_time")?;
    let frames = e.integer::<u32>("numframes", "settings.frames")?;
    let width = e.integer::<u32>("sizex", "settings.width")?;
    let height = e.integer::<u32>("sizey", "settings.height")?;
    let environment = match e.word("envmap", "settings.environment.file")? {
        Some(file) => Some(EnvironmentDesc {
            file,
            intensity: e
                .f32("envmapintensity", "settings.environment.intensity")?
                .unwrap_or(1.0),
            rotation: e
                .f32("envmaprotation", "settings.environment.rotation")?
                .unwrap_or(0.0),
            negatives: e
                .choice(
                    "envmapnegatives",
                    "settings.environment.negatives",
                    &NegativeTexels::ALL.map(NegativeTexels::name),
                )?
                .and_then(|w| NegativeTexels::by_name(&w).ok()),
        }),
        None => {
            for key in ["envmapintensity", "envmaprotation", "envmapnegatives"] {
                if let Some(entry) = e.take(key, "settings.environment") {
                    return Err(e.error(&entry, "needs an `envmap` line in the same block"));
                }
            }
            None
        }
    };
    let default = SamplingConfig::default();
    let point_set = e.choice(
        "pointset",
        "settings.sampling.point_set",
        &names::POINT_SET_WORDS,
    )?;
    let spp = e.integer::<u32>("numsamples", "settings.sampling.spp")?;
    let time_filter = e.choice(
        "timefilter",
        "settings.sampling.time_filter",
        &names::TIME_FILTER_WORDS,
    )?;
    // `choice` admitted only the text words, each of which names a set or filter.
    let sampling = SamplingConfig {
        point_set: point_set.map_or(default.point_set, |w| {
            names::point_set_from_text(&w).expect("a text word")
        }),
        spp: spp.unwrap_or(default.spp),
        time_filter: time_filter.map_or(default.time_filter, |w| {
            names::time_filter_from_text(&w).expect("a text word")
        }),
        ..Default::default()
    }
    .with_options(&options::read(e, "settings.sampling", Host::Scene)?);
    let desc = SettingsDesc {
        start_time: e.f32("starttime", "settings.start_time")?.unwrap_or(0.0),
        frame_time: e.require(frame_time, "frametime", "<seconds>")?,
        frames: e.require(frames, "numframes", "<count>")?,
        fps: e.f64("fps", "settings.fps")?.unwrap_or(DEFAULT_FPS),
        width: e.require(width, "sizex", "<pixels>")?,
        height: e.require(height, "sizey", "<pixels>")?,
        ambient_light: e
            .colour("ambientlightcolor", "settings.ambient_light")?
            .unwrap_or_default(),
        max_depth: e
            .integer::<u32>("maxdepth", "settings.max_depth")?
            .unwrap_or(DEFAULT_MAX_DEPTH),
        environment,
        exposure: e.f32("exposure", "settings.exposure")?.unwrap_or(1.0),
        sampling,
    };
    Ok(Settings {
        desc,
        name: e.word("scenename", "name")?,
        description: e.word("description", "description")?,
    })
}
