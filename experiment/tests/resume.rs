//! Resume after a kill: a session is interrupted between writes (the log ends after a whole
//! line) and during a write (the log is cut inside a line), then continued. The finished log
//! must hold exactly the planned trials, in the planned order, each once, with the answers an
//! uninterrupted session gives. The kill is simulated by truncating a complete log.

use experiment::Design;
use experiment::log::writer::Durability;
use experiment::log::{LogLine, SessionLog, TrialRecord};
use experiment::session::{Phase, Session};
use experiment::simulate::answer_all;
use std::path::Path;
use support::{Fixture, info};

mod support;

const DESIGN: &str = r#"{
    "format": "blurlab-design/1", "name": "resume", "manifest": "none",
    "factors": {"scenes": ["plane"], "point_sets": ["hammersley", "poisson"],
                "time_filters": ["box"]},
    "levels": [1, 27], "repeats": 2, "break_every": 3,
    "practice": {"trials": 2}, "seed": {"master": 11}
}"#;

const OBSERVER: &str = r#"{"format": "blurlab-observer/1", "name": "o", "slope": 1.0,
    "thresholds": [{"spp": 10}]}"#;

fn fixture() -> Fixture {
    support::fixture(DESIGN, OBSERVER)
}

fn start(f: &Fixture, durability: Durability) -> Session {
    support::start(&f.design, &f.path, durability)
}

/// Answer `n` trials (advancing through screens), then drop the session as a kill would.
fn answer_some(f: &Fixture, s: &mut Session, n: usize) {
    let mut answered = 0;
    while answered < n {
        match s.phase() {
            Phase::Practice(_) | Phase::Trial(_) => {
                let r = f.observer.respond(s.trial().unwrap(), "s01").unwrap();
                s.answer(r, Default::default()).unwrap();
                answered += 1;
            }
            Phase::Finished => return,
            _ => s.advance(),
        }
    }
}

fn trials(path: &Path) -> Vec<TrialRecord> {
    SessionLog::read(path).unwrap().trials
}

/// The uninterrupted session's log bytes.
fn reference(f: &Fixture) -> Vec<u8> {
    let mut s = start(f, Durability::Sync);
    answer_all(&mut s, &f.observer).unwrap();
    std::fs::read(&f.path).unwrap()
}

/// Byte offsets where each line ends (after its newline).
fn line_ends(bytes: &[u8]) -> Vec<usize> {
    bytes
        .iter()
        .enumerate()
        .filter(|(_, b)| **b == b'\n')
        .map(|(i, _)| i + 1)
        .collect()
}

fn resume_to_end(f: &Fixture) -> Session {
    let mut s = start(f, Durability::Flush);
    answer_all(&mut s, &f.observer).unwrap();
    s
}

#[test]
fn killed_between_writes_continues_at_the_next_unanswered_trial() {
    let f = fixture();
    let full = reference(&f);
    let want = trials(&f.path);
    assert_eq!(want.len(), 2 + 8);
    for (k, &end) in line_ends(&full).iter().enumerate() {
        std::fs::write(&f.path, &full[..end]).unwrap();
        let mut s = Session::open(&f.design, "s01", &f.path, Durability::Flush).unwrap();
        assert!(s.resumed());
        // k whole trial lines survive (line 0 is the header).
        let practice_kept = k.min(2);
        let main_kept = k.saturating_sub(2);
        assert_eq!(s.practice_progress().0, practice_kept);
        assert_eq!(s.progress().0, main_kept);
        s.start(info()).unwrap();
        s.advance();
        let expected = if practice_kept < 2 {
            Phase::Practice(practice_kept)
        } else if main_kept < 8 {
            Phase::Trial(main_kept)
        } else {
            Phase::Finished
        };
        assert_eq!(s.phase(), expected, "cut after line {k}");
        answer_all(&mut s, &f.observer).unwrap();
        let log = SessionLog::read(&f.path).unwrap();
        assert_eq!(log.trials, want, "cut after line {k}");
        assert!(log.warnings.is_empty());
        assert_eq!(log.resumes.len(), 1);
        // What was on disk before the kill is untouched.
        assert_eq!(&std::fs::read(&f.path).unwrap()[..end], &full[..end]);
    }
}

