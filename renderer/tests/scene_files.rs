//! Scene files: the suite's scenes load and render, bad files are refused with messages that
//! name the file and the field, and a job renders a real scene with its overrides.

use renderer::job::Overrides;
use renderer::job::scene_source::load_source;
use renderer::progress::NoProgress;
use renderer::render::render_frame;
use renderer::sampling::SamplingConfig;
use renderer::scene::Scene;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes")
}

#[test]
fn the_suites_scenes_load_and_render_without_nan() {
    for name in ["thesis/plane", "thesis/spheres", "static"] {
        let path = scenes_dir().join(format!("{name}.json"));
        let mut scene = Scene::load(&path).unwrap();
        assert!(scene.warnings.is_empty(), "{name}: {:?}", scene.warnings);
        assert_eq!(scene.has_motion(), name != "static", "{name}");
        scene.settings.width = 16;
        scene.settings.height = 16;
        // The scene's own sampling at 8 spp (a cube, as stratified sets need).
        let cfg = SamplingConfig {
            spp: 8,
            ..scene.settings.sampling.clone()
        };
        let last = scene.settings.frames - 1;
        for frame in [0, last / 2, last] {
            let (film, stats) = render_frame(&scene, &cfg, 1, frame, &NoProgress).unwrap();
            assert_eq!(stats.non_finite, 0, "{name} frame {frame}");
            assert!(film.pixels.iter().all(|p| p.is_finite()));
        }
    }
}

/// A small valid scene to break in one place at a time.
fn valid(dir: &Path) -> Value {
    std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    json!({
        "format": "blurlab-scene/1",
        "materials": [{"name": "m", "diffuse": [0.5, 0.5, 0.5]}],
        "objects": [
            {"name": "tri", "type": "model", "file": "tri.obj", "material": "m"},
            {"name": "ball", "type": "sphere", "radius": 1, "material": "m", "hidden": true}
        ],
        "instances": [{"name": "b1", "object": "ball", "location": [2, 0, 0]}],
        "groups": [{"name": "g", "children": ["tri", "b1"]}],
        "lights": [{"type": "point", "position": [0, 5, 5]}],
        "camera": {"location": [0, 0, 5], "look_at": [0, 0, 0], "fov": 40},
        "settings": {"frame_time": 0.1, "frames": 3, "width": 8, "height": 8}
    })
}

/// Replace the value at a slash-separated path (`objects/1/radius`); `null` removes it.
fn with(mut v: Value, path: &str, new: Value) -> Value {
    let (parent, key) = path.rsplit_once('/').unwrap_or(("", path));
    let mut at = &mut v;
    for k in parent.split('/').filter(|k| !k.is_empty()) {
        at = match k.parse::<usize>() {
            Ok(i) => &mut at[i],
            Err(_) => &mut at[k],
        };
    }
    match (at, key.parse::<usize>()) {
        (Value::Array(a), Ok(i)) => a[i] = new,
        (Value::Object(o), _) if new.is_null() => {
            o.remove(key);
        }
        (Value::Object(o), _) => {
            o.insert(key.into(), new);
        }
        (other, _) => panic!("cannot set {path} in {other}"),
    }
    v
}

