//! The thesis's own file formats: Figure 12's job and Figure 13's scene, as the thesis prints
//! them (`tests/fixtures/thesis/`), parse to the printed values, render (the Figure 13 scene
//! with small stand-ins for its model and map, the Figure 12 job through `render job` with the
//! highest level as each condition's reference), and convert to JSON and back without loss.

mod support;

use proptest::prelude::*;
use renderer::condition::{PointSetKind, TimeFilter};
use renderer::convert::{self, Document};
use renderer::job::line_format;
use renderer::job::{
    IndependentReference, JOB_FORMAT, Job, JobFile, Overrides, Reference, ReferenceSpec,
};
use renderer::progress::NoProgress;
use renderer::render::render_frame;
use renderer::sampling::{
    Density, Randomization, SamplingConfig, SamplingOptions, Scope, SpatialFilter,
};
use renderer::scene::block_format;
use renderer::scene::file::{
    CameraDesc, EnvironmentDesc, FresnelDesc, GroupDesc, InstanceDesc, LightDesc, LightKind,
    MaterialDesc, ObjectDesc, ObjectKind, Scale, SceneFile, SettingsDesc,
};
use renderer::scene::{SCENE_FORMAT, Scene};
use std::path::{Path, PathBuf};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/thesis")
        .join(name)
}

fn read(name: &str) -> String {
    std::fs::read_to_string(fixture(name)).unwrap()
}

/// A folder holding Figure 13's scene (as `name`) and small stand-ins at the paths it names.
fn figure13_folder(name: &str) -> tempfile::TempDir {
    support::figure13_folder(&read("figure13.scene"), name)
}

#[test]
fn figure_12_reads_as_printed() {
    let path = fixture("figure12.job");
    let (job, _) = line_format::read(&read("figure12.job"), &path).unwrap();
    assert_eq!(
        job,
        JobFile {
            format: JOB_FORMAT.into(),
            name: "Plane_scene".into(),
            // No scene line: the scene named after the job file, beside it.
            scenes: vec!["figure12.scene".into()],
            levels: vec![1, 8, 27, 64, 125, 216, 343, 512],
            // `stratifiedmc` is the suite's `stratified`.
            point_sets: vec![
                PointSetKind::Hammersley,
                PointSetKind::Stratified,
                PointSetKind::Poisson,
            ],
            // `box` is the thesis's truncated box (docs/thesis-formats.md).
            time_filters: vec![TimeFilter::TruncatedBox, TimeFilter::Triangle],
            // The thesis's ground truth: the highest level of the same point set and filter.
            reference: ReferenceSpec::HighestLevel,
            seed: line_format::DEFAULT_SEED,
            overrides: Overrides {
                // Every set gets new points and new pixel shifts every frame.
                sampling: SamplingOptions {
                    point_set_scope: Some(Scope::Frame),
                    shift_scope: Some(Scope::Frame),
                    ..Default::default()
                },
                ..Default::default()
            },
            frames_per_unit: None,
        }
    );
}

#[test]
fn figure_13_reads_as_printed() {
    let path = fixture("figure13.scene");
    let (scene, _) = block_format::read(&read("figure13.scene"), &path).unwrap();
    let expected = SceneFile {
        format: SCENE_FORMAT.into(),
        name: Some("planescene".into()),
        description: None,
        materials: vec![MaterialDesc {
            name: "plane_material".into(),
            diffuse: [0.6, 0.85, 1.0],
            specular: [0.3, 0.3, 0.3],
            ambient: [0.05, 0.05, 0.05],
            phong_exponent: 32.0,
            fresnel: Some(FresnelDesc {
                min: 0.3,
                max: 1.0,
                exponent: 2.0,
            }),
        }],
        objects: vec![ObjectDesc {
            // Figure 13's object has no name: the first object block is `object1`.
            name: "object1".into(),
            kind: ObjectKind::Model,
            material: "plane_material".into(),
            file: Some("models/B-727-200.obj".into()),
            radius: None,
            half_extent: None,
            scale: Some(Scale::Uniform(13.0)),
            location: [0.0, 0.0, 420.0],
            velocity: [-1000.0, 0.0, 0.0],
            rotation: [0.0; 3],
            angular_velocity: [0.0; 3],
            hidden: false,
        }],
        instances: vec![],
        groups: vec![],
        lights: vec![],
        camera: CameraDesc {
            location: [400.0, 375.0, 800.0],
            location_velocity: [-600.0, 0.0, 0.0],
            look_at: [300.0, 350.0, 0.0],
            look_at_velocity: [-800.0, 10.0, 0.0],
            up: [0.0, 1.0, 0.0],
            up_velocity: [0.0, 0.0, 0.005],
            fov: 50.0,
        },
        settings: SettingsDesc {
            start_time: -12.5,
            frame_time: 0.12,
            frames: 210,
            fps: 30.0,
            width: 768,
            height: 768,
            ambient_light: [0.7, 0.9, 1.0],
            max_depth: 4,
            environment: Some(EnvironmentDesc {
                file: "data/CedarCity.hdr".into(),
                intensity: 1.0,
                rotation: 0.0,
                negatives: None,
            }),
            exposure: 1.0,
            sampling: SamplingConfig {
                point_set: PointSetKind::Hammersley,
                spp: 64,
                time_filter: TimeFilter::Triangle,
                ..Default::default()
            },
        },
    };
    assert_eq!(scene, expected);
}

