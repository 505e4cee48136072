//! The app without a display (egui_kittest): whole short sessions driven by key presses and
//! button clicks, with egui's clock advanced 1/60 s per step, then the log checked. The app's
//! code is the real one; only the window is simulated.
#![cfg(feature = "gui")]

use egui::Key;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use experiment::app::{Pacing, SessionApp};
use experiment::fixture::{Study, StudySpec, write_study};
use experiment::log::SessionLog;
use experiment::log::sink::MemoryLog;
use experiment::log::writer::Durability;
use experiment::playback::frame_store::{FrameDir, MemoryFrames};
use experiment::playback::frames::RgbFrame;
use experiment::preflight::{PreflightOptions, needed_stimuli, preflight};
use experiment::{Design, Phase, Session};
use serde_json::json;
use std::path::{Path, PathBuf};
use std::sync::Arc;

const DT: f32 = 1.0 / 60.0;

/// One scene, one point set, levels 1 and 8, 2 repeats (4 trials), 1 practice trial, a break
/// after every 2 trials; 6-frame videos at 30 fps.
fn study(dir: &Path) -> Study {
    let spec = StudySpec {
        scenes: vec!["alpha".into()],
        point_sets: vec!["random".into()],
        design: json!({
            "repeats": 2, "practice": {"trials": 1}, "break_every": 2,
            "playback": {"loops": 1, "fixation_ms": 100, "gap_ms": 100}
        }),
        ..StudySpec::tiny()
    };
    write_study(dir, &spec).unwrap()
}

fn open_app(study: &Study, subject: &str) -> (SessionApp, PathBuf) {
    let design = Design::load(&study.design_path).unwrap();
    let report = preflight(
        &design,
        PreflightOptions { check_hashes: true },
        &renderer::progress::NoProgress,
    );
    let manifest_path = report.manifest_path.clone();
    let manifest = report.into_result().unwrap();
    let log = study.root.join("sessions").join(format!("{subject}.jsonl"));
    std::fs::create_dir_all(log.parent().unwrap()).unwrap();
    let session = Session::open(&design, subject, &log, Durability::Sync).unwrap();
    (
        SessionApp::new(
            session,
            Arc::new(FrameDir::new(manifest, manifest_path)),
            Pacing::Vsync,
        ),
        log,
    )
}

fn harness(app: SessionApp, ppp: f32) -> Harness<'static, SessionApp> {
    Harness::builder()
        .with_size([1280.0 / ppp, 720.0 / ppp])
        .with_pixels_per_point(ppp)
        .with_step_dt(DT)
        .build_ui_state(|ui, app: &mut SessionApp| app.show(ui), app)
}

