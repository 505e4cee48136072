//! Property tests of the renderer's readers (issue 16): scene JSON, the thesis's `.scene`
//! and `.job` texts, job JSON, manifests, OBJ models and environment maps, fed arbitrary
//! bytes and valid files with a few edits ([`mutate`]), end in `Ok` or an error naming the
//! file and a line, field or key — never a panic. Seeds are proptest's (fixed per test name,
//! failures saved under `proptest-regressions/`).

#[path = "../../tests/support/mutate.rs"]
mod mutate;

use mutate::{apply, assert_located, cases, edits};
use proptest::prelude::*;
use renderer::job::Job;
use renderer::manifest::Manifest;
use renderer::scene::Scene;
use std::path::{Path, PathBuf};

/// The corpus's folder of valid files (a triangle model the scenes below use).
fn valid() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/corpus/valid")
}

fn read(rel: &str) -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel)).unwrap()
}

/// The thesis's plane scene text, with the corpus's triangle for its model and no sky (so
/// that a case reads no large file).
fn plane_scene() -> String {
    read("scenes/thesis/plane.scene")
        .replace("models/B-727-200.obj", "triangle.obj")
        .replace("envmap data/CedarCity.hdr\n", "")
}

/// Write `bytes` as `name` in a fresh folder beside copies of the valid files, and read it
/// with `load`; an error must be located.
fn load_file<T>(name: &str, bytes: &[u8], load: impl Fn(&Path) -> anyhow::Result<T>) {
    let dir = tempfile::tempdir().unwrap();
    for f in ["scene.json", "triangle.obj"] {
        std::fs::copy(valid().join(f), dir.path().join(f)).unwrap();
    }
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    if let Err(e) = load(&path) {
        assert_located(&format!("{e:#}"), name);
    }
}

fn scene_text(bytes: &[u8], name: &str) {
    let path = valid().join(name);
    let text = String::from_utf8_lossy(bytes);
    let r = if name.ends_with(".scene") {
        Scene::from_block_text(&text, &path)
    } else {
        Scene::from_json(&text, &path)
    };
    if let Err(e) = r {
        assert_located(&format!("{e:#}"), name);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(256)))]

    #[test]
    fn scene_json_never_panics(e in edits(6)) {
        let base = std::fs::read(valid().join("scene.json")).unwrap();
        scene_text(&apply(&base, &e), "fuzz.json");
    }

    #[test]
    fn scene_text_never_panics(e in edits(6)) {
        scene_text(&apply(plane_scene().as_bytes(), &e), "fuzz.scene");
    }

    #[test]
    fn arbitrary_bytes_as_scenes_never_panic(b in prop::collection::vec(any::<u8>(), 0..600)) {
        scene_text(&b, "fuzz.json");
        scene_text(&b, "fuzz.scene");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(96)))]

    #[test]
    fn job_files_never_panic(e in edits(6), text_job in any::<bool>()) {
        let (name, base) = if text_job {
            let job = read("scenes/thesis/plane.job") + "scene scene.json\n";
            ("fuzz.job", job)
        } else {
            ("fuzz.json", read("scenes/demo/job.json").replace("../thesis/plane.json", "scene.json")
                .replace("\"../thesis/spheres.json\"", "\"scene.json\""))
        };
        load_file(name, &apply(base.as_bytes(), &e), Job::load);
    }

    #[test]
    fn manifests_never_panic(e in edits(6)) {
        let m = r#"{"format": "blurlab-manifest/1", "job": "j", "stimuli": [{"id": "a-b-c-8",
            "scene": "a", "point_set": "sobol", "time_filter": "box", "spp": 8, "reference": false,
            "seed": 1, "width": 4, "height": 4, "frames": 1, "fps": 30.0,
            "frame_paths": ["a/0.png"], "content_hash": "00", "render_seconds": 0.5}]}"#;
        load_file("manifest.json", &apply(m.as_bytes(), &e), Manifest::load);
    }

    #[test]
    fn obj_models_never_panic(e in edits(8)) {
        let obj = "# a quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1 4//1\n";
        load_file("fuzz.obj", &apply(obj.as_bytes(), &e), |p| {
            renderer::geometry::TriangleMesh::from_obj(p).map_err(anyhow::Error::from)
        });
    }

    #[test]
    fn arbitrary_bytes_as_obj_jobs_and_manifests_never_panic(
        b in prop::collection::vec(any::<u8>(), 0..400)
    ) {
        load_file("fuzz.obj", &b, |p| {
            renderer::geometry::TriangleMesh::from_obj(p).map_err(anyhow::Error::from)
        });
        load_file("fuzz.job", &b, Job::load);
        load_file("fuzz.json", &b, Job::load);
        load_file("manifest.json", &b, Manifest::load);
    }
}

/// A small valid Radiance HDR map (flat RLE-free scanlines), and an EXR written by the suite.
fn hdr_bytes() -> Vec<u8> {
    let mut b = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 4\n".to_vec();
    for i in 0..16u8 {
        b.extend_from_slice(&[100 + i, 90, 80, 129]);
    }
    b
}

fn exr_bytes() -> Vec<u8> {
    let px: Vec<[f32; 3]> = (0..16).map(|i| [i as f32, 1.0, 0.5]).collect();
    renderer::frame_io::exr::exr_bytes(&px, 4, 4).unwrap()
}

fn load_map(name: &str, bytes: &[u8]) {
    load_file(name, bytes, |p| {
        renderer::environment::Environment::load(p, 1.0, 0.0, None).map(drop)
    });
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(128)))]

    #[test]
    fn environment_maps_never_panic(e in edits(4), exr in any::<bool>()) {
        if exr {
            load_map("sky.exr", &apply(&exr_bytes(), &e));
        } else {
            load_map("sky.hdr", &apply(&hdr_bytes(), &e));
        }
    }

    #[test]
    fn arbitrary_bytes_as_maps_never_panic(b in prop::collection::vec(any::<u8>(), 0..400)) {
        load_map("sky.exr", &b);
        load_map("sky.hdr", &b);
    }
}

#[test]
fn the_valid_bases_are_valid() {
    Scene::from_block_text(&plane_scene(), &valid().join("fuzz.scene")).unwrap();
    Scene::load(&valid().join("scene.json")).unwrap();
    load_map("sky.hdr", &hdr_bytes());
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("sky.exr");
    std::fs::write(&p, exr_bytes()).unwrap();
    renderer::environment::Environment::load(&p, 1.0, 0.0, None).unwrap();
}
