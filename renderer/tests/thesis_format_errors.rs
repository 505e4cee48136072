//! Every way a `.scene` or `.job` file can be wrong, with the message the user gets: the file,
//! the line, the key, and what was expected. The scene cases edit Figure 13 (as the thesis
//! prints it) in one place each; checks made after reading (a material that is not defined, a
//! model file that is missing) still name the line and key.

use renderer::job::Job;
use renderer::job::line_format;
use renderer::scene::Scene;
use renderer::scene::block_format;
use std::path::Path;

fn figure13() -> String {
    std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/thesis/figure13.scene"),
    )
    .unwrap()
}

fn figure12() -> String {
    std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/thesis/figure12.job"),
    )
    .unwrap()
}

/// Figure 13 with `from` replaced by `to` (which must change it).
fn edited(from: &str, to: &str) -> String {
    let text = figure13();
    assert!(text.contains(from), "{from}");
    text.replacen(from, to, 1)
}

fn scene_error(text: &str) -> String {
    format!(
        "{:#}",
        block_format::read(text, Path::new("f.scene")).unwrap_err()
    )
}

#[test]
fn syntax_errors_name_the_line() {
    let cases: Vec<(String, &str)> = vec![
        (
            "lamp\nend\n".into(),
            "f.scene:1: `lamp` outside a block; expected a block keyword (material, object, \
             objectinstance, group, light, camera, settings) on its own line, then its keys, \
             then `end`",
        ),
        (
            edited("material\n", "fov 50\nmaterial\n"),
            "f.scene:1: `fov` outside a block; expected a block keyword (material, object, \
             objectinstance, group, light, camera, settings) on its own line, then its keys, \
             then `end`",
        ),
        ("end\n".into(), "f.scene:1: `end` without an open block"),
        (
            edited("material\n", "material plane_material\n"),
            "f.scene:1: block keyword `material` stands alone on its line; found `material \
             plane_material`",
        ),
        (
            edited("fov 50\nend\n", "fov 50\n"),
            "f.scene:29: block `camera` opened on line 20 is not closed by `end` before block \
             `settings`",
        ),
        (
            edited("scenename planescene\nend\n", "scenename planescene\n"),
            "f.scene:30: block `settings` is not closed by `end` before the end of the file",
        ),
        (
            edited("fov 50\nend\n", "fov 50\nend camera\n"),
            "f.scene:28: `end` stands alone on its line; found `end camera`",
        ),
        (
            edited("scenename planescene", "scenename \"plane scene"),
            "f.scene:42: quoted word \"plane scene is not closed by `\"`",
        ),
    ];
    for (text, want) in cases {
        assert_eq!(scene_error(&text), want);
    }
}

