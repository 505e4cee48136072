//! Lab and browser sessions analyzed together (issue 39): logs whose header says `mode: web`
//! (written by `blurlab serve`) are a person's answers like the lab app's `gui` ones; the
//! report counts the sessions of each mode; `--max-dropped-frames` names the trials over the
//! limit, `--exclude-dropped` leaves them out, and a subject with a large share is named.
//! The web logs are made by hand from simulated ones: the header's mode and the trials'
//! dropped frames rewritten, everything else as a session writes it.

use analysis::data::Dataset;
use analysis::data::dropped::DroppedFrames;
use analysis::report::{Settings, analyze};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Subject `subject`'s simulated demo session rewritten as `mode`, with `dropped(i)` dropped
/// frames on main trial i.
fn session(dir: &Path, subject: &str, mode: &str, dropped: impl Fn(u64) -> u64) -> PathBuf {
    let design = experiment::Design::load(&root().join("scenes/demo/design.json")).unwrap();
    let observer = experiment::Observer::load(&root().join("scenes/thesis/observer.json")).unwrap();
    let path = dir.join(format!("{subject}_{mode}.jsonl"));
    experiment::simulate::simulate_subject(&design, &observer, subject, &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<String> = text
        .lines()
        .map(|line| {
            let mut v: serde_json::Value = serde_json::from_str(line).unwrap();
            if v["kind"] == "header" {
                v["mode"] = mode.into();
                v.as_object_mut().unwrap().remove("observer");
            } else if v["kind"] == "trial" && v["practice"] == false {
                let i = v["index"].as_u64().unwrap();
                v["dropped_frames"] = dropped(i).into();
            }
            serde_json::to_string(&v).unwrap()
        })
        .collect();
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    path
}

#[test]
fn lab_and_web_sessions_analyze_together_and_are_counted() {
    let dir = tempfile::tempdir().unwrap();
    let files = vec![
        session(dir.path(), "s01", "gui", |_| 0),
        session(dir.path(), "s02", "web", |_| 0),
        session(dir.path(), "s03", "web", |_| 0),
    ];
    let ds = Dataset::read(&files).unwrap();
    assert_eq!(ds.subjects, ["s01", "s02", "s03"]);
    let counts: Vec<(&str, usize)> = ds
        .sessions_by_mode
        .iter()
        .map(|(m, n)| (m.as_str(), *n))
        .collect();
    assert_eq!(counts, [("gui", 1), ("web", 2)]);
    let mut s = Settings::default();
    s.bootstrap.resamples = 100;
    let report = analyze(&ds, &s);
    let out = dir.path().join("report");
    analysis::output::write(&report, &out).unwrap();
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        md.contains("Sessions: 1 lab (`gui`), 2 web (`blurlab serve`)."),
        "{md}"
    );
}

#[test]
fn one_subject_may_sit_in_the_lab_and_in_a_browser_but_not_beside_a_model() {
    let dir = tempfile::tempdir().unwrap();
    let lab = session(dir.path(), "s01", "gui", |_| 0);
    let web = session(dir.path(), "s01", "web", |_| 0);
    // Two logs of one subject and session number would be one trial counted twice: a second
    // session is numbered 2, as a resumed subject's next session is.
    let text = std::fs::read_to_string(&web)
        .unwrap()
        .replacen("\"session\":1", "\"session\":2", 1);
    std::fs::write(&web, text).unwrap();
    let ds = Dataset::read(&[lab.clone(), web]).unwrap();
    assert_eq!(ds.subjects, ["s01"]);
    let model = session(dir.path(), "s01", "simulated", |_| 0);
    let e = Dataset::read(&[lab, model]).unwrap_err().to_string();
    assert!(e.contains("must hold one kind of answers"), "{e}");
}

#[test]
fn trials_over_the_dropped_frames_limit_are_named_and_left_out_on_request() {
    let dir = tempfile::tempdir().unwrap();
    // s01 drops 5 frames on every fourth main trial (30 of 120: 25%), s02 on none.
    let files = vec![
        session(dir.path(), "s01", "web", |i| if i % 4 == 0 { 5 } else { 1 }),
        session(dir.path(), "s02", "web", |_| 0),
    ];
    let all = Dataset::read(&files).unwrap();
    let warn = DroppedFrames {
        max: 2,
        exclude: false,
        max_share: 0.2,
    };
    let warned = Dataset::read_with(&files, None, false, Some(&warn)).unwrap();
    assert_eq!(warned.trials, all.trials, "a warning leaves every trial in");
    let w = warned.warnings.join("\n");
    assert!(
        w.contains("30 main trials have more than 2 dropped frames"),
        "{w}"
    );
    assert!(w.contains("s01_web.jsonl:"), "{w}");
    assert!(w.contains("still analyzed"), "{w}");
    assert!(
        w.contains("subject \"s01\": 30 of 120 main trials (25%)"),
        "{w}"
    );
    assert!(!w.contains("subject \"s02\""), "{w}");

    let exclude = DroppedFrames {
        exclude: true,
        ..warn
    };
    let kept = Dataset::read_with(&files, None, false, Some(&exclude)).unwrap();
    assert_eq!(kept.trials, all.trials - 30);
    assert!(
        kept.warnings
            .join("\n")
            .contains("left out (--exclude-dropped)")
    );

    // Below the share limit the subject is not named.
    let lenient_share = DroppedFrames {
        max_share: 0.3,
        ..exclude
    };
    let kept = Dataset::read_with(&files, None, false, Some(&lenient_share)).unwrap();
    assert!(!kept.warnings.join("\n").contains("subject \"s01\""));
}