#[test]
fn figure_13_renders_with_stand_ins_at_the_paths_it_names() {
    let dir = figure13_folder("plane.scene");
    let mut scene = Scene::load(&dir.path().join("plane.scene")).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert!(scene.has_motion() && scene.has_reflections());
    scene.settings.width = 24;
    scene.settings.height = 24;
    // Frame 0: the stand-in airliner (52 x 13 x 52 at scale 13) is 4600 units ahead of the
    // camera, about 14 degrees off its axis: far too small to cover a pixel at 24 x 24, so
    // the frame is the sky map seen through the camera, reflected in nothing.
    let cfg = SamplingConfig {
        spp: 8,
        ..scene.settings.sampling.clone()
    };
    for frame in [0, 104, 209] {
        let (film, stats) = render_frame(&scene, &cfg, 1, frame, &NoProgress).unwrap();
        assert_eq!(stats.non_finite, 0);
        let lum: Vec<f32> = film.pixels.iter().map(|p| p.x + p.y + p.z).collect();
        assert!(
            lum.iter().all(|v| v.is_finite() && *v > 0.0),
            "frame {frame}"
        );
        let (lo, hi) = lum
            .iter()
            .fold((f32::MAX, 0.0f32), |(a, b), &v| (a.min(v), b.max(v)));
        assert!(
            hi > lo * 1.01,
            "frame {frame}: the sky's gradient shows ({lo}..{hi})"
        );
    }
}

#[test]
fn a_json_job_may_name_text_scenes_and_a_text_job_may_name_json_scenes() {
    let dir = figure13_folder("plane.scene");
    let d = dir.path();
    convert::convert(&d.join("plane.scene"), &d.join("plane.json")).unwrap();
    let json_job = d.join("j.json");
    std::fs::write(
        &json_job,
        r#"{"format": "blurlab-job/1", "name": "j", "scenes": ["plane.scene"],
            "levels": [1, 8], "point_sets": ["random"], "time_filters": ["box"],
            "reference": {"spp": 27}, "seed": 3}"#,
    )
    .unwrap();
    let text_job = d.join("t.job");
    std::fs::write(
        &text_job,
        "t\n2\n1 8\n1\nrandom\n1\nfullbox\nscene plane.json\nreference 27\nseed 3\n\
         pointsetscope scene\nshiftscope scene\n",
    )
    .unwrap();
    let a = Job::load(&json_job).unwrap();
    let b = Job::load(&text_job).unwrap();
    assert_eq!(a.scenes[0].path, d.join("plane.scene"));
    assert_eq!(b.scenes[0].path, d.join("plane.json"));
    assert_eq!(
        (&a.levels, &a.time_filters, &a.reference),
        (&b.levels, &b.time_filters, &b.reference)
    );
    assert!(matches!(a.reference, Reference::Independent(_)));
    // The same scene in either format renders the same pixels.
    let sources_a = renderer::job::scene_source::load_sources(&a)
        .unwrap()
        .sources;
    let sources_b = renderer::job::scene_source::load_sources(&b)
        .unwrap()
        .sources;
    let sampling = SamplingConfig {
        spp: 2,
        ..Default::default()
    };
    let (fa, fb) = (
        sources_a[0]
            .resized(6, 6)
            .unwrap()
            .render(&sampling, 9, 40)
            .unwrap(),
        sources_b[0]
            .resized(6, 6)
            .unwrap()
            .render(&sampling, 9, 40)
            .unwrap(),
    );
    assert_eq!(fa.display, fb.display);
    // --scene replaces a job's scenes.
    let c = Job::load_with_scenes(&text_job, &[d.join("plane.scene")]).unwrap();
    assert_eq!(c.scenes[0].path, d.join("plane.scene"));
}

