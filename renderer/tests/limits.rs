//! A job's overrides are held to the scene's own size limit (`renderer::limits`,
//! docs/limits.md); the command line's limits are tested with the binary, in the root
//! package's `tests/render_cli.rs`.

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
