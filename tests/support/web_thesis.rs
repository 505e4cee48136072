//! Issue 48 in a real browser: a thesis-sized design (768x768, 210 frames at 30 fps, four videos
//! a trial) played whole in headless Chromium with its pixels exact, no dropped frame, Chromium's
//! memory and the wait before a trial within their targets, each video fetched once; and videos
//! served by a real nginx (Debian's package, started here unprivileged on its own port) while the
//! answers go to `blurlab serve`.

use super::browser::*;
use experiment::fixture::{Study, StudySpec, write_study};
use experiment::web::wire::ClientSettings;
use serde_json::json;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Chromium's peak memory while a thesis-sized trial plays (issue 48 item 3).
const PEAK_PSS_LIMIT: u64 = 1_200_000_000;
/// The wait before a trial, once its videos were fetched ahead.
const WAIT_LIMIT_MS: f64 = 1000.0;

/// The thesis-sized playback runs alone (write); the other browser tests share (read).
pub static ALONE: tokio::sync::RwLock<()> = tokio::sync::RwLock::const_new(());

/// The 1-minute load average (runnable processes), from /proc/loadavg.
fn load_average() -> f64 {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse().ok())
        .unwrap_or(0.0)
}

/// The thesis's video size, length and rate from the synthetic scene (drifting stripes and a
/// highlight, filtered over pixel and shutter by the point set's samples: real Monte Carlo noise
/// at low spp): one condition, a 1 spp test against a 2 spp reference, three main trials,
/// sequential pairs as in the thesis design with a shorter fixation and gap.
fn thesis_sized(root: &Path) -> Study {
    let mut spec = StudySpec::tiny();
    spec.name = "thesis_sized".into();
    spec.scenes = vec!["alpha".into()];
    spec.point_sets = vec!["hammersley".into()];
    spec.levels = vec![1];
    spec.reference_spp = 2;
    (spec.width, spec.height, spec.frames, spec.fps) = (768, 768, 210, 30.0);
    spec.design = json!({
        "repeats": 3, "practice": {"trials": 0}, "break_every": 0, "layout": "sequential",
        "playback": {"loops": 1, "fixation_ms": 100, "gap_ms": 300, "spacing_px": 32,
                     "background": [0, 0, 0]},
    });
    let t0 = Instant::now();
    let study = write_study(root, &spec).expect("the thesis-sized study renders");
    eprintln!(
        "thesis-sized stimuli rendered in {:.1} s",
        t0.elapsed().as_secs_f64()
    );
    study
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_thesis_sized_design_plays_exact_in_bounded_memory_without_dropped_frames() {
    if !browser_available() {
        return;
    }
    // Rendering, encoding and decoding 768x768 frames need the cores: no other browser test
    // runs meanwhile (their blind-spot polls and frame timing would starve).
    let _alone = ALONE.write().await;
    let dir = tempfile::tempdir().unwrap();
    let study = thesis_sized(dir.path());
    let t0 = Instant::now();
    let served = serve(&study.design_path, &dir.path().join("out"), 1).await;
    eprintln!("videos encoded in {:.1} s", t0.elapsed().as_secs_f64());
    let b = Browser::start_alone(1.0, [1700, 900]).await;
    let sampler = PssSampler::start(b.driver.id());
    b.client.goto(&served.links[0]).await.unwrap();
    let timeout = Duration::from_secs(180);
    let last = drive_for(&b, 1.0, &mut |t| (t != "m2").then_some('1'), timeout).await;
    assert_eq!(last, "respond");
    // The last trial's frames on the canvas are the stimulus PNGs', byte for byte.
    let manifest = study.stimuli_dir.join("manifest.json");
    for (pair, frame) in [(1, 0), (2, 209), (1, 105)] {
        held_frame_is_a_stimulus(&b, 1.0, &manifest, pair, frame).await;
    }
    // Each distinct video (the test and the reference) crossed the network once.
    let fetched = b.js("return window.blurlab.fetched()").await;
    let cache = dir.path().join("stimuli/thesis_sized/web");
    let pack_bytes: u64 = std::fs::read_dir(&cache)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "webpframes"))
        .map(|p| std::fs::metadata(p).unwrap().len())
        .sum();
    assert_eq!(fetched["fetches"], 2, "{fetched}");
    assert_eq!(fetched["bytes"].as_u64().unwrap(), pack_bytes, "{fetched}");
    b.key('1').await;
    let last = drive_for(&b, 1.0, &mut |_| Some('1'), timeout).await;
    assert_eq!(last, "done");
    let peak = sampler.stop();
    let load = load_average();
    b.close().await;
    let sessions = served.sessions.clone();
    served.shutdown().await;

    let lines = super::log_lines(&sessions);
    let trials: Vec<_> = lines.iter().filter(|l| l["kind"] == "trial").collect();
    assert_eq!(trials.len(), 3);
    let waits: Vec<f64> = trials
        .iter()
        .map(|t| t["preload_ms"].as_f64().unwrap())
        .collect();
    let dropped: Vec<u64> = trials
        .iter()
        .map(|t| t["dropped_frames"].as_u64().unwrap())
        .collect();
    let late: Vec<u64> = trials
        .iter()
        .map(|t| t["late_frames"].as_u64().unwrap())
        .collect();
    eprintln!(
        "thesis-sized: Chromium peak PSS {:.0} MB; waits before trials {waits:?} ms; dropped \
         {dropped:?}; late {late:?}; {} bytes fetched ({} PNG bytes); load average {load:.1}",
        peak as f64 / 1e6,
        fetched["bytes"],
        png_bytes(&study.stimuli_dir)
    );
    for t in &trials {
        let shown = t["frame_times_ms"].as_array().unwrap().len() as u64;
        assert_eq!(
            shown + t["dropped_frames"].as_u64().unwrap(),
            2 * 210,
            "{t}"
        );
    }
    assert!(
        peak <= PEAK_PSS_LIMIT,
        "Chromium's peak PSS {peak} B > {PEAK_PSS_LIMIT}"
    );
    // Decoding in time needs the machine's cores. With the load average within the core count
    // plus this test's own share (its render just before playback keeps the 1-minute average
    // above the core count for a while) at most 2% of a trial's frames may drop: run alone on
    // the 2-core machine it drops none, inside the whole suite 1 to 7 of 420 (docs/benchmarks/
    // web.md). Busier, CI (BLURLAB_REQUIRE_BROWSER_TESTS=1) still checks that playback degrades
    // gracefully (at most 10%); elsewhere the figures are printed (other builds on a shared
    // machine take the cores).
    let cores = std::thread::available_parallelism().map_or(2, |n| n.get()) as f64;
    let required = std::env::var(REQUIRE).is_ok_and(|v| v == "1");
    let quiet = load <= cores + 1.0;
    if !required && !quiet {
        eprintln!(
            "timing targets not checked: load average {load:.1} > {cores} cores + 1 (dropped \
             {dropped:?}, waits {waits:?} ms)"
        );
        return;
    }
    let allowed = if quiet { 2 * 210 / 50 } else { 2 * 210 / 10 };
    assert!(
        dropped.iter().all(|&d| d <= allowed),
        "dropped frames {dropped:?}, more than {allowed} a trial (load average {load:.1})"
    );
    assert!(
        waits[1..].iter().all(|&w| w <= WAIT_LIMIT_MS),
        "waits before trials 2 and 3: {waits:?} ms (load average {load:.1})"
    );
    assert!(
        peak <= PEAK_PSS_LIMIT,
        "Chromium's peak PSS {peak} B > {PEAK_PSS_LIMIT}"
    );
}