#[test]
fn key_errors_name_the_line_the_key_and_what_was_expected() {
    let cases = [
        // The text copy's OCR errors are not accepted.
        (
            "location 0 0 420",
            "location O 0 420",
            "f.scene:16: key `location` expects a number; `O` is not one",
        ),
        (
            "up 0 1 0",
            "up 010",
            "f.scene:24: key `up` expects 3 numbers (x y z), found 1 value(s): `010`",
        ),
        (
            "fov 50",
            "fov 50 60",
            "f.scene:27: key `fov` expects one number, found 2 value(s): `50 60`",
        ),
        (
            "fov 50",
            "fov inf",
            "f.scene:27: key `fov` expects finite numbers; `inf` is not",
        ),
        (
            "numframes 210",
            "numframes 210.5",
            "f.scene:33: key `numframes` expects a whole number >= 0; `210.5` is not one",
        ),
        (
            "type model",
            "type airliner",
            "f.scene:12: key `type` expects one of model, sphere, plane; found `airliner`",
        ),
        (
            "scale 13",
            "scale 13 13",
            "f.scene:15: key `scale` expects 1 number (uniform) or 3 (x y z), found 2 value(s)",
        ),
        (
            "fov 50",
            "fov 50\nfov 60",
            "f.scene:28: key `fov` is given twice in block `camera` (line 20) (first on line \
             27); expected it once",
        ),
        (
            "fov 50",
            "fov 50\nfocus 3",
            "f.scene:28: unknown key `focus` in block `camera` (line 20); expected one of: fov, \
             location, locationvelocity, lookat, lookatvelocity, up, upvelocity",
        ),
        (
            "fov 50\n",
            "",
            "f.scene:20: block `camera` (line 20) has no key `fov`; expected a line `fov \
             <degrees>`",
        ),
        (
            "materialname plane_material\ndiffusecolor",
            "diffusecolor",
            "f.scene:1: block `material` (line 1) has no key `materialname`; expected a line \
             `materialname <name>`",
        ),
        (
            "type model\n",
            "",
            "f.scene:11: block `object` (line 11) has no key `type`; expected a line `type \
             model|sphere|plane`",
        ),
        (
            "frametime 0.12\n",
            "",
            "f.scene:30: block `settings` (line 30) has no key `frametime`; expected a line \
             `frametime <seconds>`",
        ),
        (
            "fresnelmaximum 1.0\nfresnelexponent 2.0\n",
            "",
            "f.scene:1: block `material` (line 1) lacks `fresnelmaximum` and \
             `fresnelexponent`; a reflective material gives all three Fresnel keys (none: no \
             reflection)",
        ),
        (
            "envmap data/CedarCity.hdr",
            "envmaprotation 90",
            "f.scene:41: key `envmaprotation` needs an `envmap` line in the same block",
        ),
        (
            "maxdepth 4",
            "maxdepth 4\ndensity temporal eight",
            "f.scene:38: key `density` expects `joint`, `temporal K` or `spatial K`; `eight` \
             is not a whole number",
        ),
        (
            "maxdepth 4",
            "maxdepth 4\ndensity both",
            "f.scene:38: key `density` expects `joint`, `temporal K` or `spatial K`; found \
             `both`",
        ),
        (
            "maxdepth 4",
            "maxdepth 4\nshiftscope scene",
            "f.scene:38: key `shiftscope` expects one of frame, sequence; found `scene`",
        ),
        (
            "maxdepth 4",
            "maxdepth 4\nrandomization owen",
            "f.scene:38: key `randomization` expects one of shift, scramble; found `owen`",
        ),
        (
            "maxdepth 4",
            "maxdepth 4\nspatialfilter tent",
            "f.scene:38: key `spatialfilter` expects one of gaussian, box; found `tent`",
        ),
        (
            "camera\n",
            "light\ntype spot\nend\ncamera\n",
            "f.scene:21: key `type` expects one of point, directional; found `spot`",
        ),
        (
            "object\n",
            "group\nchildren a b\nhidden true\nend\nobject\n",
            "f.scene:13: unknown key `hidden` in block `group` (line 11); expected one of: \
             angularvelocity, children, groupname, location, rotation, scale, velocity",
        ),
        (
            "camera\n",
            "objectinstance\nlocation 1 2 3\nend\ncamera\n",
            "f.scene:20: block `objectinstance` (line 20) has no key `objectname`; expected a \
             line `objectname <name of the object copied>`",
        ),
    ];
    for (from, to, want) in cases {
        assert_eq!(scene_error(&edited(from, to)), want, "{from} -> {to}");
    }
}

#[test]
fn one_camera_and_one_settings_block() {
    let text = figure13();
    let camera = &text[text.find("camera\n").unwrap()..text.find("settings\n").unwrap()];
    assert_eq!(
        scene_error(&format!("{text}\n{camera}")),
        "f.scene:45: a second `camera` block (the first is on line 20); a scene has exactly one"
    );
    assert_eq!(
        scene_error(&text.replacen(camera, "", 1)),
        "f.scene: no `camera` block; a scene has exactly one (`camera` ... `end`, thesis \
         Figure 13)"
    );
    let settings = &text[text.find("settings\n").unwrap()..];
    assert_eq!(
        scene_error(&text.replacen(settings, "", 1)),
        "f.scene: no `settings` block; a scene has exactly one (`settings` ... `end`, thesis \
         Figure 13)"
    );
}

