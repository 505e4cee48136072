//! Issue 49's exclusion report end to end: sessions of a design with catch trials and
//! exclusion criteria, among them one fast-clicking subject, one whose display dropped frames
//! and one who fails the catch trials; `analyze` names each with its reason, writes
//! `exclusions.csv`, and fits without them (or with them, `--keep-excluded`).

use analysis::analyze::{AnalyzeOptions, run_report};
use experiment::Design;
use experiment::log::SessionLog;
use experiment::log::Timing;
use experiment::log::writer::Durability;
use experiment::session::{Session, StartInfo};
use renderer::hash::hash;
use std::path::Path;

const DESIGN: &str = r#"{
    "format": "blurlab-design/1",
    "name": "online",
    "manifest": "stimuli/none",
    "factors": {"scenes": ["plane"], "point_sets": ["hammersley", "poisson"],
                "time_filters": ["box"]},
    "levels": [1, 4, 16, 64],
    "repeats": 8,
    "practice": {"trials": 0},
    "break_every": 0,
    "catch_trials": {"rate": 0.125},
    "exclusion": {"min_catch_accuracy": 0.75, "max_bad_frames": 0.1, "min_rt_ms": 150},
    "seed": {"master": 3}
}"#;

#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Good,
    FastClicker,
    DroppedFrames,
    FailsCatch,
}

/// One subject's session: answers from a psychometric function of the level (a JND near 16
/// spp), catch trials right, 600 ms responses, 12 frames a trial all drawn; each kind of bad
/// subject departs in one way.
fn simulate(design: &Design, dir: &Path, subject: &str, kind: Kind) {
    let path = dir.join(format!("{subject}.jsonl"));
    let mut s = Session::open(design, subject, &path, Durability::Flush).unwrap();
    s.start(StartInfo {
        mode: "simulated".into(),
        display: None,
        observer: None,
        started_unix: 0.0,
    })
    .unwrap();
    s.advance();
    let mut k = 0u64;
    while let Some(t) = s.trial().cloned() {
        k += 1;
        let u = (hash(
            hash(7, &[k]),
            &[subject.len() as u64, subject.as_bytes()[1] as u64],
        ) >> 11) as f64
            / (1u64 << 53) as f64;
        let p = 0.5 + 0.5 / (1.0 + (f64::from(t.level).ln() - 16f64.ln()).exp().powf(2.0));
        let correct = match kind {
            Kind::FastClicker => u < 0.5,
            Kind::FailsCatch if t.catch => u < 0.25,
            _ if t.catch => true,
            _ => u < p,
        };
        let response = if correct {
            t.diff_pair
        } else {
            3 - t.diff_pair
        };
        let dropped = if kind == Kind::DroppedFrames { 4 } else { 0 };
        let timing = Timing {
            rt_ms: if kind == Kind::FastClicker {
                40.0
            } else {
                600.0
            },
            frame_times_ms: vec![0.0; 12 - dropped],
            dropped_frames: dropped as u32,
            late_frames: Some(0),
            ..Timing::default()
        };
        s.answer(response, timing).unwrap();
        if s.phase() == experiment::Phase::Break {
            s.advance();
        }
    }
}

fn study() -> (tempfile::TempDir, Design) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("design.json");
    std::fs::write(&path, DESIGN).unwrap();
    let design = Design::load(&path).unwrap();
    let sessions = dir.path().join("sessions");
    std::fs::create_dir_all(&sessions).unwrap();
    for i in 1..=6 {
        simulate(&design, &sessions, &format!("g{i:02}"), Kind::Good);
    }
    simulate(&design, &sessions, "fast", Kind::FastClicker);
    simulate(&design, &sessions, "drops", Kind::DroppedFrames);
    simulate(&design, &sessions, "nocatch", Kind::FailsCatch);
    (dir, design)
}

fn options(dir: &Path) -> AnalyzeOptions {
    let mut o = AnalyzeOptions::new(vec![dir.join("sessions")], dir.join("report"));
    o.design = Some(dir.join("design.json"));
    o.bootstrap = 1000;
    o
}

#[test]
fn catch_trials_are_interleaved_logged_and_not_fitted() {
    let (dir, design) = study();
    let log = SessionLog::read(&dir.path().join("sessions/g01.jsonl")).unwrap();
    let main: Vec<_> = log.main_trials().collect();
    // 64 procedure trials in blocks of 7 + 1 catch trial: 10 catch trials.
    assert_eq!(design.main_trial_count(), 74);
    assert_eq!(main.len(), 74);
    assert_eq!(main.iter().filter(|t| t.catch).count(), 10);
    assert!(main.iter().filter(|t| t.catch).all(|t| t.level == 1));
    assert_eq!(log.analyzed_trials().count(), 64);
    let report = run_report(&options(dir.path())).unwrap();
    // 6 good subjects x 64 fitted trials; the catch trials (and the 3 excluded) left out.
    assert_eq!(report.trials, 6 * 64);
}

#[test]
fn the_excluded_are_named_with_their_reasons_and_left_out_of_the_fits() {
    let (dir, _) = study();
    let report = run_report(&options(dir.path())).unwrap();
    let named: Vec<(&str, &str)> = report
        .excluded
        .iter()
        .map(|e| (e.subject.as_str(), e.reason.as_str()))
        .collect();
    assert_eq!(named.len(), 3, "{named:?}");
    let reason = |s: &str| named.iter().find(|(x, _)| *x == s).unwrap().1;
    assert!(reason("fast").contains("faster than 150 ms"), "{named:?}");
    assert!(reason("drops").contains("dropped or late"), "{named:?}");
    assert!(reason("nocatch").contains("catch trials"), "{named:?}");
    assert_eq!(report.subjects.len(), 6);
    let csv = std::fs::read_to_string(dir.path().join("report/exclusions.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 9, "{csv}");
    assert!(
        csv.lines()
            .any(|l| l.starts_with("g01,") && l.contains(",false,\"\"")),
        "{csv}"
    );
    assert!(
        csv.lines()
            .any(|l| l.starts_with("drops,") && l.contains(",true,")),
        "{csv}"
    );
    let md = std::fs::read_to_string(dir.path().join("report/report.md")).unwrap();
    assert!(md.contains("nocatch"), "the report names the excluded");

    // --keep-excluded: named in a warning, fitted all the same.
    let mut keep = options(dir.path());
    keep.keep_excluded = true;
    let kept = run_report(&keep).unwrap();
    assert!(kept.excluded.is_empty());
    assert_eq!(kept.subjects.len(), 9);
    assert!(
        kept.warnings
            .iter()
            .any(|w| w.contains("--keep-excluded") && w.contains("fast"))
    );

    // A flag replaces the design's criterion: at 0.2 of frames bad, `drops` (4 of 12) still
    // fails; at 0.5 it passes.
    let mut loose = options(dir.path());
    loose.criteria.max_bad_frames = Some(0.5);
    let r = run_report(&loose).unwrap();
    assert!(!r.excluded.iter().any(|e| e.subject == "drops"));
    assert_eq!(r.excluded.len(), 2);
}