#[test]
fn bad_scenes_are_refused_naming_the_file_and_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("bad_scene.json");
    let base = valid(dir.path());
    Scene::from_json(&base.to_string(), &file).expect("the base scene is valid");
    // (change, words the message must hold besides the file name)
    let cases: Vec<(Value, &[&str])> = vec![
        (
            with(base.clone(), "format", json!("blurlab-scene/9")),
            &["`format`", "blurlab-scene/1"],
        ),
        (
            with(base.clone(), "objects/0/velocty", json!([1, 0, 0])),
            &["objects[0]", "velocty"],
        ),
        (
            with(base.clone(), "objects/0/velocity", json!("fast")),
            &["objects[0].velocity", "array"],
        ),
        (
            with(base.clone(), "objects/0/location", json!([1, 2])),
            &["objects[0].location", "length 3"],
        ),
        (
            with(base.clone(), "objects/0/material", json!("nope")),
            &["objects[0].material", "`nope`", "`m`"],
        ),
        (
            with(base.clone(), "objects/0/type", json!("cube")),
            &["objects[0].type", "cube"],
        ),
        (
            with(base.clone(), "objects/0/file", json!("missing.obj")),
            &["objects[0].file", "missing.obj"],
        ),
        (
            with(base.clone(), "objects/1/radius", Value::Null),
            &["objects[1].radius", "missing"],
        ),
        (
            with(base.clone(), "objects/1/radius", json!(-1)),
            &["objects[1].radius", "> 0"],
        ),
        (
            with(base.clone(), "objects/1/file", json!("tri.obj")),
            &["objects[1].file", "sphere"],
        ),
        (
            with(base.clone(), "objects/0/scale", json!([1, 0, 1])),
            &["objects[0].scale", "positive"],
        ),
        (
            with(base.clone(), "objects/0/scale", json!("big")),
            &["objects[0].scale", "positive number"],
        ),
        (
            with(base.clone(), "instances/0/object", json!("bal")),
            &["instances[0].object", "`bal`"],
        ),
        (
            with(base.clone(), "instances/0/name", json!("tri")),
            &["instances[0].name", "`tri`", "objects[0]"],
        ),
        (
            with(base.clone(), "groups/0/children/1", json!("ghost")),
            &["groups[0].children[1]", "ghost"],
        ),
        (
            with(base.clone(), "groups/0/children/1", json!("ball")),
            &["groups[0].children[1]", "hidden"],
        ),
        (
            with(
                base.clone(),
                "materials/0/fresnel",
                json!({"min": 0.8, "max": 0.2, "exponent": 5}),
            ),
            &["materials[0].fresnel", "min <= max"],
        ),
        (
            with(base.clone(), "materials/0/phong_exponent", json!(1e9)),
            &["materials[0].phong_exponent", "1000000000", "[0, 1e6]"],
        ),
        (
            with(base.clone(), "materials/0/phong_exponent", json!(-2)),
            &["materials[0].phong_exponent", "[0, 1e6]"],
        ),
        (
            with(base.clone(), "materials/0/diffuse", json!([0.5, -1, 0.5])),
            &["materials[0].diffuse", ">= 0"],
        ),
        (
            with(base.clone(), "lights/0/position", Value::Null),
            &["lights[0].position", "missing"],
        ),
        (
            with(base.clone(), "lights/0/type", json!("directional")),
            &["lights[0].direction", "missing"],
        ),
        (
            with(base.clone(), "camera/look_at", json!([0, 0, 5])),
            &["`camera`", "look_at"],
        ),
        (
            with(base.clone(), "camera/fov", json!(180)),
            &["camera.fov", "between 0 and 180"],
        ),
        (
            with(base.clone(), "settings/width", json!(0)),
            &["settings.width", "1 to"],
        ),
        (
            with(base.clone(), "settings/frame_time", json!(0)),
            &["settings.frame_time", "> 0"],
        ),
        (
            with(base.clone(), "settings/sampling", json!({"spp": 0})),
            &["settings.sampling", "spp"],
        ),
        (
            with(
                base.clone(),
                "settings/environment",
                json!({"file": "sky.hdr"}),
            ),
            &["settings.environment.file", "sky.hdr"],
        ),
        (
            with(
                base.clone(),
                "settings/environment",
                json!({"file": "tri.obj"}),
            ),
            &["settings.environment.file", ".hdr or .exr"],
        ),
        // The map is read beside the rest of the scene; the errors keep their order: the
        // rest's first, then the environment's fields, then its file.
        (
            with(
                with(base.clone(), "camera/fov", json!(180)),
                "settings/environment",
                json!({"file": "sky.hdr"}),
            ),
            &["camera.fov", "between 0 and 180"],
        ),
        (
            with(
                base.clone(),
                "settings/environment",
                json!({"file": "sky.hdr", "intensity": -1}),
            ),
            &["settings.environment.intensity", ">= 0"],
        ),
        (
            with(base.clone(), "settings/frames", Value::Null),
            &["settings", "frames"],
        ),
        // Magnitudes the tracer's 32-bit floats cannot carry (docs/limits.md).
        (
            with(base.clone(), "objects/1/radius", json!(1e20)),
            &["objects[1].radius", "1e20", "at most 1e7"],
        ),
        (
            with(base.clone(), "objects/1/radius", json!(1e10)),
            &["objects[1].radius", "at most 1e7"],
        ),
        (
            with(
                base.clone(),
                "settings/environment",
                json!({"file": "x.hdr", "intensity": 1e38}),
            ),
            &["settings.environment.intensity", "at most 1e7"],
        ),
        (
            with(
                with(base.clone(), "settings/start_time", json!(-100)),
                "objects/0/velocity",
                json!([1e6, 0, 0]),
            ),
            &["objects[0].velocity", "velocity x time"],
        ),
    ];
    for (scene, words) in cases {
        let err = match Scene::from_json(&scene.to_string(), &file) {
            Ok(_) => panic!("accepted: {scene}"),
            Err(e) => format!("{e:#}"),
        };
        assert!(err.contains("bad_scene.json"), "no file name in: {err}");
        for w in words {
            assert!(err.contains(w), "`{w}` missing from: {err}");
        }
    }
}