/// Step until `done` holds; loading runs on real threads, so wait a little while it does.
fn step_until(h: &mut Harness<'_, SessionApp>, what: &str, done: impl Fn(&SessionApp) -> bool) {
    for _ in 0..2000 {
        if done(h.state()) {
            return;
        }
        if h.state().loading() {
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
        h.step();
    }
    panic!(
        "never reached: {what} (phase {:?}, error {:?})",
        h.state().session().phase(),
        h.state().fatal_error()
    );
}

fn press(h: &mut Harness<'_, SessionApp>, key: Key) {
    h.key_press(key);
    h.step();
}

fn closed(h: &Harness<'_, SessionApp>) -> bool {
    h.state().closing()
}

/// Leave the instructions (once the refresh interval is measured).
fn start(h: &mut Harness<'_, SessionApp>) {
    h.run_steps(61);
    press(h, Key::Space);
}

#[test]
fn a_whole_session_by_keys_and_buttons_is_logged_with_its_timing() {
    let dir = tempfile::tempdir().unwrap();
    let study = study(dir.path());
    let (app, log_path) = open_app(&study, "k1");
    let mut h = harness(app, 1.5);
    start(&mut h);
    // Answers: keys 1, Right arrow, the "Pair 1" button, 2, Left arrow.
    let mut answers = vec!["1", "ArrowRight", "button", "2", "ArrowLeft"].into_iter();
    let mut seen = vec![];
    loop {
        let phase = h.state().session().phase();
        seen.push(phase);
        match phase {
            Phase::Practice(_) | Phase::Trial(_) => {
                step_until(&mut h, "the response screen", SessionApp::responding);
                match answers.next().unwrap() {
                    "button" => {
                        h.get_by_label("Pair 1").click();
                        h.step();
                    }
                    k => press(&mut h, Key::from_name(k).unwrap()),
                }
                if matches!(phase, Phase::Practice(_)) {
                    // Practice feedback stays up for a second.
                    h.run_steps(70);
                }
            }
            Phase::PracticeDone | Phase::Break => press(&mut h, Key::Space),
            Phase::Instructions => panic!("still at the instructions"),
            Phase::Finished => break,
        }
    }
    seen.dedup();
    use Phase::*;
    assert_eq!(
        seen,
        vec![
            Practice(0),
            PracticeDone,
            Trial(0),
            Trial(1),
            Break,
            Trial(2),
            Trial(3),
            Finished
        ]
    );
    press(&mut h, Key::Space);
    assert!(closed(&h), "Space on the end screen closes the window");

    let log = SessionLog::read(&log_path).unwrap();
    let d = log.header.display.as_ref().unwrap();
    assert_eq!((d.width, d.height, d.pixels_per_point), (1280, 720, 1.5));
    assert!((d.refresh_interval_ms - 1000.0 / 60.0).abs() < 1e-6);
    assert_eq!(log.header.mode, "gui");
    let responses: Vec<u8> = log.trials.iter().map(|t| t.response).collect();
    assert_eq!(responses, vec![1, 2, 1, 2, 1]);
    for t in &log.trials {
        assert_eq!(t.correct, t.response == t.diff_pair);
        // 60 repaints a second, 30 video frames: each of the 6 frames of both pairs is drawn
        // (twice), none skipped.
        assert_eq!(t.timing.frame_times_ms.len(), 12);
        assert_eq!(t.timing.dropped_frames, 0);
        assert_eq!(t.timing.onsets_ms.len(), 2);
        // Pair 2 starts after pair 1's 6 frames (0.2 s) and the 0.1 s gap.
        assert!(t.timing.onsets_ms[1] - t.timing.onsets_ms[0] >= 300.0 - 1e-6);
        assert!(
            t.timing.rt_ms > 0.0 && t.timing.rt_ms < 100.0,
            "rt {}",
            t.timing.rt_ms
        );
        assert_eq!(t.timing.pauses, 0);
    }
    assert!(log.trials[0].practice && log.main_trials().count() == 4);
}

#[test]
fn pause_restarts_the_presentation_and_quit_keeps_answers_for_resume() {
    let dir = tempfile::tempdir().unwrap();
    let study = study(dir.path());
    let (app, log_path) = open_app(&study, "k2");
    let mut h = harness(app, 1.0);
    start(&mut h);
    // Practice trial: pause while it plays, continue, answer.
    step_until(&mut h, "playback", |a| !a.loading());
    h.run_steps(10);
    press(&mut h, Key::Escape);
    assert!(h.state().paused());
    h.run_steps(30);
    // Answer keys do nothing while paused.
    press(&mut h, Key::Num1);
    assert_eq!(SessionLog::read(&log_path).unwrap().trials.len(), 0);
    press(&mut h, Key::Space);
    step_until(&mut h, "the response screen", SessionApp::responding);
    press(&mut h, Key::Num2);
    h.run_steps(70);
    let log = SessionLog::read(&log_path).unwrap();
    let t = &log.trials[0];
    assert_eq!(t.timing.pauses, 1);
    // Only the restarted, complete presentation is kept.
    assert_eq!(t.timing.frame_times_ms.len(), 12);
    assert_eq!(t.timing.onsets_ms.len(), 2);

    // End of practice, first main trial answered, then Esc + Q quits mid-session.
    press(&mut h, Key::Space);
    step_until(&mut h, "the response screen", SessionApp::responding);
    press(&mut h, Key::Num1);
    step_until(&mut h, "the second trial", |a| {
        a.loading() || a.responding()
    });
    press(&mut h, Key::Escape);
    press(&mut h, Key::Q);
    assert!(closed(&h));
    drop(h);
    let before = SessionLog::read(&log_path).unwrap();
    assert_eq!(before.trials.len(), 2);

    // Starting again continues at main trial 1 and writes a resume line.
    let (app, _) = open_app(&study, "k2");
    let mut h = harness(app, 1.0);
    assert!(h.state().session().resumed());
    start(&mut h);
    assert_eq!(h.state().session().phase(), Phase::Trial(1));
    step_until(&mut h, "the response screen", SessionApp::responding);
    h.get_by_label("Pair 2").click();
    h.step();
    let after = SessionLog::read(&log_path).unwrap();
    assert_eq!(after.resumes.len(), 1);
    assert_eq!(after.resumes[0].trials_done, 1);
    assert_eq!(after.trials.len(), 3);
    assert_eq!(after.trials[2].index, 1);
    assert_eq!(after.trials[..2], before.trials[..]);
}

#[test]
fn the_next_trial_loads_while_the_subject_answers() {
    let dir = tempfile::tempdir().unwrap();
    let study = study(dir.path());
    let (app, log_path) = open_app(&study, "k4");
    let mut h = harness(app, 1.0);
    start(&mut h);
    step_until(&mut h, "the response screen", SessionApp::responding);
    // The first trial had to load before it could start; the next one loads now (uploads begin
    // on the repaint after the question appeared).
    let session = h.state().session();
    let plan = experiment::trials::plan(session.design(), session.subject());
    if plan.practice[0].test_stimulus != plan.main[0].test_stimulus {
        assert!(h.state().prefetching());
    }
    step_until(&mut h, "the prefetch", |a| !a.prefetching());
    press(&mut h, Key::Num1);
    h.run_steps(70); // practice feedback
    press(&mut h, Key::Space); // end of practice
    step_until(&mut h, "the response screen", SessionApp::responding);
    press(&mut h, Key::Num1);
    let log = SessionLog::read(&log_path).unwrap();
    assert!(log.trials[0].timing.preload_ms > 0.0);
    // Nothing was left to load when trial 2 began: its wait was one repaint's bookkeeping.
    assert!(
        log.trials[1].timing.preload_ms < 5.0,
        "{}",
        log.trials[1].timing.preload_ms
    );
}

#[test]
fn videos_too_large_for_the_display_stop_before_the_session_starts() {
    let dir = tempfile::tempdir().unwrap();
    let study = study(dir.path());
    let (app, log_path) = open_app(&study, "k3");
    // 24-pixel videos side by side need 2 * 24 + 32 = 80 physical pixels.
    let mut h = Harness::builder()
        .with_size([79.0, 600.0])
        .with_step_dt(DT)
        .build_ui_state(|ui, app: &mut SessionApp| app.show(ui), app);
    start(&mut h);
    let e = h.state().fatal_error().unwrap().to_string();
    assert!(e.contains("80x16") && e.contains("79x600"), "{e}");
    assert!(
        !log_path.exists(),
        "no log is written for a session that cannot run"
    );
}

/// The app with no file system: the design parsed from text (its manifest nowhere), the log in
/// memory (`MemoryLog`) and the videos in memory (`MemoryFrames`): a whole QUEST+ session by
/// key presses, every frame of every trial drawn.
#[test]
fn a_session_runs_from_frames_and_a_log_in_memory() {
    let text = json!({
        "format": "blurlab-design/1", "name": "memory",
        "manifest": "stimuli/memory/manifest.json",
        "factors": {"scenes": ["alpha"], "point_sets": ["random"], "time_filters": ["box"]},
        "levels": [1, 8, 27], "seed": {"master": 3},
        "procedure": {"quest_plus": {"trials": 3}},
        "playback": {"loops": 1, "fixation_ms": 100, "gap_ms": 100}
    });
    let nowhere = Path::new("/nonexistent/blurlab/memory.json");
    let design = Design::parse(nowhere, &text.to_string()).unwrap();
    let mut frames = MemoryFrames::new();
    for (v, n) in needed_stimuli(&design).iter().enumerate() {
        let video = (0..6u8)
            .map(|f| RgbFrame {
                width: 24,
                height: 16,
                rgb: (0..24 * 16 * 3)
                    .map(|i| (i as u8) ^ (f * 40 + v as u8))
                    .collect(),
            })
            .collect();
        frames.insert(&n.id, 30.0, video).unwrap();
    }
    let log = MemoryLog::new("m1.jsonl");
    let session = Session::open_with(&design, "m1", Box::new(log.clone())).unwrap();
    let app = SessionApp::new(session, Arc::new(frames), Pacing::Vsync);
    let mut h = harness(app, 1.0);
    start(&mut h);
    loop {
        match h.state().session().phase() {
            Phase::Practice(_) | Phase::Trial(_) => {
                step_until(&mut h, "the response screen", SessionApp::responding);
                press(&mut h, Key::Num1);
                h.run_steps(70); // practice feedback, if any
            }
            Phase::PracticeDone | Phase::Break => press(&mut h, Key::Space),
            Phase::Instructions => panic!("still at the instructions"),
            Phase::Finished => break,
        }
    }
    assert_eq!(h.state().fatal_error(), None);
    let read = SessionLog::parse(Path::new("m1.jsonl"), log.bytes()).unwrap();
    assert_eq!(read.header.mode, "gui");
    assert_eq!(read.main_trials().count(), 3);
    for t in &read.trials {
        // 60 repaints a second, 30 video frames: each of the 6 frames of both pairs drawn
        // twice, none held back for want of a frame.
        assert_eq!(t.timing.frame_times_ms.len(), 12);
        assert_eq!(t.timing.dropped_frames, 0);
    }
}