#[test]
fn killed_during_a_write_loses_only_the_torn_answer() {
    let f = fixture();
    let full = reference(&f);
    let want = trials(&f.path);
    let ends = line_ends(&full);
    // Cut inside every trial line: after 1 byte, in the middle, and just before the newline
    // (a complete JSON line missing only its newline, which is kept).
    for w in ends.windows(2) {
        let (start_of_line, end_of_line) = (w[0], w[1]);
        for cut in [
            start_of_line + 1,
            (start_of_line + end_of_line) / 2,
            end_of_line - 1,
        ] {
            std::fs::write(&f.path, &full[..cut]).unwrap();
            let s = resume_to_end(&f);
            let log = SessionLog::read(&f.path).unwrap();
            assert_eq!(log.trials, want, "cut at byte {cut}");
            let torn = cut != end_of_line - 1;
            assert_eq!(
                s.warnings()
                    .iter()
                    .any(|w| w.contains("incomplete last line")),
                torn,
                "cut at byte {cut}: {:?}",
                s.warnings()
            );
            // The resume line records what was tolerated.
            assert_eq!(log.resumes[0].warnings.is_empty(), !torn);
        }
    }
}

#[test]
fn killed_twice_including_inside_a_resume_line() {
    let f = fixture();
    reference(&f);
    let want = trials(&f.path);
    let full = std::fs::read(&f.path).unwrap();
    let ends = line_ends(&full);
    std::fs::write(&f.path, &full[..ends[4] - 7]).unwrap(); // torn 4th trial line
    let mut s = start(&f, Durability::Sync);
    answer_some(&f, &mut s, 2);
    drop(s);
    // Second kill: inside the resume line written by the first resume (line index 4).
    let bytes = std::fs::read(&f.path).unwrap();
    let ends2 = line_ends(&bytes);
    let resume_line = &bytes[ends2[3]..ends2[4]];
    assert!(resume_line.starts_with(b"{\"kind\":\"resume\""));
    std::fs::write(&f.path, &bytes[..ends2[3] + 10]).unwrap();
    resume_to_end(&f);
    let log = SessionLog::read(&f.path).unwrap();
    assert_eq!(log.trials, want);
    assert_eq!(log.resumes.len(), 1);
}

#[test]
fn a_log_cut_inside_its_header_starts_afresh() {
    let f = fixture();
    let full = reference(&f);
    std::fs::write(&f.path, &full[..20]).unwrap();
    let s = resume_to_end(&f);
    assert!(!s.resumed());
    assert!(s.warnings()[0].contains("no complete line"));
    assert_eq!(std::fs::read(&f.path).unwrap(), full);
}

#[test]
fn a_changed_design_another_subject_or_a_foreign_trial_is_refused() {
    let f = fixture();
    let full = reference(&f);
    let ends = line_ends(&full);
    std::fs::write(&f.path, &full[..ends[5]]).unwrap();

    let changed = DESIGN.replace("\"repeats\": 2", "\"repeats\": 3");
    let d2 = Design::parse(&f.design.path, &changed).unwrap();
    let e = Session::open(&d2, "s01", &f.path, Durability::Flush).unwrap_err();
    let msg = format!("{e:#}");
    assert!(msg.contains("hash") && msg.contains("s01.jsonl"), "{msg}");

    let e = Session::open(&f.design, "s02", &f.path, Durability::Flush).unwrap_err();
    assert!(e.to_string().contains("`subject`"), "{e}");

    // A trial line edited to another stimulus does not belong to this list.
    let text = String::from_utf8(full[..ends[5]].to_vec()).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let mut rec: LogLine = serde_json::from_str(&lines[4]).unwrap();
    if let LogLine::Trial(t) = &mut rec {
        t.diff_pair = 3 - t.diff_pair;
    }
    lines[4] = serde_json::to_string(&rec).unwrap();
    std::fs::write(&f.path, lines.join("\n") + "\n").unwrap();
    let e = Session::open(&f.design, "s01", &f.path, Durability::Flush).unwrap_err();
    assert!(e.to_string().contains("not the trial"), "{e}");
    // Refusals write nothing.
    assert_eq!(
        std::fs::read(&f.path).unwrap(),
        (lines.join("\n") + "\n").into_bytes()
    );
}

#[test]
fn breaks_come_every_n_main_trials_and_the_end_after_the_last() {
    let f = fixture();
    let mut s = start(&f, Durability::Flush);
    let mut phases = vec![s.phase()];
    loop {
        match s.phase() {
            Phase::Practice(_) | Phase::Trial(_) => {
                s.answer(1, Default::default()).unwrap();
            }
            Phase::Finished => break,
            _ => s.advance(),
        }
        phases.push(s.phase());
    }
    use Phase::*;
    assert_eq!(
        phases,
        vec![
            Instructions,
            Practice(0),
            Practice(1),
            PracticeDone,
            Trial(0),
            Trial(1),
            Trial(2),
            Break,
            Trial(3),
            Trial(4),
            Trial(5),
            Break,
            Trial(6),
            Trial(7),
            Finished
        ]
    );
    assert!(s.answer(1, Default::default()).is_err());
}