/// Checks made on the model after reading (`scene::build`) point at the line and key too.
#[test]
fn checks_after_reading_name_the_line_and_key() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("models")).unwrap();
    std::fs::write(
        dir.path().join("models/B-727-200.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    let path = dir.path().join("f.scene");
    let error = |text: String| {
        let e = format!("{:#}", Scene::from_block_text(&text, &path).unwrap_err());
        e.replace(&format!("{}/", dir.path().display()), "")
    };
    let cases = [
        (
            "materialname plane_material\nmodelfilename",
            "materialname plane\nmodelfilename",
            "f.scene:13: key `materialname` (field `objects[0].material`) names material \
             `plane`, which is not defined (materials: `plane_material`)",
        ),
        (
            "fov 50",
            "fov 190",
            "f.scene:27: key `fov` (field `camera.fov`) is 190; expected degrees between 0 and \
             180",
        ),
        (
            "scale 13",
            "scale -13",
            "f.scene:15: key `scale` (field `objects[0].scale`) is [-13, -13, -13]; expected \
             positive scale factors",
        ),
        (
            "fresnelminimum 0.3",
            "fresnelminimum 1.3",
            "f.scene:1: block `material` (field `materials[0].fresnel`) has min 1.3 and max 1; \
             expected 0 <= min <= max <= 1",
        ),
        (
            "pointset hammersley\nnumsamples 64",
            "pointset stratifiedmc\nnumsamples 65",
            "f.scene:30: block `settings` (field `settings.sampling`) stratified sampling in \
             3D needs a cube number of samples, not 65",
        ),
        (
            "B-727-200.obj",
            "B-727-200.0bj",
            "f.scene:14: key `modelfilename` (field `objects[0].file`) cannot read",
        ),
        (
            "data/CedarCity.hdr",
            "data/nope.hdr",
            "f.scene:41: key `envmap` (field `settings.environment.file`) cannot read \
             environment map data/nope.hdr",
        ),
        (
            "type model\n",
            "type model\nradius 3\n",
            "f.scene:13: key `radius` (field `objects[0].radius`) does not apply to a model",
        ),
        (
            "object\n",
            "objectinstance\ninstancename object1\nobjectname object1\nend\nobject\n",
            "f.scene:12: key `instancename` (field `instances[0].name`) repeats `object1` \
             (already objects[0])",
        ),
        (
            "object\n",
            "object\nobjectname object2\ntype sphere\nradius 1\nmaterialname plane_material\n\
             end\nobject\n",
            "f.scene:17: the block (no `objectname`: named `object2`) (field `objects[1].name`) \
             repeats `object2` (already objects[0])",
        ),
    ];
    for (from, to, want) in cases {
        let e = error(edited(from, to));
        assert!(e.starts_with(want), "{from} -> {to}:\n{e}\nwanted\n{want}");
    }
}

fn job_error(text: &str) -> String {
    format!(
        "{:#}",
        line_format::read(text, Path::new("j.job")).unwrap_err()
    )
}

/// Figure 12 plus extension lines.
fn with(extra: &str) -> String {
    figure12() + extra
}

#[test]
fn job_errors_name_the_line_and_key() {
    let cases: Vec<(String, &str)> = vec![
        (
            "Plane_scene\n8\n1 8 27 64 125 216 343 512\n".into(),
            "j.job: has 3 of the seven lines of a job (thesis Figure 12: name; number of \
             levels; levels; number of point sets; point sets; number of time filters; time \
             filters); the next line would be the number of point sets",
        ),
        (
            figure12().replace("Plane_scene", "Plane scene"),
            "j.job:1: the job's `name` is one word; found `Plane scene`",
        ),
        (
            figure12().replacen("8\n", "eight\n", 1),
            "j.job:2: `number of levels` (line 2 of 7) is one whole number; found `eight`",
        ),
        (
            figure12().replacen("8\n", "9\n", 1),
            "j.job:3: `levels` lists 8 (1 8 27 64 125 216 343 512), but the `number of levels` \
             on line 2 is 9; expected as many as the count",
        ),
        (
            figure12().replace("3\nhammersley", "2\nhammersley"),
            "j.job:5: `point sets` lists 3 (hammersley stratifiedmc poisson), but the `number \
             of point sets` on line 4 is 2; expected as many as the count",
        ),
        (
            figure12().replace("box triangle", "box"),
            "j.job:7: `time filters` lists 1 (box), but the `number of time filters` on line 6 \
             is 2; expected as many as the count",
        ),
        (
            figure12().replace(" 64 ", " 6x4 "),
            "j.job:3: `levels`: `6x4` is not a whole number of samples per pixel",
        ),
        (
            with("seed 1\nseed 2\n"),
            "j.job:9: key `seed` is given twice in the job's extension lines (after the seven) \
             (first on line 8); expected it once",
        ),
        (
            with("size 64\n"),
            "j.job:8: unknown key `size` in the job's extension lines (after the seven); \
             expected one of: density, exr, firstframe, frames, framesperunit, height, \
             pointsetscope, randomization, reference, referencepointset, referencetimefilter, \
             scene, seed, shiftscope, spatialfilter, spatialsigma, width",
        ),
        (
            with("scene a.scene b.scene\n"),
            "j.job:8: key `scene` expects one scene file (quote a name with spaces), found 2 \
             value(s)",
        ),
        (
            with("reference best\n"),
            "j.job:8: key `reference` expects `highestlevel` or the reference's samples per \
             pixel; found `best`",
        ),
        (
            with("reference highestlevel\nreferencepointset stratified\n"),
            "j.job:8: key `reference` is `highestlevel`, but `referencepointset` and \
             `referencetimefilter` apply only to an independent reference (`reference <spp>`); \
             the highest level has each condition's own point set and time filter",
        ),
        (
            with("referencetimefilter box\n"),
            "j.job:8: the job's extension lines (after the seven) have no `reference <spp>` \
             line, but `referencepointset` and `referencetimefilter` apply only to an \
             independent reference (`reference <spp>`); the highest level has each condition's \
             own point set and time filter",
        ),
        (
            with("randomization owen\n"),
            "j.job:8: key `randomization` expects one of shift, scramble; found `owen`",
        ),
        (
            with("shiftscope pixel\n"),
            "j.job:8: key `shiftscope` expects one of frame, sequence, scene; found `pixel`",
        ),
        (
            with("width 64 64\n"),
            "j.job:8: key `width` expects one whole number, found 2 value(s): `64 64`",
        ),
        (
            with("exr yes\n"),
            "j.job:8: key `exr` expects one of true, false; found `yes`",
        ),
    ];
    for (text, want) in cases {
        assert_eq!(job_error(&text), want);
    }
}

/// Checks made on the job after reading (`Job::from_file`) point at the line too.
#[test]
fn job_checks_after_reading_name_the_line() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.json"), "{}").unwrap();
    let path = dir.path().join("j.job");
    let error = |text: String| {
        std::fs::write(&path, text).unwrap();
        let e = format!("{:#}", Job::load(&path).unwrap_err());
        e.replace(&format!("{}/", dir.path().display()), "")
    };
    let cases = [
        (
            figure12(),
            "j.job: the default scene `j.scene` (no `scene` line, so the file named after the \
             job, beside it; add a line `scene <file>` or pass --scene) (field `scenes[0]`) \
             names \"j.scene\", but j.scene is not a file",
        ),
        (
            with("scene s.json\nscene t.json\n"),
            "j.job:9: key `scene` (field `scenes[1]`) names \"t.json\", but t.json is not a file",
        ),
        (
            with("scene s.json\n").replace("stratifiedmc", "jittered"),
            "j.job:5: `point sets` (line 5 of 7) (field `point_sets[1]`) unknown point set \
             \"jittered\"",
        ),
        (
            with("scene s.json\n").replace(" 64 ", " 63 "),
            "j.job:5: `point sets` (line 5 of 7) (field `point_sets[1]`) with time filter \
             \"truncated_box\" at 63 spp: stratified sampling in 3D needs a cube number of \
             samples, not 63",
        ),
        (
            with("scene s.json\n").replace(" 64 ", " 8 "),
            "j.job:3: `levels` (line 3 of 7) (field `levels[3]`) repeats 8",
        ),
        (
            with("scene s.json\nreference 500\n"),
            "j.job:9: key `reference` (field `reference.spp`) is 500; expected more than the \
             highest level (512)",
        ),
        (
            with("scene s.json\nwidth 0\n"),
            "j.job:9: key `width` (field `overrides.width`) is 0; expected 1 to 16384 pixels",
        ),
        (
            figure12().replace("Plane_scene", "Plane-scene") + "scene s.json\n",
            "j.job:1: `name` (line 1 of 7) (field `name`) is \"Plane-scene\"; expected a \
             non-empty name of ASCII letters, digits and `_`",
        ),
    ];
    for (text, want) in cases {
        let e = error(text);
        assert!(e.starts_with(want), "\n{e}\nwanted\n{want}");
    }
}

