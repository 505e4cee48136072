//! The browser client in a real browser (issue 39): headless Chromium driven through WebDriver
//! (chromedriver, via the `fantoccini` crate) against `blurlab serve` started in this process on
//! 127.0.0.1 at a random port. Whole sessions with key presses, calibration included (the demo
//! design cut short, and a QUEST+ design), whose logs `blurlab analyze --design` then reads, the
//! demo's together with a lab session of it at the app; the canvas read back pixel for pixel against the
//! stimulus PNG at device scale 1 and 2; a reload that resumes at the next trial and a second tab
//! that is refused.
//!
//! Needs Debian's `chromium` and `chromium-driver` (`.ci/run` installs them). Without them the
//! tests say so and pass, unless `BLURLAB_REQUIRE_BROWSER_TESTS=1` (set by `.ci/run`), which
//! makes a missing browser a failure.

use experiment::fixture::{Study, StudySpec, write_study};

#[path = "support/browser.rs"]
mod browser;
#[cfg(feature = "gui")]
#[path = "support/lab.rs"]
mod lab;
#[path = "support/web_thesis.rs"]
mod web_thesis;
use browser::*;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

/// A small demo-like study: 24x16 px videos of 6 frames, short fixation and gap.
fn study(root: &Path, procedure: Option<Value>) -> Study {
    let mut spec = StudySpec::tiny();
    spec.design = json!({
        "repeats": 1, "practice": {"trials": 1}, "break_every": 3,
        "playback": {"fixation_ms": 100, "gap_ms": 100, "spacing_px": 8,
                     "background": [128, 128, 128]},
    });
    if let Some(p) = procedure {
        spec.design["procedure"] = p;
        spec.levels = vec![1, 8, 27];
        spec.reference_spp = 64;
    }
    write_study(root, &spec).expect("the fixture study renders")
}

/// The log's lines as JSON.
fn log_lines(sessions: &Path) -> Vec<Value> {
    let mut logs: Vec<_> = std::fs::read_dir(sessions)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "jsonl"))
        .collect();
    assert_eq!(logs.len(), 1, "one subject's log in {}", sessions.display());
    let text = std::fs::read_to_string(logs.pop().unwrap()).unwrap();
    text.lines()
        .map(|l| serde_json::from_str(l).expect("a JSON line"))
        .collect()
}

/// Check the header's browser display facts and each trial's timing, then run
/// `blurlab analyze --design` on the sessions; returns the main trials' indices.
fn check_log_and_analyze(
    design: &Path,
    frames_per_trial: usize,
    sessions: &Path,
    out: &Path,
) -> Vec<u64> {
    let lines = log_lines(sessions);
    let header = &lines[0];
    assert_eq!(header["mode"], "web", "{header}");
    let browser = &header["display"]["browser"];
    let px_per_mm = browser["px_per_mm"].as_f64().expect("px_per_mm logged");
    let want = (PX_PER_MM_AT_1 * 85.6).round() / 85.6;
    assert!(
        (px_per_mm - want).abs() < 1e-9,
        "px/mm {px_per_mm}, pressed {want}"
    );
    // The dot moves a few pixels between the test's polls: the press lands at or just past
    // 80 mm, so the distance is 80 / tan(13.5 deg) = 333.2 mm or somewhat more.
    let d = browser["viewing_distance_mm"].as_f64().unwrap();
    let d0 = BLIND_SPOT_MM / 13.5f64.to_radians().tan();
    assert!(
        d >= d0 - 0.5 && d < d0 * 1.15,
        "viewing distance {d} mm, expected ~{d0:.1}"
    );
    let ppd = browser["pixels_per_degree"].as_f64().unwrap();
    let ppd0 = px_per_mm * 2.0 * d * 0.5f64.to_radians().tan();
    assert!((ppd - ppd0).abs() < 1e-6, "ppd {ppd} vs {ppd0}");
    let mut main = Vec::new();
    for t in lines.iter().filter(|l| l["kind"] == "trial") {
        let shown = t["frame_times_ms"].as_array().expect("frame times").len() as u64;
        let dropped = t["dropped_frames"].as_u64().unwrap();
        // Both pairs' frames over every loop, each either shown or dropped.
        assert_eq!(shown + dropped, frames_per_trial as u64, "{t}");
        assert_eq!(t["onsets_ms"].as_array().unwrap().len(), 2, "{t}");
        assert!(t["refresh_interval_ms"].as_f64().unwrap() > 0.0, "{t}");
        if t["practice"] == false {
            main.push(t["index"].as_u64().unwrap());
        }
    }
    analyze(&[sessions], design, out);
    main
}

