//! `blurlab predict` checks its frames against the manifest as `run`'s preflight does (issue
//! 29): a test frame swapped for another file of the same size, a zeroed `content_hash` and a
//! `frames` that disagrees with the frame list are each refused, naming the stimulus; the study
//! as rendered passes. The stimuli are the experiment crate's tiny rendered study.

use experiment::fixture::{StudySpec, write_study};
use renderer::manifest::Manifest;
use serde_json::Value;
use std::path::Path;

/// Edit the manifest's JSON in place.
fn edit(stimuli: &Path, change: impl Fn(&mut Value)) {
    let path = stimuli.join("manifest.json");
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    change(&mut v);
    std::fs::write(&path, serde_json::to_string_pretty(&v).unwrap()).unwrap();
}

/// The error of checking the first test stimulus, or `None` when it passes.
fn check(stimuli: &Path) -> Option<String> {
    let m = Manifest::load(&stimuli.join("manifest.json")).unwrap();
    let test = m.stimuli.iter().find(|s| !s.reference).unwrap().id.clone();
    analysis::predict::preflight::check(&m, stimuli, &[&test])
        .err()
        .map(|e| format!("{e:#}"))
}

#[test]
fn frames_that_disagree_with_the_manifest_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let study = write_study(dir.path(), &StudySpec::tiny()).unwrap();
    let stimuli = &study.stimuli_dir;
    assert_eq!(check(stimuli), None);
    let original = std::fs::read_to_string(stimuli.join("manifest.json")).unwrap();
    let restore = || std::fs::write(stimuli.join("manifest.json"), &original).unwrap();
    let first_test = |v: &mut Value| -> usize {
        let list = v["stimuli"].as_array().unwrap();
        list.iter().position(|s| s["reference"] == false).unwrap()
    };

    edit(stimuli, |v| {
        let i = first_test(v);
        v["stimuli"][i]["content_hash"] = Value::from("0".repeat(64));
    });
    let e = check(stimuli).expect("a zeroed content_hash is refused");
    assert!(e.contains("content hash of the frames is") && e.contains("nothing was predicted"));
    restore();

    edit(stimuli, |v| {
        let i = first_test(v);
        v["stimuli"][i]["frames"] = Value::from(5);
    });
    let e = check(stimuli).expect("frames against the frame list");
    assert!(e.contains("says 5 frames but lists 6 frame files"), "{e}");
    restore();

    // Frame 0 of the test replaced by frame 1 of the same size: only the hash can tell.
    let m = Manifest::load(&stimuli.join("manifest.json")).unwrap();
    let s = m.stimuli.iter().find(|s| !s.reference).unwrap();
    let [a, b] = [0, 1].map(|f| stimuli.join(&s.frame_paths[f]));
    std::fs::copy(&b, &a).unwrap();
    let e = check(stimuli).expect("a swapped frame is refused");
    assert!(e.contains(&s.id) && e.contains("content hash"), "{e}");
}