/// Issue 29: `render convert` writes portable files. The thesis's plane scene converted into
/// folders at other depths, in either format, names its model and sky by relative paths and
/// renders the same pixels as the original.
#[test]
fn converted_scenes_render_the_same_frame_wherever_they_are_written() {
    let original = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/thesis/plane.scene");
    let frame_93 = |path: &Path| {
        let mut scene = Scene::load(path).unwrap();
        scene.settings.width = 8;
        scene.settings.height = 8;
        let cfg = SamplingConfig {
            spp: 2,
            ..scene.settings.sampling.clone()
        };
        render_frame(&scene, &cfg, 1, 93, &NoProgress)
            .unwrap()
            .0
            .pixels
    };
    let want = frame_93(&original);
    let dir = tempfile::tempdir().unwrap();
    let root = std::path::absolute(env!("CARGO_MANIFEST_DIR")).unwrap();
    let root = root.parent().unwrap().to_str().unwrap();
    for out in ["near/plane.json", "far/a/b/plane.json", "far/a/plane.scene"] {
        let out = dir.path().join(out);
        convert::convert(&original, &out).unwrap();
        let text = std::fs::read_to_string(&out).unwrap();
        assert!(
            !['"', ' ']
                .iter()
                .any(|c| text.contains(&format!("{c}{root}"))),
            "{}: an absolute path\n{text}",
            out.display()
        );
        assert_eq!(frame_93(&out), want, "{}", out.display());
    }
}

#[test]
fn the_figures_convert_to_json_and_back_without_loss() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (name, back) in [
        ("figure13.scene", "back.scene"),
        ("figure12.job", "back.job"),
    ] {
        let original = convert::read(&fixture(name)).unwrap();
        std::fs::copy(fixture(name), d.join(name)).unwrap();
        let json = d.join(format!("{name}.json"));
        convert::convert(&d.join(name), &json).unwrap();
        convert::convert(&json, &d.join(back)).unwrap();
        let again = convert::read(&d.join(back)).unwrap();
        assert_eq!(again, original, "{name}");
    }
    // Written back, Figure 13 keeps every line (numbers in shortest form: `1.0` is `1`), and
    // adds the derived object name and a header comment.
    let text = std::fs::read_to_string(d.join("back.scene")).unwrap();
    let shortest = |line: &str| -> Vec<String> {
        line.split_whitespace()
            .map(|w| w.parse::<f32>().map_or(w.to_string(), |v| v.to_string()))
            .collect()
    };
    let written: Vec<Vec<String>> = text.lines().map(shortest).collect();
    for line in read("figure13.scene").lines().filter(|l| !l.is_empty()) {
        assert!(written.contains(&shortest(line)), "lost `{line}`:\n{text}");
    }
    assert!(text.contains("\nobjectname object1\n"), "{text}");
    let job = std::fs::read_to_string(d.join("back.job")).unwrap();
    let seven: Vec<&str> = job
        .lines()
        .filter(|l| !l.starts_with('#'))
        .take(7)
        .collect();
    assert_eq!(seven.join("\n") + "\n", read("figure12.job"));
}

