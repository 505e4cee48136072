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

#[cfg(feature = "gui")]
#[path = "support/lab.rs"]
mod lab;
use experiment::web::{Config, Server};
use fantoccini::actions::{InputSource, KeyAction, KeyActions};
use fantoccini::{Client, ClientBuilder};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const CHROMIUM: &str = "/usr/bin/chromium";
const CHROMEDRIVER: &str = "/usr/bin/chromedriver";
const REQUIRE: &str = "BLURLAB_REQUIRE_BROWSER_TESTS";
/// Longest a session (or a part of one) may take before the test fails.
const SESSION_TIMEOUT: Duration = Duration::from_secs(60);

/// The card the tests "hold" to the screen: this many device pixels per millimetre at scale 1.
const PX_PER_MM_AT_1: f64 = 3.0;
/// Where the tests "see" the dot vanish: this many millimetres from the cross.
const BLIND_SPOT_MM: f64 = 80.0;

/// Whether the browser is installed; panics when it must be and is not.
fn browser_available() -> bool {
    let present = Path::new(CHROMIUM).exists() && Path::new(CHROMEDRIVER).exists();
    if !present {
        assert!(
            std::env::var(REQUIRE).as_deref() != Ok("1"),
            "{REQUIRE}=1 but {CHROMIUM} or {CHROMEDRIVER} is missing: install Debian's chromium \
             and chromium-driver (.ci/run does)"
        );
        eprintln!("skipped: {CHROMIUM} or {CHROMEDRIVER} missing (set {REQUIRE}=1 to fail)");
    }
    present
}

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

/// `blurlab serve` in this process: the subject links and a sender that stops it.
struct Served {
    links: Vec<String>,
    stop: Option<tokio::sync::oneshot::Sender<()>>,
    task: tokio::task::JoinHandle<anyhow::Result<()>>,
    sessions: PathBuf,
}

async fn serve(design: &Path, out: &Path, subjects: u32) -> Served {
    let config = Config {
        design: design.to_path_buf(),
        out: out.to_path_buf(),
        addr: "127.0.0.1:0".parse().unwrap(),
        enrol: Some(subjects),
        open_enrolment: None,
        base_url: None,
    };
    let server = Server::bind(&config).await.expect("the server starts");
    let csv = std::fs::read_to_string(server.started.links_csv.as_ref().expect("links.csv"))
        .expect("links.csv reads");
    let links: Vec<String> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).expect("subject,url").trim().to_string())
        .collect();
    let sessions = server.started.sessions_dir.clone();
    let (tx, rx) = tokio::sync::oneshot::channel::<()>();
    let task = tokio::spawn(server.run(async {
        let _ = rx.await;
    }));
    Served {
        links,
        stop: Some(tx),
        task,
        sessions,
    }
}

impl Served {
    async fn shutdown(mut self) {
        if let Some(tx) = self.stop.take() {
            let _ = tx.send(());
        }
        let _ = tokio::time::timeout(Duration::from_secs(5), self.task).await;
    }
}

/// chromedriver and one headless Chromium session.
struct Browser {
    driver: Child,
    client: Client,
    _profile: tempfile::TempDir,
}

