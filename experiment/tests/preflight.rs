//! Preflight on real rendered stimuli (the job runner on synthetic scenes): a clean set passes;
//! a missing frame, a frame of the wrong size, changed frame content and a stimulus the job never
//! rendered are each reported, all at once, naming the stimulus and the file.

use experiment::Design;
use experiment::fixture::{StudySpec, write_study, write_study_with_reference};
use experiment::preflight::{PreflightOptions, needed_stimuli, preflight};
use renderer::progress::NoProgress;
use std::path::Path;

const FULL: PreflightOptions = PreflightOptions { check_hashes: true };

fn frame(stimuli: &Path, id: &str, f: u32) -> std::path::PathBuf {
    stimuli.join(id).join(format!("frame_{f:04}.png"))
}

#[test]
fn clean_stimuli_pass_and_every_needed_video_is_checked() {
    let dir = tempfile::tempdir().unwrap();
    let study = write_study(dir.path(), &StudySpec::tiny()).unwrap();
    let design = Design::load(&study.design_path).unwrap();
    let report = preflight(&design, FULL, &NoProgress);
    assert!(report.problems.is_empty(), "{:?}", report.problems);
    // 2 scenes x (1 reference + 2 point sets x 2 levels).
    assert_eq!(needed_stimuli(&design).len(), 2 * (1 + 4));
    assert_eq!(report.stimuli_checked, 10);
    assert_eq!(report.frames_checked, 10 * 6);
    assert!(report.bytes_hashed > 0);
    report.into_result().unwrap();
}

/// The thesis's ground truth: stimuli rendered with the job reference `highest_level` and a
/// design comparing each condition against its highest level. Preflight checks the highest
/// level once, as a test stimulus; its trials show the same video in all four places; the
/// manifest measured every other level against the same video the design shows beside it.
#[test]
fn highest_level_references_pass_preflight_and_show_identical_pairs_at_the_top() {
    let dir = tempfile::tempdir().unwrap();
    let spec = StudySpec {
        design: serde_json::json!({"repeats": 2, "reference": "highest_level"}),
        ..StudySpec::tiny()
    };
    let study =
        write_study_with_reference(dir.path(), &spec, serde_json::json!("highest_level")).unwrap();
    let design = Design::load(&study.design_path).unwrap();
    let report = preflight(&design, FULL, &NoProgress);
    assert!(report.problems.is_empty(), "{:?}", report.problems);
    // 2 scenes x 2 point sets x 2 levels, no separate reference.
    assert_eq!(needed_stimuli(&design).len(), 8);
    let manifest = report.into_result().unwrap();
    assert!(manifest.stimuli.iter().all(|s| !s.reference));
    let plan = experiment::trials::plan(&design, "s01");
    for t in &plan.main {
        let test = manifest.get(&t.test_stimulus).unwrap();
        assert_eq!(
            test.reference_id.as_deref(),
            Some(t.reference_stimulus.as_str())
        );
        let same = t.test_stimulus == t.reference_stimulus;
        assert_eq!(same, t.level == 8, "{}", t.test_stimulus);
        assert_eq!(test.error.is_none(), same, "{}", t.test_stimulus);
    }
}

#[test]
fn missing_frame_wrong_size_wrong_hash_and_unrendered_level_are_all_listed() {
    let dir = tempfile::tempdir().unwrap();
    let study = write_study(dir.path(), &StudySpec::tiny()).unwrap();
    let s = &study.stimuli_dir;
    // 1. A missing frame.
    std::fs::remove_file(frame(s, "alpha-random-box-0001", 2)).unwrap();
    // 2. A frame of another size (a valid PNG, 5x5).
    let small = image::RgbImage::from_pixel(5, 5, image::Rgb([1, 2, 3]));
    small.save(frame(s, "beta-reference", 0)).unwrap();
    // 3. Same size, one pixel changed: only the hash can tell.
    let p = frame(s, "alpha-stratified-box-0008", 4);
    let mut img = image::open(&p).unwrap().into_rgb8();
    let px = img.get_pixel_mut(3, 3);
    px[0] = px[0].wrapping_add(1);
    img.save(&p).unwrap();
    // 4. The design asks for a level the job never rendered.
    let mut d: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&study.design_path).unwrap()).unwrap();
    d["levels"] = serde_json::json!([1, 8, 64]);
    std::fs::write(&study.design_path, d.to_string()).unwrap();

    let design = Design::load(&study.design_path).unwrap();
    let report = preflight(&design, FULL, &NoProgress);
    let text: Vec<String> = report.problems.iter().map(|p| p.to_string()).collect();
    let has = |needle: &str, what: &str| {
        assert!(
            text.iter().any(|t| t.contains(needle) && t.contains(what)),
            "no problem with {needle:?} and {what:?} in {text:#?}"
        )
    };
    has("alpha-random-box-0001", "missing: frame 2");
    has("beta-reference", "wrong size: frame 0");
    has("beta-reference", "5x5; the manifest says 24x16");
    has("alpha-stratified-box-0008", "content hash");
    // Four 64-spp stimuli were never rendered.
    assert_eq!(
        text.iter()
            .filter(|t| t.contains("not in the manifest"))
            .count(),
        4
    );
    let err = format!("{:#}", report.into_result().unwrap_err());
    assert!(err.contains("no session was started"), "{err}");
}

#[test]
fn without_hashes_sizes_and_missing_frames_are_still_checked() {
    let dir = tempfile::tempdir().unwrap();
    let study = write_study(dir.path(), &StudySpec::tiny()).unwrap();
    let s = &study.stimuli_dir;
    std::fs::remove_file(frame(s, "beta-random-box-0008", 5)).unwrap();
    let p = frame(s, "alpha-reference", 1);
    let mut img = image::open(&p).unwrap().into_rgb8();
    img.get_pixel_mut(0, 0)[1] ^= 0xff;
    img.save(&p).unwrap();
    let design = Design::load(&study.design_path).unwrap();
    let report = preflight(
        &design,
        PreflightOptions {
            check_hashes: false,
        },
        &NoProgress,
    );
    assert_eq!(report.problems.len(), 1, "{:?}", report.problems);
    assert!(
        report.problems[0]
            .to_string()
            .contains("beta-random-box-0008")
    );
    assert_eq!(report.bytes_hashed, 0);
}

#[test]
fn a_missing_manifest_is_one_clear_problem() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("d.json");
    std::fs::write(
        &path,
        r#"{"format": "blurlab-design/1", "name": "x", "manifest": "nowhere/manifest.json",
            "factors": {"scenes": ["a"], "point_sets": ["sobol"], "time_filters": ["box"]},
            "levels": [1], "seed": {"master": 1}}"#,
    )
    .unwrap();
    let report = preflight(&Design::load(&path).unwrap(), FULL, &NoProgress);
    assert_eq!(report.problems.len(), 1);
    assert!(
        report.problems[0]
            .message
            .contains("render the stimuli first")
    );
}
