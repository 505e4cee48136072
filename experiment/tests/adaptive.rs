//! Adaptive sessions resumed: a QUEST+ or staircase session killed at any point and continued
//! presents the trial an uninterrupted session presents there, and finishes with the same log
//! (the procedure's state is rebuilt by replaying the logged answers). One test kills a real
//! child process with SIGKILL while it writes; the others cut a complete log at every line.

use experiment::log::writer::Durability;
use experiment::log::{SessionLog, TrialRecord};
use experiment::session::{Phase, Session};
use experiment::simulate::answer_all;
use experiment::trials::Trial;
use experiment::{Design, Observer};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use support::{Fixture, start};

mod support;

const DESIGN: &str = r#"{
    "format": "blurlab-design/1", "name": "adaptive", "manifest": "none",
    "factors": {"scenes": ["plane", "spheres"], "point_sets": ["hammersley"],
                "time_filters": ["box"]},
    "levels": [1, 8, 27, 64, 125], "break_every": 5,
    "practice": {"trials": 2}, "seed": {"master": 11},
    "procedure": PROCEDURE
}"#;

const QUEST: &str = r#"{"quest_plus": {"trials": 8}}"#;
const STAIRS: &str =
    r#"{"staircase": {"rule": "one_up_three_down", "interleaved": 2, "trials": 5}}"#;

const OBSERVER: &str = r#"{"format": "blurlab-observer/1", "name": "o", "slope": 1.5,
    "thresholds": [{"scene": "plane", "spp": 20}, {"spp": 50}]}"#;

fn fixture(procedure: &str) -> Fixture {
    support::fixture(&DESIGN.replace("PROCEDURE", procedure), OBSERVER)
}

/// The uninterrupted session's trials.
fn reference(f: &Fixture) -> Vec<TrialRecord> {
    let mut s = start(&f.design, &f.path, Durability::Flush);
    answer_all(&mut s, &f.observer).unwrap();
    SessionLog::read(&f.path).unwrap().trials
}

/// Screens passed, the trial the resumed session presents first.
fn first_trial(s: &mut Session) -> Option<Trial> {
    while matches!(
        s.phase(),
        Phase::Instructions | Phase::PracticeDone | Phase::Break
    ) {
        s.advance();
    }
    s.trial().cloned()
}

#[test]
fn cut_after_any_line_an_adaptive_session_continues_as_an_uninterrupted_one() {
    for procedure in [QUEST, STAIRS] {
        let f = fixture(procedure);
        let want = reference(&f);
        // Adaptive: the levels differ between conditions and over the session.
        let main: Vec<&TrialRecord> = want.iter().filter(|t| !t.practice).collect();
        assert_eq!(main.len() as u32, f.design.main_trial_count());
        assert!(main.iter().any(|t| t.level != main[0].level));
        let full = std::fs::read(&f.path).unwrap();
        let ends: Vec<usize> = (0..full.len()).filter(|&i| full[i] == b'\n').collect();
        for (k, &end) in ends.iter().enumerate() {
            std::fs::write(&f.path, &full[..=end]).unwrap();
            let mut s = start(&f.design, &f.path, Durability::Flush);
            let next = first_trial(&mut s);
            match want.get(k) {
                Some(w) => assert!(next.as_ref().unwrap().matches(w), "{procedure}: line {k}"),
                None => assert!(next.is_none()),
            }
            answer_all(&mut s, &f.observer).unwrap();
            assert_eq!(
                SessionLog::read(&f.path).unwrap().trials,
                want,
                "{procedure}: line {k}"
            );
        }
    }
}

/// The child's half of the SIGKILL test: run the session of the design in
/// `BLURLAB_KILL_CHILD` slowly, syncing every answer, until it is killed.
#[test]
fn kill_child() {
    let Ok(dir) = std::env::var("BLURLAB_KILL_CHILD") else {
        return;
    };
    let dir = PathBuf::from(dir);
    let design = Design::load(&dir.join("design.json")).unwrap();
    let observer = Observer::parse(Path::new("o.json"), OBSERVER).unwrap();
    let mut s = start(&design, &dir.join("s01.jsonl"), Durability::Sync);
    loop {
        match s.phase() {
            Phase::Practice(_) | Phase::Trial(_) => {
                let r = observer.respond(s.trial().unwrap(), "s01").unwrap();
                s.answer(r, Default::default()).unwrap();
                std::thread::sleep(Duration::from_millis(15));
            }
            Phase::Finished => return,
            _ => s.advance(),
        }
    }
}

#[test]
fn killed_with_sigkill_the_resumed_session_presents_the_uninterrupted_next_trial() {
    let f = fixture(QUEST);
    let want = reference(&f);
    std::fs::remove_file(&f.path).unwrap();
    let dir = f.path.parent().unwrap();
    let mut child = std::process::Command::new(std::env::current_exe().unwrap())
        .args(["kill_child", "--exact", "--nocapture", "--test-threads=1"])
        .env("BLURLAB_KILL_CHILD", dir)
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Kill it once the header, the practice and a few main trials are on disk.
    let deadline = Instant::now() + Duration::from_secs(60);
    while std::fs::read(&f.path).map_or(0, |b| b.iter().filter(|&&c| c == b'\n').count()) < 7 {
        assert!(Instant::now() < deadline, "the child wrote nothing in 60 s");
        std::thread::sleep(Duration::from_millis(2));
    }
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    let done = SessionLog::read(&f.path).unwrap().trials.len();
    assert!(
        done >= 6 && done < want.len(),
        "{done} trials before the kill"
    );
    let mut s = start(&f.design, &f.path, Durability::Flush);
    let next = first_trial(&mut s).unwrap();
    assert!(next.matches(&want[done]), "{next:?} vs {:?}", want[done]);
    answer_all(&mut s, &f.observer).unwrap();
    assert_eq!(SessionLog::read(&f.path).unwrap().trials, want);
}