#[test]
fn a_job_renders_a_real_scene_with_its_overrides() {
    let dir = tempfile::tempdir().unwrap();
    let mut v = valid(dir.path());
    v["objects"][0]["velocity"] = json!([1, 0, 0]);
    v["settings"]["sampling"] = json!({"point_set": "random", "spp": 3, "time_filter": "box"});
    let path = dir.path().join("scene.json");
    std::fs::write(&path, v.to_string()).unwrap();
    let overrides = Overrides {
        width: Some(6),
        height: Some(4),
        frames: Some(2),
        first_frame: Some(1),
        ..Default::default()
    };
    let src = load_source(&path, &overrides, &Default::default(), &mut vec![]).unwrap();
    let setup = src.setup();
    assert_eq!((setup.width, setup.height, setup.frames), (6, 4, 2));
    assert_eq!(setup.fps, 30.0);
    let job_sampling = SamplingConfig {
        spp: 5,
        ..SamplingConfig::default()
    };
    let frame = src.render(&job_sampling, 9, 1).unwrap();
    assert_eq!(frame.linear.len(), 24);
    assert_eq!(frame.display.len(), 72);
    // Stimulus frame 1 is scene frame 2 at the job's spp: the same as rendering it directly.
    let mut scene = Scene::load(&path).unwrap();
    scene.settings.width = 6;
    scene.settings.height = 4;
    let (film, _) = render_frame(&scene, &job_sampling, 9, 2, &NoProgress).unwrap();
    assert_eq!(film.develop(1.0).display, frame.display);
    let small = src.resized(3, 2).unwrap();
    assert_eq!(small.render(&job_sampling, 9, 0).unwrap().linear.len(), 6);
    // Asking for frames past the animation is an error naming the scene.
    let too_long = Overrides {
        frames: Some(3),
        ..overrides
    };
    let err = format!(
        "{:#}",
        load_source(&path, &too_long, &Default::default(), &mut vec![])
            .err()
            .unwrap()
    );
    assert!(
        err.contains("scene.json") && err.contains("settings.frames"),
        "{err}"
    );
}

#[test]
fn scene_text_is_whole_json_and_may_start_with_a_byte_order_mark() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("s.json");
    let text = valid(dir.path()).to_string();
    Scene::from_json(&format!("\u{feff}{text}"), &file).expect("a BOM is skipped");
    let err = format!(
        "{:#}",
        Scene::from_json(&format!("{text} {{\"x\": 1}}"), &file).unwrap_err()
    );
    assert!(
        err.contains("s.json") && err.contains("nothing after"),
        "{err}"
    );
}
