//! Checking a parsed scene file and turning it into a [`Scene`]. Every error names the file,
//! the field path (`objects[2].velocity`) and what was expected ([`check`]), and the errors
//! come in the file's order: materials, then the objects and instances with their groups
//! ([`placing`]), lights, settings and camera ([`blocks`]), then the environment map.

mod blocks;
mod check;
mod placing;

pub use blocks::MAX_PHONG_EXPONENT;

use super::Scene;
use super::file::{SCENE_FORMAT, SceneFile};
use crate::assets::Assets;
use crate::environment::Environment;
use crate::text::SourceMap;
use anyhow::Result;
use check::Check;
use std::path::Path;
use std::sync::Arc;

/// Parse scene text; a syntax or type error names the field path where it happened
/// ([`crate::json::from_str`]: a byte-order mark is skipped, trailing text refused).
pub fn parse(text: &str, path: &Path) -> Result<SceneFile> {
    let file = crate::json::from_str(text, path, "scene file")?;
    super::magnitude::check_tiny(text)
        .map_err(|(field, what)| anyhow::anyhow!("{}: field `{field}` {what}", path.display()))?;
    Ok(file)
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
    let materials = blocks::materials(c, &f.materials)?;
    let instances = placing::instances(c, f, dir)?;
    let lights = f
        .lights
        .iter()
        .enumerate()
        .map(|(i, l)| blocks::light(c, &format!("lights[{i}]"), l))
        .collect::<Result<Vec<_>>>()?;
    let settings = blocks::settings(c, &f.settings)?;
    // After the fields with their own range (Phong exponent, sizes), which name it first;
    // before the camera's frames are checked (a frame_time of 3e38 is named as such) and the
    // environment map is read.
    super::magnitude::check(f).map_err(|(field, what)| c.err(field, what))?;
    let camera = blocks::camera(c, &f.camera, &settings)?;
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
