//! Property tests of the experiment's readers (issue 16): designs, observers, predictions and
//! session logs, fed arbitrary bytes and valid files with a few edits ([`mutate`]), end in
//! `Ok` or an error naming the file and a line, field or key — never a panic.

#[path = "../../tests/support/mutate.rs"]
mod mutate;

use experiment::log::SessionLog;
use experiment::predicted::PredictedTable;
use experiment::{Design, Observer};
use mutate::{apply, assert_located, cases, edits};
use proptest::prelude::*;
use std::path::Path;

fn read(rel: &str) -> Vec<u8> {
    std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel)).unwrap()
}

/// Read `bytes` as the file `name` with `load`; an error must be located.
fn load_file<T>(name: &str, bytes: &[u8], load: impl Fn(&Path) -> anyhow::Result<T>) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    if let Err(e) = load(&path) {
        assert_located(&format!("{e:#}"), name);
    }
}

/// A valid two-trial log of the corpus's shape.
fn log_bytes() -> Vec<u8> {
    let header = r#"{"kind": "header", "format": "blurlab-session/1", "subject": "s01", "session": 1, "design": "demo", "design_hash": "ab", "seed": 3, "app_version": "blurlab 0.1.0", "mode": "gui", "started_unix": 0.0, "trials_planned": 2}"#;
    let trial = |i: u32| {
        format!(
            r#"{{"kind": "trial", "index": {i}, "practice": false, "scene": "plane", "point_set": "hammersley", "time_filter": "box", "level": 8, "test_stimulus": "plane-hammersley-box-8", "reference_stimulus": "plane-reference", "diff_pair": 1, "test_side": "left", "response": 1, "correct": true, "rt_ms": 500.0}}"#
        )
    };
    format!("{header}\n{}\n{}\n", trial(0), trial(1)).into_bytes()
}

fn predicted_bytes() -> Vec<u8> {
    b"# format: blurlab-predicted/1\nscene,point_set,time_filter,spp,test_stimulus,reference_stimulus,q,k,d_prime,p_correct,p_frame_min,p_frame_median,p_frame_max,frames\nplane,hammersley,box,8,plane-hammersley-box-8,plane-reference,1.0,1.0,1.0,0.7,0.6,0.7,0.8,6\n".to_vec()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(256)))]

    #[test]
    fn designs_never_panic(e in edits(6)) {
        load_file("design.json", &apply(&read("scenes/demo/design.json"), &e), Design::load);
    }

    #[test]
    fn observers_never_panic(e in edits(6)) {
        load_file("observer.json", &apply(&read("scenes/thesis/observer.json"), &e), Observer::load);
    }

    #[test]
    fn predictions_never_panic(e in edits(6)) {
        load_file("predicted.csv", &apply(&predicted_bytes(), &e), PredictedTable::load);
    }

    #[test]
    fn session_logs_never_panic(e in edits(6)) {
        load_file("s01.jsonl", &apply(&log_bytes(), &e), SessionLog::read);
    }

    #[test]
    fn arbitrary_bytes_never_panic(b in prop::collection::vec(any::<u8>(), 0..400)) {
        load_file("design.json", &b, Design::load);
        load_file("observer.json", &b, Observer::load);
        load_file("predicted.csv", &b, PredictedTable::load);
        load_file("s01.jsonl", &b, SessionLog::read);
    }
}

#[test]
fn the_valid_bases_are_valid() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("s01.jsonl");
    std::fs::write(&log, log_bytes()).unwrap();
    assert_eq!(SessionLog::read(&log).unwrap().trials.len(), 2);
    let p = dir.path().join("predicted.csv");
    std::fs::write(&p, predicted_bytes()).unwrap();
    PredictedTable::load(&p).unwrap();
    let obs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/thesis/observer.json");
    Observer::load(&obs).unwrap();
}
