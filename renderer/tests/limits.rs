//! The same limits wherever a number enters (`renderer::limits`, docs/limits.md): the command
//! line refuses sizes and sample counts out of range, negative numbers included, with a message
//! saying what was expected (before: an abort allocating 120 GB, or clap's `-- -1` hint), and a
//! job's overrides are held to the scene's own size limit.

use std::process::Command;

fn render_err(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_render"))
        .args(args)
        .output()
        .unwrap();
    assert!(!out.status.success(), "render {args:?} succeeded");
    assert_eq!(
        out.status.code(),
        Some(2),
        "render {args:?}: not a usage error"
    );
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn command_line_sizes_and_counts_are_bounded() {
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/static.json");
    let out = std::env::temp_dir().join("blurlab-limits-never-written");
    let o = out.to_str().unwrap();
    for (flag, value, expected) in [
        ("--width", "100000", "from 1 to 16384"),
        ("--height", "-5", "from 1 to 16384"),
        ("--spp", "-1", "samples per pixel from 1 to 65536"),
        ("--spp", "1000000", "samples per pixel from 1 to 65536"),
        ("--frames", "-1..1", "frame numbers from 0"),
    ] {
        let err = render_err(&["scene", scene, "--out", o, flag, value]);
        assert!(err.contains(expected), "{flag} {value}: {err}");
        assert!(!err.contains("-- -"), "{flag} {value}: clap's hint: {err}");
    }
    assert!(!out.exists());
}

#[test]
fn job_overrides_are_held_to_the_image_size_limit() {
    let dir = tempfile::tempdir().unwrap();
    let job = dir.path().join("big.json");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/static.json");
    std::fs::write(
        &job,
        serde_json::json!({
            "format": "blurlab-job/1", "name": "big", "scenes": [scene],
            "levels": [1], "point_sets": ["random"], "time_filters": ["box"],
            "reference": {"spp": 4}, "seed": 1, "overrides": {"width": 100000}
        })
        .to_string(),
    )
    .unwrap();
    let err = format!("{:#}", renderer::job::Job::load(&job).unwrap_err());
    assert!(
        err.contains("big.json") && err.contains("overrides.width") && err.contains("16384"),
        "{err}"
    );
}
