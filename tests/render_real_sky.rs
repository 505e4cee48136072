//! `blurlab render job --asset CedarCity.hdr=PATH`: the thesis's plane scene rendered under the user's
//! copy of the thesis's sky instead of the stand-in, recorded by hash in the manifest. The copy
//! is never part of the project: the test uses `$BLURLAB_TEST_ASSETS/CedarCity.hdr` and is
//! skipped without it.

use renderer::digest::sha256_hex;
use renderer::manifest::Manifest;
use std::path::{Path, PathBuf};
use std::process::Command;

#[path = "support/test_assets.rs"]
mod test_assets;

const BLURLAB: &str = env!("CARGO_BIN_EXE_blurlab");

/// A one-frame, 32 x 32 job of the thesis's plane scene at a sun-facing frame, where the sky
/// fills most of the view.
fn job(dir: &Path) -> PathBuf {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/thesis/plane.json");
    let text = format!(
        r#"{{"format": "blurlab-job/1", "name": "sky", "scenes": [{scene:?}],
            "levels": [8], "point_sets": ["stratified"], "time_filters": ["truncated_box"],
            "reference": "highest_level", "seed": 3,
            "overrides": {{"width": 32, "height": 32, "frames": 1, "first_frame": 148}}}}"#,
        scene = scene.display().to_string()
    );
    let path = dir.join("job.json");
    std::fs::write(&path, text).unwrap();
    path
}

fn render_job(job: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    Command::new(BLURLAB)
        .args([
            "render",
            "job",
            job.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .arg("--no-progress")
        .args(extra)
        .output()
        .unwrap()
}

fn frame(out: &Path, m: &Manifest) -> image::RgbImage {
    let path = out.join("sky").join(&m.stimuli[0].frame_paths[0]);
    image::open(path).unwrap().to_rgb8()
}

#[test]
fn the_user_s_cedar_city_map_replaces_the_stand_in_and_is_recorded_by_hash() {
    let Some(sky) = test_assets::asset("CedarCity.hdr") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let job = job(dir.path());
    let (stand_in, real) = (dir.path().join("stand_in"), dir.path().join("real"));
    let flag = format!("CedarCity.hdr={}", sky.display());
    for (out, extra) in [(&stand_in, vec![]), (&real, vec!["--asset", flag.as_str()])] {
        let o = render_job(&job, out, &extra);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let (a, b) = (
        Manifest::load(&stand_in.join("sky")).unwrap(),
        Manifest::load(&real.join("sky")).unwrap(),
    );
    assert!(a.assets.is_empty());
    assert_eq!(b.assets.len(), 1);
    assert_eq!(b.assets[0].name, "CedarCity.hdr");
    assert_eq!(
        b.assets[0].sha256,
        sha256_hex(&std::fs::read(&sky).unwrap())
    );
    // Two different skies: most pixels of the view, which is mostly sky and desert at this
    // frame, differ by more than the 8-spp noise of either (a few levels of 255).
    let (fa, fb) = (frame(&stand_in, &a), frame(&real, &b));
    let differ = fa
        .pixels()
        .zip(fb.pixels())
        .filter(|(p, q)| (0..3).any(|c| p[c].abs_diff(q[c]) > 24))
        .count();
    assert!(differ * 2 > 32 * 32, "{differ} of 1024 pixels differ");
}

#[test]
fn a_file_that_is_no_lat_long_radiance_map_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let job = job(dir.path());
    let obj = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/thesis/models/B-727-200.obj");
    let flag = format!("CedarCity.hdr={}", obj.display());
    let o = render_job(&job, &dir.path().join("out"), &["--asset", &flag]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("B-727-200.obj") && err.contains("#?RADIANCE"),
        "{err}"
    );
    assert!(!dir.path().join("out/sky").exists());
}
