//! Property test of the analysis's own reader (issue 16): counts tables (`analyze table.csv`),
//! and session logs as `analyze` reads them (checks included), fed arbitrary bytes and valid
//! files with a few edits ([`mutate`]), end in `Ok` or an error naming the file and a line,
//! field or key — never a panic.

#[path = "../../tests/support/mutate.rs"]
mod mutate;

use analysis::data::Dataset;
use mutate::{apply, assert_located, cases, edits};
use proptest::prelude::*;

const COUNTS: &str = "subject,scene,point_set,time_filter,level,correct,trials\n\
s01,plane,hammersley,box,8,3,4\ns01,plane,hammersley,box,27,4,4\n\
s02,plane,hammersley,box,8,2,4\ns02,plane,hammersley,box,27,4,4\n";

fn analyze_file(name: &str, bytes: &[u8], lenient: bool) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    if let Err(e) = Dataset::read_checked(&[path], None, lenient) {
        assert_located(&format!("{e:#}"), name);
    }
}

fn log_bytes() -> Vec<u8> {
    let header = r#"{"kind": "header", "format": "blurlab-session/1", "subject": "s01", "session": 1, "design": "demo", "design_hash": "ab", "seed": 3, "app_version": "blurlab 0.1.0", "mode": "gui", "started_unix": 0.0, "trials_planned": 2}"#;
    let trial = |i: u32, r: u32| {
        format!(
            r#"{{"kind": "trial", "index": {i}, "practice": false, "scene": "plane", "point_set": "hammersley", "time_filter": "box", "level": 8, "test_stimulus": "t", "reference_stimulus": "r", "diff_pair": 1, "test_side": "left", "response": {r}, "correct": {}, "rt_ms": 500.0}}"#,
            r == 1
        )
    };
    format!("{header}\n{}\n{}\n", trial(0, 1), trial(1, 2)).into_bytes()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(256)))]

    #[test]
    fn counts_tables_never_panic(e in edits(6)) {
        analyze_file("counts.csv", &apply(COUNTS.as_bytes(), &e), false);
    }

    #[test]
    fn logs_as_analyzed_never_panic(e in edits(6), lenient in any::<bool>()) {
        analyze_file("s01.jsonl", &apply(&log_bytes(), &e), lenient);
    }

    #[test]
    fn arbitrary_bytes_never_panic(b in prop::collection::vec(any::<u8>(), 0..400)) {
        analyze_file("counts.csv", &b, false);
        analyze_file("s01.jsonl", &b, true);
    }
}

#[test]
fn the_valid_bases_are_valid() {
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes) in [
        ("counts.csv", COUNTS.as_bytes().to_vec()),
        ("s01.jsonl", log_bytes()),
    ] {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        Dataset::read_checked(&[path], None, false).unwrap();
    }
}