/// `blurlab analyze --design` on the given logs or folders; returns report.md.
fn analyze(logs: &[&Path], design: &Path, out: &Path) -> String {
    blurlab(
        Command::new(env!("CARGO_BIN_EXE_blurlab"))
            .arg("analyze")
            .args(logs)
            .arg("--design")
            .arg(design)
            .arg("--out")
            .arg(out),
    );
    std::fs::read_to_string(out.join("report.md")).expect("report.md")
}

/// Run a `blurlab` command; fails the test with its stderr if it fails.
fn blurlab(command: &mut Command) {
    let output = command.output().expect("blurlab runs");
    assert!(
        output.status.success(),
        "{command:?} failed:\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
}

/// Answer "pair 1" and "pair 2" in turn.
fn alternate() -> impl FnMut(&str) -> Option<char> {
    let mut n = 0;
    move |_| {
        n += 1;
        Some(if n % 2 == 0 { '2' } else { '1' })
    }
}

/// One subject's whole browser session of the design at `design` (a server under `dir/out`),
/// its log checked (`frames_per_trial` frames each) and analyzed; returns the sessions folder.
async fn browser_session(design: &Path, frames_per_trial: usize, dir: &Path) -> PathBuf {
    let served = serve(design, &dir.join("out"), 1).await;
    let b = Browser::start(1.0).await;
    b.client
        .goto(&served.links[0])
        .await
        .expect("the link opens");
    let last = drive(&b, 1.0, &mut alternate()).await;
    assert_eq!(last, "done");
    b.close().await;
    let sessions = served.sessions.clone();
    served.shutdown().await;
    let main = check_log_and_analyze(design, frames_per_trial, &sessions, &dir.join("report"));
    let want: Vec<u64> = (0..main.len() as u64).collect();
    assert_eq!(main, want, "every main trial once, in order");
    assert!(!main.is_empty());
    sessions
}

/// The demo's job and design (`scenes/demo/job.json`, `scenes/demo/design.json`) cut to a
/// short session: one point set, levels 1 and 125, one repeat (4 main trials and the demo's 3
/// practice trials), everything else (stimuli, playback, keys, layout) the demo's own.
/// Renders its stimuli under `root` and returns the design's path.
fn short_demo(root: &Path) -> PathBuf {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let read =
        |p: &Path| -> Value { serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap() };
    let mut job = read(&scenes.join("demo/job.json"));
    job["scenes"] = json!([
        scenes.join("thesis/plane.json"),
        scenes.join("thesis/spheres.json")
    ]);
    job["point_sets"] = json!(["hammersley"]);
    job["levels"] = json!([1, 125]);
    let job_path = root.join("job.json");
    std::fs::write(&job_path, job.to_string()).unwrap();
    let job = renderer::job::Job::load(&job_path).unwrap();
    let opts = renderer::job::RunOptions::new(root.join("stimuli"));
    renderer::job::run(&job, &opts, &renderer::progress::NoProgress).expect("the demo renders");
    let mut design = read(&scenes.join("demo/design.json"));
    design["manifest"] = json!("stimuli/demo/manifest.json");
    design["factors"]["point_sets"] = json!(["hammersley"]);
    design["levels"] = json!([1, 125]);
    design["repeats"] = json!(1);
    let path = root.join("demo_short.json");
    std::fs::write(&path, design.to_string()).unwrap();
    path
}

async fn whole_session(procedure: Option<Value>) {
    if !browser_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let study = study(dir.path(), procedure);
    // 2 pairs x 6 frames x 1 loop.
    browser_session(&study.design_path, 12, dir.path()).await;
}

/// The demo design (cut short) in the browser, then the same design at the lab app: the two
/// logs analyze together and the report counts one session of each mode; `predict --viewer`
/// predicts at the browser subject's own pixels per degree.
#[cfg(feature = "gui")]
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn browser_and_lab_sessions_of_the_demo_design_analyze_together() {
    if !browser_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let design = short_demo(dir.path());
    // 2 pairs x 6 frames x 2 loops.
    let web = browser_session(&design, 24, dir.path()).await;
    let lab = dir.path().join("lab");
    std::fs::create_dir_all(&lab).unwrap();
    lab::run(&design, "lab1", &lab.join("lab1.jsonl"));
    let report = analyze(&[&web, &lab], &design, &dir.path().join("both"));
    assert!(
        report.contains("2 subjects, 8 main trials from 2 session logs")
            && report.contains("Sessions: 1 lab (`gui`), 1 web (`blurlab serve`)."),
        "{report}"
    );
    let log = std::fs::read_dir(&web)
        .unwrap()
        .next()
        .unwrap()
        .unwrap()
        .path();
    let ppd = log_lines(&web)[0]["display"]["browser"]["pixels_per_degree"]
        .as_f64()
        .unwrap();
    let predicted = dir.path().join("predict");
    blurlab(
        Command::new(env!("CARGO_BIN_EXE_blurlab"))
            .arg("predict")
            .arg(dir.path().join("stimuli/demo"))
            .arg("--design")
            .arg(&design)
            .arg("--viewer")
            .arg(&log)
            .arg("--out")
            .arg(&predicted)
            .arg("--no-progress"),
    );
    let md = std::fs::read_to_string(predicted.join("predict.md")).unwrap();
    assert!(
        md.contains(&format!("({ppd:.1} px/deg)")),
        "ppd {ppd}:\n{md}"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn browser_session_quest_plus_analyzes() {
    whole_session(Some(json!({"quest_plus": {"trials": 3}}))).await;
}

async fn canvas_matches_stimulus(scale: f64) {
    if !browser_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let study = study(dir.path(), None);
    let served = serve(&study.design_path, &dir.path().join("out"), 1).await;
    let b = Browser::start(scale).await;
    b.client.goto(&served.links[0]).await.unwrap();
    let last = drive(&b, scale, &mut |_| None).await;
    assert_eq!(last, "respond");
    let manifest = study.stimuli_dir.join("manifest.json");
    for (pair, frame) in [(1, 0), (2, 5), (1, 3)] {
        held_frame_is_a_stimulus(&b, scale, &manifest, pair, frame).await;
    }
    b.close().await;
    served.shutdown().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn canvas_reads_back_the_stimulus_pixel_for_pixel_at_scale_1() {
    canvas_matches_stimulus(1.0).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn canvas_reads_back_the_stimulus_pixel_for_pixel_at_scale_2() {
    canvas_matches_stimulus(2.0).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn reload_resumes_at_the_next_trial_and_a_second_tab_is_refused() {
    if !browser_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let study = study(dir.path(), None);
    let served = serve(&study.design_path, &dir.path().join("out"), 1).await;
    let b = Browser::start(1.0).await;
    let link = served.links[0].clone();
    b.client.goto(&link).await.unwrap();
    // Answer the practice trial and main trial 0, stop at main trial 1's answer screen.
    let mut answered = Vec::new();
    let last = drive(&b, 1.0, &mut |t| {
        if t == "m1" {
            return None;
        }
        answered.push(t.to_string());
        Some('1')
    })
    .await;
    assert_eq!(last, "respond");
    assert_eq!(answered, ["p0", "m0"]);

    // A second tab on the same link is told the session is open elsewhere.
    let first = b.client.window().await.unwrap();
    let second = b.client.new_window(true).await.unwrap();
    b.client.switch_to_window(second.handle).await.unwrap();
    b.client.goto(&link).await.unwrap();
    let t0 = Instant::now();
    loop {
        let (screen, _, data) = b.screen().await;
        if screen == "elsewhere" {
            assert!(
                data["text"].as_str().unwrap().contains("another tab"),
                "{data}"
            );
            break;
        }
        assert!(
            t0.elapsed() < Duration::from_secs(10),
            "second tab shows {screen}"
        );
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    b.client.close_window().await.unwrap();
    b.client.switch_to_window(first).await.unwrap();

    // A reload mid-trial resumes at the trial not yet answered, then at the next ones.
    b.client.refresh().await.unwrap();
    let mut after = Vec::new();
    let last = drive(&b, 1.0, &mut |t| {
        after.push(t.to_string());
        Some('2')
    })
    .await;
    assert_eq!(last, "done");
    assert_eq!(after.first().map(String::as_str), Some("m1"), "{after:?}");
    b.close().await;
    let sessions = served.sessions.clone();
    served.shutdown().await;
    let main = check_log_and_analyze(
        &study.design_path,
        12,
        &sessions,
        &dir.path().join("report"),
    );
    let want: Vec<u64> = (0..main.len() as u64).collect();
    assert_eq!(
        main, want,
        "every main trial exactly once across the reload"
    );
}

/// A platform study (issue 49) on `port`: consent and debriefing texts, catch trials, the
/// completion and screen-out URLs on this server, and `refresh_hz` as the screening range.
fn platform_study(root: &Path, port: u16, refresh_hz: [f64; 2]) -> Study {
    let mut spec = StudySpec::tiny();
    spec.design = json!({
        "repeats": 1, "practice": {"trials": 1}, "break_every": 0,
        "playback": {"fixation_ms": 100, "gap_ms": 100, "spacing_px": 8},
        "catch_trials": {"rate": 0.25},
        "online": {"platform": "prolific",
                   "completion_url": format!("http://127.0.0.1:{port}/complete?cc={{code}}"),
                   "completion_code": "C0MPLETE",
                   "screen_out_url": format!("http://127.0.0.1:{port}/screened?cc={{code}}"),
                   "screen_out_code": "SCREENED",
                   "consent": "consent.txt", "debriefing": "debriefing.txt",
                   "screening": {"refresh_hz": refresh_hz}},
    });
    std::fs::create_dir_all(root).unwrap();
    std::fs::write(root.join("consent.txt"), "You agree to take part.").unwrap();
    std::fs::write(root.join("debriefing.txt"), "The study measured noise.").unwrap();
    write_study(root, &spec).expect("the fixture study renders")
}

/// Serve `study` with open enrolment on `port`; its study link, without the query.
async fn serve_platform(study: &Study, out: &Path, port: u16) -> (Served, String) {
    let mut config = config(&study.design_path, out, 1, Default::default());
    config.enrol = None;
    config.open_enrolment = Some(10);
    config.addr = format!("127.0.0.1:{port}").parse().unwrap();
    let served = serve_config(config).await;
    let join = served.join_url.clone().expect("open enrolment");
    (served, join)
}

fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .unwrap()
        .port()
}

/// Answer the consent screen with `key` and wait until the page leaves it.
async fn answer_consent(b: &Browser, key: char) {
    b.key(key).await;
    let t0 = Instant::now();
    while b.screen().await.0 == "consent" {
        assert!(
            t0.elapsed() < Duration::from_secs(10),
            "the consent screen stays"
        );
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
}

/// Press `key` at the current screen (again every 300 ms: the page ignores keys for a moment
/// after showing an end screen) until the page is at `url`.
async fn leave_for(b: &Browser, key: char, url: &str) {
    let t0 = Instant::now();
    loop {
        let now = b.client.current_url().await.unwrap().to_string();
        if now == url {
            return;
        }
        assert!(
            t0.elapsed() < Duration::from_secs(10),
            "at {now}, not {url}"
        );
        b.key(key).await;
        tokio::time::sleep(Duration::from_millis(300)).await;
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_prolific_participant_consents_completes_and_lands_on_the_completion_url() {
    if !browser_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let port = free_port();
    let study = platform_study(&dir.path().join("a"), port, [20.0, 400.0]);
    let (served, join) = serve_platform(&study, &dir.path().join("out"), port).await;
    let link = |pid: &str| format!("{join}?PROLIFIC_PID={pid}&STUDY_ID=s1&SESSION_ID=x{pid}");
    let b = Browser::start(1.0).await;

    // Consent, a short session with catch trials, the debriefing, the completion URL.
    b.client.goto(&link("pA")).await.unwrap();
    assert_eq!(drive(&b, 1.0, &mut alternate()).await, "consent");
    let subject_url = b.client.current_url().await.unwrap().to_string();
    answer_consent(&b, 'y').await;
    assert_eq!(drive(&b, 1.0, &mut alternate()).await, "done");
    let (_, _, data) = b.screen().await;
    assert!(
        data["text"].as_str().unwrap().contains("measured noise"),
        "{data}"
    );
    leave_for(
        &b,
        ' ',
        &format!("http://127.0.0.1:{port}/complete?cc=C0MPLETE"),
    )
    .await;
    let lines = log_lines(&served.sessions);
    assert_eq!(lines[0]["participant"]["ids"]["PROLIFIC_PID"], "pA");
    assert!(lines[0]["participant"]["consent"]["text_sha256"].is_string());
    assert!(
        lines.iter().any(|l| l["catch"] == true),
        "catch trials logged"
    );

    // A second visit with the same id goes back to the same subject.
    b.client.goto(&link("pA")).await.unwrap();
    assert_eq!(drive(&b, 1.0, &mut alternate()).await, "done");
    assert_eq!(
        b.client.current_url().await.unwrap().to_string(),
        subject_url
    );

    // A declined consent: the screen-out URL, and no log.
    b.client.goto(&link("pB")).await.unwrap();
    assert_eq!(drive(&b, 1.0, &mut alternate()).await, "consent");
    answer_consent(&b, 'n').await;
    assert_eq!(drive(&b, 1.0, &mut alternate()).await, "screened-out");
    leave_for(
        &b,
        ' ',
        &format!("http://127.0.0.1:{port}/screened?cc=SCREENED"),
    )
    .await;
    log_lines(&served.sessions); // still exactly one log: pA's
    served.shutdown().await;

    // A display check that fails (the headless display's refresh is outside 200-400 Hz).
    let port = free_port();
    let strict = platform_study(&dir.path().join("b"), port, [200.0, 400.0]);
    let (served, join) = serve_platform(&strict, &dir.path().join("out-b"), port).await;
    b.client
        .goto(&format!("{join}?PROLIFIC_PID=pC"))
        .await
        .unwrap();
    assert_eq!(drive(&b, 1.0, &mut alternate()).await, "consent");
    answer_consent(&b, 'y').await;
    assert_eq!(drive(&b, 1.0, &mut alternate()).await, "screened-out");
    leave_for(
        &b,
        ' ',
        &format!("http://127.0.0.1:{port}/screened?cc=SCREENED"),
    )
    .await;
    let logs = std::fs::read_dir(&served.sessions).unwrap().count();
    assert_eq!(
        logs, 0,
        "a participant screened out at the display check writes no log"
    );
    b.close().await;
    served.shutdown().await;
}
