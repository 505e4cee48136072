//! Simulated subjects through the real session machine and log writer: one complete log per
//! subject, readable by the reader the analysis uses, reproducible byte for byte, with answers
//! that follow the observer's psychometric function.

use experiment::log::SessionLog;
use experiment::log::sink::MemoryLog;
use experiment::simulate::{simulate, simulate_in_memory, simulate_subject_to};
use experiment::trials::plan;
use experiment::{Design, Observer};
use std::path::Path;

fn repo(p: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(p)
}

#[test]
fn twelve_thesis_subjects_follow_the_observer_and_rerun_identically() {
    let design = Design::load(&repo("scenes/thesis/design.json")).unwrap();
    let observer = Observer::load(&repo("scenes/thesis/observer.json")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let paths = simulate(&design, &observer, 12, dir.path()).unwrap();
    assert_eq!(paths.len(), 12);
    let first: Vec<Vec<u8>> = paths.iter().map(|p| std::fs::read(p).unwrap()).collect();

    let mut correct_at = std::collections::BTreeMap::<(String, u32), (u32, u32, f64)>::new();
    for (i, p) in paths.iter().enumerate() {
        let log = SessionLog::read(p).unwrap();
        let subject = format!("s{:02}", i + 1);
        assert_eq!(log.header.subject, subject);
        assert_eq!(log.header.mode, "simulated");
        assert_eq!(log.header.design_hash, design.hash);
        assert_eq!(log.header.trials_planned, 192);
        assert_eq!(log.header.observer.as_ref().unwrap()["name"], "thesis");
        let plan = plan(&design, &subject);
        assert_eq!(log.header.seed, plan.seed);
        let main: Vec<_> = log.main_trials().collect();
        assert_eq!(main.len(), 192);
        assert_eq!(log.trials.len(), 192 + 4);
        for (t, r) in plan.main.iter().zip(&main) {
            assert!(t.matches(r));
            assert_eq!(r.correct, r.response == r.diff_pair);
            let e = correct_at
                .entry((t.condition.scene.clone(), t.level))
                .or_default();
            e.0 += r.correct as u32;
            e.1 += 1;
            e.2 += observer.p_trial(t, &subject).unwrap();
            // The thesis's ground truth: the 512-spp trial compares a video with itself.
            assert_eq!(t.test_stimulus == t.reference_stimulus, t.level == 512);
        }
    }
    // Per scene x level: 12 subjects x 3 point sets x 4 repeats = 144 answers; the observed
    // proportion's standard error is at most sqrt(0.25 / 144) = 0.042. Allow 4 sigma.
    for ((scene, level), (c, n, p_sum)) in &correct_at {
        assert_eq!(*n, 144);
        let observed = *c as f64 / *n as f64;
        let expected = p_sum / *n as f64;
        assert!(
            (observed - expected).abs() < 4.0 * 0.042,
            "{scene} at {level} spp: observed {observed}, expected {expected}"
        );
    }
    // The pooled proportions fall from near 1 to near 0.5 across the levels, as in the thesis.
    let plane_1 = correct_at[&("plane".to_string(), 1)];
    let plane_512 = correct_at[&("plane".to_string(), 512)];
    assert!(plane_1.0 as f64 / 144.0 > 0.9);
    assert!((plane_512.0 as f64 / 144.0) < 0.7);
    assert_eq!(
        plane_512.2 / 144.0,
        0.5,
        "chance by construction at the highest level"
    );

    let again = simulate(&design, &observer, 12, dir.path()).unwrap();
    for (p, bytes) in again.iter().zip(&first) {
        assert_eq!(&std::fs::read(p).unwrap(), bytes, "{} differs", p.display());
    }
}

#[test]
fn an_observer_that_does_not_cover_the_design_is_refused_before_writing() {
    let design = Design::load(&repo("scenes/demo/design.json")).unwrap();
    let observer = Observer::parse(
        Path::new("o.json"),
        r#"{"format": "blurlab-observer/1", "name": "o", "slope": 1,
            "thresholds": [{"scene": "plane", "spp": 10}]}"#,
    )
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sessions");
    let e = simulate(&design, &observer, 2, &out).unwrap_err();
    assert!(e.to_string().contains("spheres"), "{e}");
    assert!(!out.exists());
}

