//! `analyze` checks every main trial of the logs before it counts (analysis::validate): each
//! edited field is an error naming file, line and field; `--lenient` leaves the trial out with
//! a counted warning instead.

use analysis::data::Dataset;
use experiment::simulate::simulate;
use experiment::{Design, Observer};
use std::path::{Path, PathBuf};

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(p)
}

/// One simulated subject of the demo design (copied into `dir` with a manifest of its
/// stimuli beside it, so that the manifest check runs); returns the log's path and lines.
fn one_log(dir: &Path) -> (PathBuf, Vec<String>, Design) {
    let text = std::fs::read_to_string(repo("scenes/demo/design.json")).unwrap();
    let copy = dir.join("design.json");
    std::fs::write(
        &copy,
        text.replace("../../stimuli/demo/manifest.json", "manifest.json"),
    )
    .unwrap();
    let design = Design::load(&copy).unwrap();
    let observer = Observer::load(&repo("scenes/thesis/observer.json")).unwrap();
    let log = simulate(&design, &observer, 1, &dir.join("sessions"))
        .unwrap()
        .remove(0);
    let lines: Vec<String> = std::fs::read_to_string(&log)
        .unwrap()
        .lines()
        .map(str::to_string)
        .collect();
    write_manifest(&dir.join("manifest.json"), &lines, |_| {});
    (log, lines, design)
}

/// A manifest listing every stimulus the log's trials name, as rendered for their condition;
/// `edit` may change an entry first.
fn write_manifest(path: &Path, lines: &[String], edit: impl Fn(&mut serde_json::Value)) {
    let mut stimuli = std::collections::BTreeMap::new();
    for l in lines {
        let v: serde_json::Value = serde_json::from_str(l).unwrap();
        if v["kind"] != "trial" {
            continue;
        }
        for (key, reference) in [("test_stimulus", false), ("reference_stimulus", true)] {
            let id = v[key].as_str().unwrap().to_string();
            let mut s = serde_json::json!({
                "id": id, "scene": v["scene"], "point_set": v["point_set"],
                "time_filter": v["time_filter"], "spp": if reference { 343 } else { v["level"].as_u64().unwrap() },
                "reference": reference, "seed": 1, "width": 8, "height": 8, "frames": 1,
                "fps": 30.0, "frame_paths": ["f.png"], "content_hash": "00", "render_seconds": 0.1
            });
            edit(&mut s);
            stimuli.insert(id, s);
        }
    }
    let m = serde_json::json!({"format": "blurlab-manifest/1", "job": "demo",
        "stimuli": stimuli.into_values().collect::<Vec<_>>()});
    std::fs::write(path, serde_json::to_string_pretty(&m).unwrap()).unwrap();
}

/// The line (1-based) of the first main trial.
fn first_main(lines: &[String]) -> usize {
    1 + lines
        .iter()
        .position(|l| l.contains("\"kind\":\"trial\"") && l.contains("\"practice\":false"))
        .expect("a main trial")
}

fn edit(line: &str, from: &str, to: &str) -> String {
    assert!(line.contains(from), "{from} not in {line}");
    line.replacen(from, to, 1)
}

fn field(line: &str, name: &str) -> String {
    let v: serde_json::Value = serde_json::from_str(line).unwrap();
    v[name].to_string()
}

#[test]
fn edited_trials_are_refused_naming_file_line_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let (log, lines, design) = one_log(dir.path());
    let n = first_main(&lines);
    let t = lines[n - 1].clone();
    let response = field(&t, "response");
    let correct = field(&t, "correct");
    let flipped = if correct == "true" { "false" } else { "true" };
    let test = field(&t, "test_stimulus");
    let scene = field(&t, "scene");
    // (edited line, needs the design, words the message must hold)
    let cases: Vec<(String, bool, Vec<&str>)> = vec![
        (
            edit(&t, &format!("\"response\":{response}"), "\"response\":7"),
            false,
            vec!["field `response` is 7", "1 or 2"],
        ),
        (
            edit(
                &t,
                &format!("\"correct\":{correct}"),
                &format!("\"correct\":{flipped}"),
            ),
            false,
            vec!["field `correct`", "`diff_pair`"],
        ),
        (
            edit(&t, "\"index\":0,", "\"index\":600,"),
            false,
            vec!["field `index` is 600", "plans"],
        ),
        (
            edit(&t, &format!("\"scene\":{scene}"), "\"scene\":\"moon\""),
            true,
            vec!["field `scene` is \"moon\"", "the design plans"],
        ),
        (
            edit(
                &t,
                &format!("\"test_stimulus\":{test}"),
                "\"test_stimulus\":\"other\"",
            ),
            true,
            vec!["field `test_stimulus`", "the design plans"],
        ),
    ];
    for (bad, with_design, words) in cases {
        let mut all = lines.clone();
        all[n - 1] = bad;
        std::fs::write(&log, all.join("\n") + "\n").unwrap();
        let d = with_design.then_some(&design);
        let e = format!(
            "{:#}",
            Dataset::read_checked(std::slice::from_ref(&log), d, false).unwrap_err()
        );
        assert!(
            e.contains(&format!("s01.jsonl:{n}:")),
            "no file:line in {e}"
        );
        assert!(e.contains("--lenient"), "{e}");
        for w in words {
            assert!(e.contains(w), "`{w}` missing from {e}");
        }
        // Lenient: the trial is left out, counted and listed.
        let ds = Dataset::read_checked(std::slice::from_ref(&log), d, true).unwrap();
        assert!(
            ds.warnings[0].starts_with("1 main trials left out"),
            "{:?}",
            ds.warnings
        );
        if !with_design {
            // Without the design, a trial of an unknown scene would count: the check needs it.
            assert!(Dataset::read_checked(std::slice::from_ref(&log), None, false).is_err());
        }
    }
    // The unedited log passes every check, with the design (and its manifest) too.
    std::fs::write(&log, lines.join("\n") + "\n").unwrap();
    let ds = Dataset::read_checked(std::slice::from_ref(&log), Some(&design), false).unwrap();
    assert!(ds.warnings.is_empty(), "{:?}", ds.warnings);
}