impl Browser {
    async fn start(scale: f64) -> Browser {
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .and_then(|l| l.local_addr())
            .expect("a free port")
            .port();
        let driver = Command::new(CHROMEDRIVER)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("chromedriver starts");
        let profile = tempfile::tempdir().unwrap();
        let args = vec![
            "--headless".to_string(),
            "--no-sandbox".into(),
            "--disable-gpu".into(),
            "--disable-quic".into(),
            "--no-first-run".into(),
            "--disable-background-networking".into(),
            "--disable-component-update".into(),
            "--disable-sync".into(),
            "--force-color-profile=srgb".into(),
            format!("--user-data-dir={}", profile.path().display()),
            "--window-size=1000,700".into(),
            format!("--force-device-scale-factor={scale}"),
        ];
        let caps = json!({
            "browserName": "chrome",
            "goog:chromeOptions": {"binary": CHROMIUM, "args": args},
        });
        let caps: fantoccini::wd::Capabilities = caps.as_object().unwrap().clone();
        let url = format!("http://127.0.0.1:{port}");
        let t0 = Instant::now();
        let client = loop {
            let connector = hyper_util::client::legacy::connect::HttpConnector::new();
            match ClientBuilder::new(connector)
                .capabilities(caps.clone())
                .connect(&url)
                .await
            {
                Ok(c) => break c,
                Err(e) if t0.elapsed() < Duration::from_secs(15) => {
                    let _ = e;
                    tokio::time::sleep(Duration::from_millis(100)).await;
                }
                Err(e) => panic!("no WebDriver session from {CHROMEDRIVER}: {e}"),
            }
        };
        Browser {
            driver,
            client,
            _profile: profile,
        }
    }

    async fn close(mut self) {
        let _ = self.client.close().await;
        let _ = self.driver.kill();
        let _ = self.driver.wait();
    }

    async fn js(&self, script: &str) -> Value {
        self.client
            .execute(script, vec![])
            .await
            .unwrap_or_else(|e| panic!("script {script}: {e}"))
    }

    async fn key(&self, key: char) {
        let keys = KeyActions::new("keys".into())
            .then(KeyAction::Down { value: key })
            .then(KeyAction::Up { value: key });
        self.client.perform_actions(keys).await.expect("key press");
    }

    /// The page's screen name, sequence number and test-visible data.
    async fn screen(&self) -> (String, u64, Value) {
        let v = self
            .js(
                "const d = document.body.dataset; return [d.screen, Number(d.seq), \
                 {cardPx: Number(d.cardPx || 0), dotPx: Number(d.dotPx || 0), trial: d.trial || '', \
                  title: document.getElementById('title').textContent, \
                  text: document.getElementById('text').textContent}]",
            )
            .await;
        (
            v[0].as_str().unwrap_or("").to_string(),
            v[1].as_u64().unwrap_or(0),
            v[2].clone(),
        )
    }
}

/// What the driver does at a respond screen: the answer to press (or None to stop there).
type OnRespond<'a> = &'a mut dyn FnMut(&str) -> Option<char>;

