//! `blurlab serve` end to end over real HTTP on 127.0.0.1: whole sessions of a small rendered
//! study (constant stimuli like the demo design, and QUEST+) answered by a simulated browser;
//! the server's log equals the log `blurlab simulate` writes for the same observer and subject
//! (answers, trials, order), in `mode: "web"` with the browser's display facts; a server stopped
//! mid-session and started again continues the session, each trial logged once.

use experiment::fixture::{StudySpec, write_study};
use experiment::log::SessionLog;
use experiment::simulate::simulate_subject_in_memory;
use experiment::{Design, Observer};
use serde_json::json;
use std::path::Path;
use std::time::Duration;
use web_client::{Running, SimBrowser, config, tokens};

mod web_client;

const OBSERVER: &str = r#"{"format": "blurlab-observer/1", "name": "o", "slope": 1.5,
    "thresholds": [{"spp": 4}]}"#;

fn observer() -> Observer {
    Observer::parse(Path::new("o.json"), OBSERVER).unwrap()
}

/// The tiny study with demo-like session settings (practice with feedback, breaks).
fn demo_like(root: &Path) -> Design {
    let mut spec = StudySpec::tiny();
    spec.design = json!({"repeats": 2, "practice": {"trials": 2, "levels": [1], "feedback": true},
                         "break_every": 5,
                         "playback": {"loops": 2, "fixation_ms": 500, "gap_ms": 700}});
    Design::load(&write_study(root, &spec).unwrap().design_path).unwrap()
}

fn quest(root: &Path) -> Design {
    let mut spec = StudySpec::tiny();
    spec.design = json!({"procedure": {"quest_plus": {"trials": 6}}, "reference": "scene_reference",
                         "practice": {"trials": 1}, "break_every": 4});
    Design::load(&write_study(root, &spec).unwrap().design_path).unwrap()
}

/// The web log's trials are the simulated session's, answer for answer.
fn assert_same_as_simulation(design: &Design, log: &SessionLog, subject: &str) {
    let sim = simulate_subject_in_memory(design, &observer(), subject).unwrap();
    let key = |t: &experiment::log::TrialRecord| {
        (
            t.practice,
            t.index,
            t.test_stimulus.clone(),
            t.diff_pair,
            t.response,
            t.correct,
        )
    };
    let web: Vec<_> = log.trials.iter().map(key).collect();
    let want: Vec<_> = sim.trials.iter().map(key).collect();
    assert_eq!(web, want);
    assert_eq!(log.header.mode, "web");
    let d = log
        .header
        .display
        .as_ref()
        .expect("a web log records the display");
    let b = d.browser.as_ref().expect("with the browser's facts");
    assert_eq!(b.viewing_distance_mm, 600.0);
    for t in &log.trials {
        assert_eq!(t.timing.late_frames, Some(0));
        assert_eq!(t.timing.refresh_interval_ms, Some(16.7));
    }
}

async fn whole_session(design: Design, dir: &Path) {
    let out = dir.join("study");
    let server = Running::start(&config(&design.path, &out, 2)).await;
    let http = reqwest::Client::new();
    let (subject, token) = tokens(&out)[1].clone();
    let browser = SimBrowser::new(
        http,
        &server.base,
        &design,
        &observer(),
        &subject,
        &token,
        Duration::ZERO,
    );
    let outcome = browser.run().await.unwrap();
    server.stop().await;
    let log = SessionLog::read(&out.join("sessions").join(format!("{subject}.jsonl"))).unwrap();
    assert_eq!(outcome.acked.len(), log.trials.len());
    // Each distinct video crossed the network once: for constant stimuli, exactly the videos
    // the subject's trial list shows.
    assert_eq!(outcome.videos as usize, outcome.fetched.len());
    if design.file.procedure.is_constant() {
        let plan = experiment::trials::plan(&design, &subject);
        let distinct: std::collections::BTreeSet<&str> = plan
            .practice
            .iter()
            .chain(&plan.main)
            .flat_map(|t| t.stimuli())
            .collect();
        assert_eq!(outcome.fetched.len(), distinct.len());
    }
    assert_same_as_simulation(&design, &log, &subject);
    assert!(log.resumes.is_empty());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_whole_constant_stimuli_session_over_http_logs_what_simulate_logs() {
    let dir = tempfile::tempdir().unwrap();
    let design = demo_like(dir.path());
    whole_session(design, dir.path()).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_whole_quest_plus_session_over_http_logs_what_simulate_logs() {
    let dir = tempfile::tempdir().unwrap();
    let design = quest(dir.path());
    whole_session(design, dir.path()).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_server_stopped_mid_session_continues_it_after_a_restart() {
    let dir = tempfile::tempdir().unwrap();
    let design = demo_like(dir.path());
    let out = dir.path().join("study");
    let server = Running::start(&config(&design.path, &out, 1)).await;
    let addr = server.started.addr;
    let (subject, token) = tokens(&out)[0].clone();
    let log_path = out.join("sessions").join(format!("{subject}.jsonl"));
    let browser = SimBrowser::new(
        reqwest::Client::new(),
        &server.base,
        &design,
        &observer(),
        &subject,
        &token,
        Duration::from_millis(5),
    );
    let run = tokio::spawn(browser.run());
    // Stop once a few trials are logged, then start again on the same address.
    while std::fs::read_to_string(&log_path).map_or(0, |t| t.lines().count()) < 6 {
        tokio::time::sleep(Duration::from_millis(5)).await;
    }
    server.stop().await;
    tokio::time::sleep(Duration::from_millis(200)).await;
    let mut again = config(&design.path, &out, 1);
    again.addr = addr;
    let server = Running::start(&again).await;
    let outcome = run.await.unwrap().unwrap();
    server.stop().await;
    // An answer stored just before a crash is acknowledged after the restart, before any claim.
    let server = Running::start(&again).await;
    let replay = serde_json::json!({"tab": format!("tab-{subject}"), "session": 1,
        "practice": true, "trial": 0, "response": 1, "timing": {"rt_ms": 1.0}});
    let url = format!("{}/api/s/{token}/answer", server.base);
    let r = web_client::post(&reqwest::Client::new(), &url, replay)
        .await
        .unwrap();
    assert_eq!(r.status, 200, "{}", r.body);
    assert_eq!(r.body["ack"]["trial"], 0);
    server.stop().await;
    let log = SessionLog::read(&log_path).unwrap();
    assert_eq!(
        log.resumes.len(),
        1,
        "one resume line where the restart picked up"
    );
    assert!(
        outcome.retries > 0,
        "the browser had to retry through the restart"
    );
    assert_eq!(outcome.acked.len(), log.trials.len());
    assert_same_as_simulation(&design, &log, &subject);
}