#[test]
fn the_suites_json_files_convert_to_text_and_back_identically() {
    // Every scene and job under scenes/ (the studies' folders also hold designs and observers).
    let is_scene_or_job = |p: &Path| {
        let text = std::fs::read_to_string(p).unwrap();
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        v["format"]
            .as_str()
            .is_some_and(|f| f == SCENE_FORMAT || f == JOB_FORMAT)
    };
    let mut files: Vec<PathBuf> = Vec::new();
    let mut dirs = vec![Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes")];
    while let Some(dir) = dirs.pop() {
        for path in std::fs::read_dir(dir).unwrap().flatten().map(|e| e.path()) {
            if path.is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|e| e == "json") && is_scene_or_job(&path) {
                files.push(path);
            }
        }
    }
    assert!(files.len() >= 9, "{files:?}");
    for path in files {
        let doc = convert::read(&path).unwrap();
        let text_path = path.with_extension(match doc {
            Document::Scene(_) => "scene",
            Document::Job(_) => "job",
        });
        let text = convert::text(&doc, &text_path).unwrap();
        let back = match &doc {
            Document::Scene(_) => Document::Scene(block_format::read(&text, &text_path).unwrap().0),
            Document::Job(_) => Document::Job(line_format::read(&text, &text_path).unwrap().0),
        };
        assert_eq!(back, doc, "{}", path.display());
        let json = |d: &Document| match d {
            Document::Scene(s) => convert::json(s).unwrap(),
            Document::Job(j) => convert::json(j).unwrap(),
        };
        assert_eq!(json(&back), json(&doc), "{}", path.display());
    }
}

// Round trips of arbitrary models: model -> text -> model is the identity, and so is
// model -> JSON -> model -> text, so JSON -> text -> JSON is identical and text -> JSON -> text
// reads back to the same model.

fn finite() -> impl Strategy<Value = f32> {
    prop_oneof![
        any::<f32>().prop_filter("finite", |v| v.is_finite()),
        Just(0.0),
        Just(-0.0),
        (-1000i32..1000).prop_map(|v| v as f32 / 8.0),
    ]
}

fn v3() -> impl Strategy<Value = [f32; 3]> {
    [finite(), finite(), finite()]
}

fn word() -> impl Strategy<Value = String> {
    prop_oneof![
        any::<String>(),
        "[a-z_0-9]{1,8}",
        Just(String::new()),
        Just("a b#\"c\\".into())
    ]
}

fn scale() -> impl Strategy<Value = Option<Scale>> {
    prop::option::of(prop_oneof![
        finite().prop_map(Scale::Uniform),
        v3().prop_map(Scale::PerAxis)
    ])
}

fn material() -> impl Strategy<Value = MaterialDesc> {
    (
        word(),
        v3(),
        v3(),
        v3(),
        finite(),
        prop::option::of((finite(), finite(), finite())),
    )
        .prop_map(
            |(name, diffuse, specular, ambient, phong_exponent, fr)| MaterialDesc {
                name,
                diffuse,
                specular,
                ambient,
                phong_exponent,
                fresnel: fr.map(|(min, max, exponent)| FresnelDesc { min, max, exponent }),
            },
        )
}

/// Location, velocity, rotation, angular velocity, scale.
type Placement = ([f32; 3], [f32; 3], [f32; 3], [f32; 3], Option<Scale>);

fn placement() -> impl Strategy<Value = Placement> {
    (v3(), v3(), v3(), v3(), scale())
}

fn object() -> impl Strategy<Value = ObjectDesc> {
    (
        word(),
        prop_oneof![
            Just(ObjectKind::Model),
            Just(ObjectKind::Sphere),
            Just(ObjectKind::Plane)
        ],
        word(),
        prop::option::of(word()),
        prop::option::of(finite()),
        prop::option::of([finite(), finite()]),
        placement(),
        any::<bool>(),
    )
        .prop_map(
            |(name, kind, material, file, radius, half_extent, p, hidden)| ObjectDesc {
                name,
                kind,
                material,
                file,
                radius,
                half_extent,
                scale: p.4,
                location: p.0,
                velocity: p.1,
                rotation: p.2,
                angular_velocity: p.3,
                hidden,
            },
        )
}

fn instance() -> impl Strategy<Value = InstanceDesc> {
    (word(), word(), prop::option::of(word()), placement()).prop_map(
        |(name, object, material, p)| InstanceDesc {
            name,
            object,
            material,
            scale: p.4,
            location: p.0,
            velocity: p.1,
            rotation: p.2,
            angular_velocity: p.3,
        },
    )
}

fn group() -> impl Strategy<Value = GroupDesc> {
    (word(), prop::collection::vec(word(), 0..3), placement()).prop_map(|(name, children, p)| {
        GroupDesc {
            name,
            children,
            scale: p.4,
            location: p.0,
            velocity: p.1,
            rotation: p.2,
            angular_velocity: p.3,
        }
    })
}