fn png_bytes(dir: &Path) -> u64 {
    let mut total = 0;
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            total += png_bytes(&p);
        } else if p.extension().is_some_and(|x| x == "png") {
            total += std::fs::metadata(&p).unwrap().len();
        }
    }
    total
}

const NGINX: &str = "/usr/sbin/nginx";

/// Debian's nginx as this user's process: its own port, pid, temp and log paths, serving
/// `root` under `/v/` with the CORS and cache headers docs/web.md gives.
struct Nginx {
    child: Child,
    access_log: std::path::PathBuf,
}

impl Nginx {
    fn start(dir: &Path, port: u16, root: &Path, allow_origin: &str) -> Nginx {
        let conf = dir.join("nginx.conf");
        let d = dir.display();
        let text = format!(
            "daemon off;\nmaster_process off;\nworker_processes 1;\npid {d}/nginx.pid;\n\
             error_log {d}/error.log;\nevents {{ worker_connections 64; }}\n\
             http {{\n  access_log {d}/access.log;\n  client_body_temp_path {d}/body;\n\
               proxy_temp_path {d}/proxy;\n  fastcgi_temp_path {d}/fastcgi;\n\
               uwsgi_temp_path {d}/uwsgi;\n  scgi_temp_path {d}/scgi;\n\
               server {{\n    listen 127.0.0.1:{port};\n    location /v/ {{\n\
                   alias {}/;\n      types {{ }}\n      default_type application/octet-stream;\n\
                   add_header Access-Control-Allow-Origin \"{allow_origin}\" always;\n\
                   add_header Cache-Control \"public, max-age=31536000, immutable\" always;\n\
                   add_header X-Content-Type-Options nosniff always;\n    }}\n  }}\n}}\n",
            root.display()
        );
        std::fs::write(&conf, text).unwrap();
        let child = Command::new(NGINX)
            .arg("-p")
            .arg(dir)
            .arg("-c")
            .arg(&conf)
            .arg("-e")
            .arg(dir.join("error.log"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("nginx starts");
        let t0 = Instant::now();
        while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
            assert!(
                t0.elapsed() < Duration::from_secs(10),
                "nginx did not listen: {}",
                std::fs::read_to_string(dir.join("error.log")).unwrap_or_default()
            );
            std::thread::sleep(Duration::from_millis(20));
        }
        Nginx {
            child,
            access_log: dir.join("access.log"),
        }
    }
}

impl Drop for Nginx {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .unwrap()
        .port()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn videos_served_by_nginx_play_exact_while_answers_go_to_the_server() {
    if !browser_available() {
        return;
    }
    if !Path::new(NGINX).exists() {
        assert!(
            std::env::var(REQUIRE).as_deref() != Ok("1"),
            "{REQUIRE}=1 but {NGINX} is missing: install Debian's nginx (.ci/run does)"
        );
        eprintln!("skipped: {NGINX} missing (set {REQUIRE}=1 to fail)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let study = super::study(dir.path(), None);
    let out = dir.path().join("out");
    let videos = dir.path().join("videos");
    let nginx_port = free_port();
    let client = ClientSettings {
        video_base: Some(format!("http://127.0.0.1:{nginx_port}/v")),
        ..ClientSettings::default()
    };
    let config = config(&study.design_path, &out, 1, client.clone());
    let exported = experiment::web::export::export(&config, &videos, &mut |_, _, _| {}).unwrap();
    assert!(exported.videos > 0);
    let served = serve_with(&study.design_path, &out, 1, client).await;
    let origin = served.links[0].split("/s/").next().unwrap().to_string();
    let nginx_dir = dir.path().join("nginx");
    std::fs::create_dir_all(&nginx_dir).unwrap();
    let nginx = Nginx::start(&nginx_dir, nginx_port, &videos, &origin);

    let b = Browser::start(1.0).await;
    b.client.goto(&served.links[0]).await.unwrap();
    let last = drive(&b, 1.0, &mut |t| (t != "m1").then_some('2')).await;
    assert_eq!(last, "respond");
    let manifest = study.stimuli_dir.join("manifest.json");
    for (pair, frame) in [(1, 0), (2, 5)] {
        held_frame_is_a_stimulus(&b, 1.0, &manifest, pair, frame).await;
    }
    b.key('2').await;
    let last = drive(&b, 1.0, &mut |_| Some('2')).await;
    assert_eq!(last, "done");
    let fetched = b.js("return window.blurlab.fetched()").await;
    b.close().await;
    let sessions = served.sessions.clone();
    served.shutdown().await;

    // Every video the page fetched came from nginx, each once, and the answers are logged.
    let log = std::fs::read_to_string(&nginx.access_log).unwrap();
    let gets: Vec<&str> = log
        .lines()
        .filter(|l| l.contains("GET /v/") && l.contains(".webpframes"))
        .collect();
    let ok: Vec<u64> = gets
        .iter()
        .filter_map(|l| {
            let after = l.split('"').nth(2)?;
            let mut f = after.split_whitespace();
            (f.next()? == "200")
                .then(|| f.next()?.parse().ok())
                .flatten()
        })
        .collect();
    assert_eq!(ok.len(), gets.len(), "{log}");
    assert_eq!(
        ok.len() as u64,
        fetched["fetches"].as_u64().unwrap(),
        "{log}"
    );
    assert_eq!(ok.iter().sum::<u64>(), fetched["bytes"].as_u64().unwrap());
    let mut names: Vec<&str> = gets.iter().filter_map(|l| l.split(' ').nth(6)).collect();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), gets.len(), "a video fetched twice: {log}");
    let trials = super::log_lines(&sessions)
        .into_iter()
        .filter(|l| l["kind"] == "trial")
        .count();
    assert!(trials >= 3, "{trials} trials logged");
}