#[test]
fn a_design_with_another_task_is_not_presented() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(repo("scenes/thesis/design.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["task"] = serde_json::json!({"alternatives": 4});
    let path = dir.path().join("four.json");
    std::fs::write(&path, v.to_string()).unwrap();
    let design = Design::load(&path).unwrap();
    let observer = Observer::load(&repo("scenes/thesis/observer.json")).unwrap();
    let e = simulate(&design, &observer, 1, &dir.path().join("sessions")).unwrap_err();
    let e = format!("{e:#}");
    assert!(e.contains("four.json") && e.contains("`task`"), "{e}");
}

/// A log holds one kind of answers: the app does not continue a simulated log with a person's
/// answers, and a simulation does not replace a person's log (it used to delete it).
#[test]
fn a_log_of_another_mode_is_neither_continued_nor_replaced() {
    use experiment::log::writer::Durability;
    use experiment::session::{Session, StartInfo};
    let design = Design::load(&repo("scenes/thesis/design.json")).unwrap();
    let observer = Observer::load(&repo("scenes/thesis/observer.json")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let log = simulate(&design, &observer, 1, dir.path())
        .unwrap()
        .remove(0);
    // Cut the simulated log after its header and a few trials, then try to go on as a person.
    let text = std::fs::read_to_string(&log).unwrap();
    let head: Vec<&str> = text.lines().take(4).collect();
    std::fs::write(&log, head.join("\n") + "\n").unwrap();
    let mut s = Session::open(&design, "s01", &log, Durability::Flush).unwrap();
    let gui = StartInfo {
        mode: "gui".into(),
        display: None,
        observer: None,
        started_unix: 0.0,
    };
    let e = format!("{:#}", s.start(gui).unwrap_err());
    assert!(
        e.contains("s01.jsonl") && e.contains("field `mode`") && e.contains("\"simulated\""),
        "{e}"
    );
    // A person's log (header mode gui) is not replaced by a simulation.
    let persons = text.replacen("\"mode\":\"simulated\"", "\"mode\":\"gui\"", 1);
    assert_ne!(persons, text, "the header's mode field was not found");
    std::fs::write(&log, &persons).unwrap();
    let e = format!(
        "{:#}",
        simulate(&design, &observer, 1, dir.path()).unwrap_err()
    );
    assert!(
        e.contains("s01.jsonl") && e.contains("a person's answers"),
        "{e}"
    );
    assert_eq!(std::fs::read_to_string(&log).unwrap(), persons);
}

/// The memory log holds the bytes the file log writes, and `simulate_in_memory` returns the
/// logs in the order a folder of their files is read (`s10` < `s100` < `s11`), so `plan`'s
/// datasets are those of the file route.
#[test]
fn memory_logs_are_the_files_bytes_in_the_folders_order() {
    let design = Design::load(&repo("scenes/thesis/design.json")).unwrap();
    let observer = Observer::load(&repo("scenes/thesis/observer.json")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let paths = simulate(&design, &observer, 101, dir.path()).unwrap();
    let mut by_name = paths.clone();
    by_name.sort();
    let memory = simulate_in_memory(&design, &observer, 101).unwrap();
    assert_eq!(memory.len(), 101);
    for (file, log) in by_name.iter().zip(&memory) {
        assert_eq!(file.file_name(), log.path.file_name());
        assert_eq!(log.trials, SessionLog::read(file).unwrap().trials);
    }
    assert_eq!(memory[10].header.subject, "s100");
    for (i, path) in paths.iter().enumerate().step_by(25) {
        let subject = format!("s{:02}", i + 1);
        let log = MemoryLog::new(&format!("{subject}.jsonl"));
        simulate_subject_to(&design, &observer, &subject, Box::new(log.clone())).unwrap();
        assert_eq!(log.bytes(), std::fs::read(path).unwrap(), "{subject}");
    }
}