/// `render convert` refuses what it cannot do, naming the file and what was expected.
#[test]
fn conversion_errors_name_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let job = d.join("j.job");
    std::fs::write(&job, figure12()).unwrap();
    let strip = |e: anyhow::Error| format!("{e:#}").replace(&format!("{}/", d.display()), "");
    let e = strip(renderer::convert::convert(&job, &d.join("j.scene")).unwrap_err());
    assert_eq!(
        e,
        "j.scene: a job cannot be written as a scene (.scene); write .job or .json"
    );
    let e = strip(renderer::convert::convert(&job, &d.join("j.yaml")).unwrap_err());
    assert_eq!(
        e,
        "j.yaml: expected a file ending in .json, .scene (thesis Figure 13) or .job (thesis \
         Figure 12)"
    );
    let json = d.join("x.json");
    std::fs::write(&json, r#"{"format": "blurlab-design/1"}"#).unwrap();
    let e = strip(renderer::convert::convert(&json, &d.join("x.job")).unwrap_err());
    assert_eq!(
        e,
        "x.json: field `format` is \"blurlab-design/1\"; expected \"blurlab-scene/1\" or \
         \"blurlab-job/1\""
    );
    // Every point set and time filter has a text spelling (the names are typed); an empty
    // list has none.
    let (mut file, _) = line_format::read(&figure12(), &job).unwrap();
    file.point_sets.clear();
    let e = format!("{:#}", line_format::write(&file).unwrap_err());
    assert_eq!(e, "field `point_sets` is empty; a job lists at least one");
    assert!(
        !d.join("j.scene").exists() && !d.join("x.job").exists(),
        "no file written"
    );
}