#[test]
fn trials_are_checked_against_the_designs_manifest() {
    let dir = tempfile::tempdir().unwrap();
    let (log, lines, design) = one_log(dir.path());
    let n = first_main(&lines);
    let test = field(&lines[n - 1], "test_stimulus");
    let test = test.trim_matches('"').to_string();
    let refuse = |words: &[&str]| {
        let e = format!(
            "{:#}",
            Dataset::read_checked(std::slice::from_ref(&log), Some(&design), false).unwrap_err()
        );
        assert!(
            e.contains(&format!("s01.jsonl:{n}:")),
            "no file:line in {e}"
        );
        for w in words {
            assert!(e.contains(w), "`{w}` missing from {e}");
        }
    };
    // The manifest does not list the trial's test stimulus (stimuli of another render).
    let manifest = dir.path().join("manifest.json");
    let t = test.clone();
    write_manifest(&manifest, &lines, |s| {
        if s["id"] == t.as_str() {
            s["id"] = "renamed".into();
        }
    });
    refuse(&["field `test_stimulus`", "does not list"]);
    // The manifest rendered it at another density.
    write_manifest(&manifest, &lines, |s| {
        if s["id"] == test.as_str() {
            s["spp"] = 4096.into();
        }
    });
    refuse(&["field `level`", "4096"]);
    // Without the manifest the design alone is checked, and the report says so.
    std::fs::remove_file(&manifest).unwrap();
    let ds = Dataset::read_checked(std::slice::from_ref(&log), Some(&design), false).unwrap();
    assert!(ds.warnings[0].contains("is not here"), "{:?}", ds.warnings);
}

#[test]
fn a_subjects_logs_must_be_of_one_mode() {
    let dir = tempfile::tempdir().unwrap();
    let (log, lines, _) = one_log(dir.path());
    // The same subject's second session, written as a person's (another session number, so
    // its trials are not duplicates).
    let second: Vec<String> = lines
        .iter()
        .map(|l| {
            l.replacen("\"mode\":\"simulated\"", "\"mode\":\"gui\"", 1)
                .replacen("\"session\":1", "\"session\":2", 1)
        })
        .collect();
    let other = dir.path().join("s01-b.jsonl");
    std::fs::write(&other, second.join("\n") + "\n").unwrap();
    let e = format!(
        "{:#}",
        Dataset::read_checked(&[log, other], None, false).unwrap_err()
    );
    // Whichever log is read first sets the subject's mode; the other is named with both modes.
    assert!(e.contains("s01-b.jsonl") && e.contains("s01.jsonl:"), "{e}");
    for w in ["field `mode`", "\"gui\"", "\"simulated\""] {
        assert!(e.contains(w), "`{w}` missing from {e}");
    }
}

#[test]
fn a_log_torn_inside_its_header_is_skipped_only_with_lenient() {
    let dir = tempfile::tempdir().unwrap();
    let (log, lines, _) = one_log(dir.path());
    let torn = dir.path().join("sessions/s02.jsonl");
    std::fs::write(&torn, &lines[0][..lines[0].len() / 2]).unwrap();
    let folder = vec![dir.path().join("sessions")];
    let e = format!(
        "{:#}",
        Dataset::read_checked(&folder, None, false).unwrap_err()
    );
    assert!(
        e.contains("s02.jsonl:1: the header line is incomplete") && e.contains("--lenient"),
        "{e}"
    );
    let ds = Dataset::read_checked(&folder, None, true).unwrap();
    assert!(
        ds.warnings
            .iter()
            .any(|w| w.contains("s02.jsonl:1") && w.contains("skipped")),
        "{:?}",
        ds.warnings
    );
    assert_eq!(ds.files, vec![log]);
}