fn light() -> impl Strategy<Value = LightDesc> {
    (
        prop_oneof![Just(LightKind::Point), Just(LightKind::Directional)],
        v3(),
        finite(),
        prop::option::of(v3()),
        prop::option::of(v3()),
    )
        .prop_map(|(kind, color, intensity, position, direction)| LightDesc {
            kind,
            color,
            intensity,
            position,
            direction,
        })
}

fn point_set() -> impl Strategy<Value = PointSetKind> {
    prop::sample::select(PointSetKind::ALL.to_vec())
}

fn time_filter() -> impl Strategy<Value = TimeFilter> {
    prop::sample::select(TimeFilter::ALL.to_vec())
}

fn scope() -> impl Strategy<Value = Option<Scope>> {
    prop::option::of(prop_oneof![Just(Scope::Frame), Just(Scope::Sequence)])
}

fn options() -> impl Strategy<Value = SamplingOptions> {
    (
        prop::option::of(prop_oneof![
            Just(SpatialFilter::Gaussian),
            Just(SpatialFilter::Box)
        ]),
        prop::option::of(any::<f64>().prop_filter("finite", |v| v.is_finite())),
        prop::option::of(prop_oneof![
            Just(Density::Joint),
            any::<u32>().prop_map(Density::Temporal),
            any::<u32>().prop_map(Density::Spatial)
        ]),
        scope(),
        scope(),
        prop::option::of(prop_oneof![
            Just(Randomization::Shift),
            Just(Randomization::Scramble)
        ]),
    )
        .prop_map(
            |(
                spatial_filter,
                spatial_sigma,
                density,
                point_set_scope,
                shift_scope,
                randomization,
            )| {
                SamplingOptions {
                    spatial_filter,
                    spatial_sigma,
                    density,
                    point_set_scope,
                    shift_scope,
                    randomization,
                }
            },
        )
}

fn settings() -> impl Strategy<Value = SettingsDesc> {
    (
        (
            finite(),
            finite(),
            any::<u32>(),
            any::<f64>().prop_filter("finite", |v| v.is_finite()),
        ),
        (any::<u32>(), any::<u32>(), v3(), any::<u32>(), finite()),
        prop::option::of((word(), finite(), finite())),
        (point_set(), any::<u32>(), time_filter(), options()),
    )
        .prop_map(|(t, size, env, sampling)| SettingsDesc {
            start_time: t.0,
            frame_time: t.1,
            frames: t.2,
            fps: t.3,
            width: size.0,
            height: size.1,
            ambient_light: size.2,
            max_depth: size.3,
            exposure: size.4,
            environment: env.map(|(file, intensity, rotation)| EnvironmentDesc {
                file,
                intensity,
                rotation,
                negatives: None,
            }),
            sampling: SamplingConfig {
                point_set: sampling.0,
                spp: sampling.1,
                time_filter: sampling.2,
                ..Default::default()
            }
            .with_options(&sampling.3),
        })
}

fn scene_file() -> impl Strategy<Value = SceneFile> {
    (
        prop::option::of(word()),
        prop::option::of(word()),
        prop::collection::vec(material(), 0..3),
        prop::collection::vec(object(), 0..3),
        prop::collection::vec(instance(), 0..2),
        prop::collection::vec(group(), 0..2),
        prop::collection::vec(light(), 0..2),
        (v3(), v3(), v3(), v3(), v3(), v3(), finite()),
        settings(),
    )
        .prop_map(
            |(name, description, materials, objects, instances, groups, lights, c, settings)| {
                SceneFile {
                    format: SCENE_FORMAT.into(),
                    name,
                    description,
                    materials,
                    objects,
                    instances,
                    groups,
                    lights,
                    camera: CameraDesc {
                        location: c.0,
                        location_velocity: c.1,
                        look_at: c.2,
                        look_at_velocity: c.3,
                        up: c.4,
                        up_velocity: c.5,
                        fov: c.6,
                    },
                    settings,
                }
            },
        )
}