/// Drive the page as a subject would until the end screen (or until `on_respond` says stop):
/// Space through the text screens, the card matched to `PX_PER_MM_AT_1` x scale, the blind spot
/// at `BLIND_SPOT_MM`. Returns the last screen's name.
async fn drive(b: &Browser, scale: f64, on_respond: OnRespond<'_>) -> String {
    let t0 = Instant::now();
    let mut seen = 0;
    let card_target = (PX_PER_MM_AT_1 * scale * 85.6).round();
    loop {
        assert!(
            t0.elapsed() < SESSION_TIMEOUT,
            "the session took over {SESSION_TIMEOUT:?}"
        );
        let (screen, seq, data) = b.screen().await;
        if seq == seen && screen != "blindspot" {
            tokio::time::sleep(Duration::from_millis(10)).await;
            continue;
        }
        let fresh = seq != seen;
        seen = seq;
        match screen.as_str() {
            "welcome" => {
                b.js("window.blurlab.config.dotSpeedMmPerS = 200").await;
                b.key(' ').await;
            }
            "card-intro" | "blindspot-intro" | "blindspot-retry" | "instructions" | "break" => {
                b.key(' ').await
            }
            "card" => {
                let now = data["cardPx"].as_f64().unwrap();
                let (key, n) = if card_target > now {
                    ('\u{E014}', card_target - now) // ArrowRight
                } else {
                    ('\u{E012}', now - card_target) // ArrowLeft
                };
                for _ in 0..n as u32 {
                    b.key(key).await;
                }
                b.key('\u{E007}').await; // Enter
            }
            "blindspot" => {
                let px_per_mm = PX_PER_MM_AT_1 * scale;
                if data["dotPx"].as_f64().unwrap() >= BLIND_SPOT_MM * px_per_mm {
                    b.key(' ').await;
                } else {
                    tokio::time::sleep(Duration::from_millis(2)).await;
                }
            }
            "respond" if fresh => match on_respond(data["trial"].as_str().unwrap()) {
                Some(k) => b.key(k).await,
                None => return screen,
            },
            "done" => return screen,
            "elsewhere" | "error" | "too-small" | "unsupported" => {
                panic!(
                    "the page stopped: {screen}: {} {}",
                    data["title"], data["text"]
                )
            }
            _ => {}
        }
    }
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

/// Find the stimulus file whose bytes are `png` (the server sends the files unchanged).
fn stimulus_with_bytes(dir: &Path, png: &[u8]) -> Option<PathBuf> {
    for entry in std::fs::read_dir(dir).ok()? {
        let path = entry.ok()?.path();
        if path.is_dir() {
            if let Some(p) = stimulus_with_bytes(&path, png) {
                return Some(p);
            }
        } else if path.extension().is_some_and(|e| e == "png")
            && std::fs::read(&path).ok()?.as_slice() == png
        {
            return Some(path);
        }
    }
    None
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
    for (pair, frame) in [(1, 0), (2, 5), (1, 3)] {
        let held = b
            .js(&format!("return window.blurlab.hold({pair}, {frame})"))
            .await;
        let dpr = held["dpr"].as_f64().unwrap();
        assert_eq!(dpr, scale);
        // The canvas is the window in device pixels, its CSS box device px / dpr.
        let canvas = [
            held["canvas"][0].as_f64().unwrap(),
            held["canvas"][1].as_f64().unwrap(),
        ];
        let css = [
            held["css"][0].as_f64().unwrap(),
            held["css"][1].as_f64().unwrap(),
        ];
        assert_eq!([canvas[0] / scale, canvas[1] / scale], css, "{held}");
        for side in 0..2 {
            let r = &held["rects"][side];
            let (x, y, w, h) = (
                r["x"].as_u64().unwrap(),
                r["y"].as_u64().unwrap(),
                r["w"].as_u64().unwrap(),
                r["h"].as_u64().unwrap(),
            );
            let pixels = b
                .js(&format!(
                    "const c = document.getElementById('stage').getContext('2d'); \
                     return Array.from(c.getImageData({x}, {y}, {w}, {h}).data)"
                ))
                .await;
            let pixels: Vec<u8> = pixels
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_u64().unwrap() as u8)
                .collect();
            let url = held["urls"][side].as_str().unwrap();
            let png = b
                .client
                .execute_async(
                    "const done = arguments[arguments.length - 1]; \
                     fetch(arguments[0]).then(r => r.arrayBuffer()) \
                       .then(a => done(Array.from(new Uint8Array(a))))",
                    vec![json!(url)],
                )
                .await
                .unwrap();
            let png: Vec<u8> = png
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_u64().unwrap() as u8)
                .collect();
            let file = stimulus_with_bytes(&study.stimuli_dir, &png)
                .expect("the frame served is a stimulus file, byte for byte");
            let want = image::load_from_memory(&png).unwrap().to_rgba8();
            assert_eq!((want.width() as u64, want.height() as u64), (w, h));
            let mut differ = 0;
            for (i, (got, want)) in pixels.chunks(4).zip(want.pixels()).enumerate() {
                if got != want.0.as_slice() {
                    differ += 1;
                    if differ == 1 {
                        eprintln!("pixel {i}: canvas {got:?}, {} {:?}", file.display(), want.0);
                    }
                }
            }
            assert_eq!(
                differ,
                0,
                "{differ} of {} pixels differ at scale {scale}",
                w * h
            );
        }
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