fn job_file() -> impl Strategy<Value = JobFile> {
    (
        word(),
        prop::collection::vec(word(), 1..3),
        prop::collection::vec(any::<u32>(), 1..5),
        prop::collection::vec(point_set(), 1..4),
        prop::collection::vec(time_filter(), 1..3),
        prop_oneof![
            Just(ReferenceSpec::HighestLevel),
            (
                any::<u32>(),
                prop::option::of(point_set()),
                prop::option::of(time_filter())
            )
                .prop_map(|(spp, point_set, time_filter)| ReferenceSpec::Independent(
                    IndependentReference {
                        spp,
                        point_set,
                        time_filter
                    }
                ))
        ],
        any::<u64>(),
        (
            prop::option::of(any::<u32>()),
            prop::option::of(any::<u32>()),
            prop::option::of(any::<u32>()),
            prop::option::of(any::<u32>()),
            prop::option::of(any::<bool>()),
            options(),
        ),
        prop::option::of(any::<u32>()),
    )
        .prop_map(
            |(name, scenes, levels, point_sets, time_filters, reference, seed, o, fpu)| JobFile {
                format: JOB_FORMAT.into(),
                name,
                scenes,
                levels,
                point_sets,
                time_filters,
                reference,
                seed,
                overrides: Overrides {
                    width: o.0,
                    height: o.1,
                    frames: o.2,
                    first_frame: o.3,
                    exr: o.4,
                    sampling: o.5,
                },
                frames_per_unit: fpu,
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn scenes_round_trip(scene in scene_file()) {
        let path = Path::new("p.scene");
        let text = block_format::write(&scene).unwrap();
        let (back, _) = block_format::read(&text, path).unwrap();
        prop_assert_eq!(&back, &scene);
        prop_assert_eq!(block_format::write(&back).unwrap(), text, "the writer is deterministic");
        let json = convert::json(&scene).unwrap();
        let from_json: SceneFile = serde_json::from_str(&json).unwrap();
        let again = block_format::read(&block_format::write(&from_json).unwrap(), path).unwrap().0;
        prop_assert_eq!(convert::json(&again).unwrap(), convert::json(&from_json).unwrap());
    }

    #[test]
    fn jobs_round_trip(job in job_file()) {
        let path = Path::new("p.job");
        let text = line_format::write(&job).unwrap();
        let (back, _) = line_format::read(&text, path).unwrap();
        prop_assert_eq!(&back, &job);
        prop_assert_eq!(line_format::write(&back).unwrap(), text, "the writer is deterministic");
        let json = convert::json(&job).unwrap();
        let from_json: JobFile = serde_json::from_str(&json).unwrap();
        let again = line_format::read(&line_format::write(&from_json).unwrap(), path).unwrap().0;
        prop_assert_eq!(convert::json(&again).unwrap(), json);
    }
}

/// `scenes/thesis/` holds each thesis scene in both formats and the thesis job in both: the text
/// twin must read to exactly the JSON model (the thesis job's text twin names the `.scene`
/// twins), so there is one definition per scene whichever file a user picks.
#[test]
fn the_thesis_files_in_both_formats_are_one_definition() {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    for name in ["plane", "spheres"] {
        let dir = scenes.join("thesis");
        let text = convert::read(&dir.join(format!("{name}.scene"))).unwrap();
        let json = convert::read(&dir.join(format!("{name}.json"))).unwrap();
        assert_eq!(text, json, "{name}.scene and {name}.json differ");
    }
    let (Document::Job(text), Document::Job(mut json)) = (
        convert::read(&scenes.join("thesis/job.job")).unwrap(),
        convert::read(&scenes.join("thesis/job.json")).unwrap(),
    ) else {
        panic!("not jobs");
    };
    for s in &mut json.scenes {
        *s = s.replace(".json", ".scene");
    }
    assert_eq!(text, json);
    // plane.job is Figure 12 as printed (its comments aside), and plane.scene is Figure 13 line
    // for line plus the additions its header names.
    let job = std::fs::read_to_string(scenes.join("thesis/plane.job")).unwrap();
    let lines: Vec<&str> = job.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(lines.join("\n") + "\n", read("figure12.job"));
    let scene = std::fs::read_to_string(scenes.join("thesis/plane.scene")).unwrap();
    let printed = read("figure13.scene");
    let figure: Vec<&str> = printed.lines().filter(|l| !l.is_empty()).collect();
    let ours: Vec<&str> = scene
        .lines()
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .filter(|l| !l.starts_with("objectname ") && !l.starts_with("description "))
        .collect();
    let light = ours.iter().position(|l| *l == "light").unwrap();
    let without_light: Vec<&str> = ours[..light]
        .iter()
        .chain(&ours[light + 6..])
        .copied()
        .collect();
    assert_eq!(without_light, figure);
}
