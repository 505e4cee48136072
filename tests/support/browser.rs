//! Headless Chromium through chromedriver (the `fantoccini` crate) against `blurlab serve`
//! started in the test's process on 127.0.0.1 at a random port, driven as a subject would drive
//! it; the canvas read back against the stimulus PNGs. Shared by the browser tests.
#![allow(dead_code)]

use experiment::web::wire::ClientSettings;
use experiment::web::{Config, Server};
use fantoccini::actions::{InputSource, KeyAction, KeyActions};
use fantoccini::{Client, ClientBuilder};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

pub const CHROMIUM: &str = "/usr/bin/chromium";
pub const CHROMEDRIVER: &str = "/usr/bin/chromedriver";
pub const REQUIRE: &str = "BLURLAB_REQUIRE_BROWSER_TESTS";
/// Longest a session (or a part of one) may take before the test fails.
pub const SESSION_TIMEOUT: Duration = Duration::from_secs(60);

/// The card the tests "hold" to the screen: this many device pixels per millimetre at scale 1.
pub const PX_PER_MM_AT_1: f64 = 3.0;
/// Where the tests "see" the dot vanish: this many millimetres from the cross.
pub const BLIND_SPOT_MM: f64 = 80.0;

/// Whether the browser is installed; panics when it must be and is not.
pub fn browser_available() -> bool {
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

/// `blurlab serve` in this process: the subject links and a sender that stops it.
pub struct Served {
    pub links: Vec<String>,
    /// The open-enrolment link, when the config asks for one.
    pub join_url: Option<String>,
    stop: Option<tokio::sync::oneshot::Sender<()>>,
    task: tokio::task::JoinHandle<anyhow::Result<()>>,
    pub sessions: PathBuf,
}

pub async fn serve(design: &Path, out: &Path, subjects: u32) -> Served {
    serve_with(design, out, subjects, ClientSettings::default()).await
}

pub async fn serve_with(
    design: &Path,
    out: &Path,
    subjects: u32,
    client: ClientSettings,
) -> Served {
    serve_config(config(design, out, subjects, client)).await
}

/// Serve `config`: the links of `links.csv` (if enrolled) and the open-enrolment link.
pub async fn serve_config(config: Config) -> Served {
    let server = Server::bind(&config).await.expect("the server starts");
    let csv = match &server.started.links_csv {
        Some(path) => std::fs::read_to_string(path).expect("links.csv reads"),
        None => String::new(),
    };
    let links: Vec<String> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).expect("subject,url").trim().to_string())
        .collect();
    let join_url = server.started.join_url.clone();
    let sessions = server.started.sessions_dir.clone();
    let (tx, rx) = tokio::sync::oneshot::channel::<()>();
    let task = tokio::spawn(server.run(async {
        let _ = rx.await;
    }));
    Served {
        links,
        join_url,
        stop: Some(tx),
        task,
        sessions,
    }
}

impl Served {
    pub async fn shutdown(mut self) {
        if let Some(tx) = self.stop.take() {
            let _ = tx.send(());
        }
        let _ = tokio::time::timeout(Duration::from_secs(5), self.task).await;
    }
}

/// A server's configuration on 127.0.0.1 at a free port.
pub fn config(design: &Path, out: &Path, subjects: u32, client: ClientSettings) -> Config {
    Config {
        design: design.to_path_buf(),
        out: out.to_path_buf(),
        addr: "127.0.0.1:0".parse().unwrap(),
        enrol: Some(subjects),
        open_enrolment: None,
        base_url: None,
        client,
        limits: Default::default(),
        connections: Default::default(),
        check_hashes: true,
    }
}

/// chromedriver and one headless Chromium session.
pub struct Browser {
    pub driver: Child,
    pub client: Client,
    _shared: Option<tokio::sync::RwLockReadGuard<'static, ()>>,
    _profile: tempfile::TempDir,
}

impl Browser {
    /// A small browser (1000 x 700 CSS pixels), sharing the cores with the others.
    pub async fn start(scale: f64) -> Browser {
        let shared = super::web_thesis::ALONE.read().await;
        Self::launch(scale, [1000, 700], Some(shared)).await
    }

    /// A browser whose window is `size` CSS pixels, for a test that already holds
    /// `web_thesis::ALONE` for writing (it plays alone).
    pub async fn start_alone(scale: f64, size: [u32; 2]) -> Browser {
        Self::launch(scale, size, None).await
    }

    async fn launch(
        scale: f64,
        size: [u32; 2],
        shared: Option<tokio::sync::RwLockReadGuard<'static, ()>>,
    ) -> Browser {
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
            format!("--window-size={},{}", size[0], size[1]),
            // Headless Chromium's screen is 800x600 unless told (full screen is the screen).
            format!(
                "--screen-info={{0,0 {}x{}}}",
                size[0].max(800),
                size[1].max(600)
            ),
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
            _shared: shared,
        }
    }

    pub async fn close(mut self) {
        let _ = self.client.close().await;
        let _ = self.driver.kill();
        let _ = self.driver.wait();
    }

    pub async fn js(&self, script: &str) -> Value {
        self.client
            .execute(script, vec![])
            .await
            .unwrap_or_else(|e| panic!("script {script}: {e}"))
    }

    pub async fn key(&self, key: char) {
        let keys = KeyActions::new("keys".into())
            .then(KeyAction::Down { value: key })
            .then(KeyAction::Up { value: key });
        self.client.perform_actions(keys).await.expect("key press");
    }

    /// The page's screen name, sequence number and test-visible data.
    pub async fn screen(&self) -> (String, u64, Value) {
        let v = self
            .js(
                "const d = document.body ? document.body.dataset : {}; return [d.screen, Number(d.seq), \
                 {cardPx: Number(d.cardPx || 0), dotPx: Number(d.dotPx || 0), trial: d.trial || '', \
                  title: document.getElementById('title')?.textContent || '', \
                  text: document.getElementById('text')?.textContent || ''}]",
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
pub type OnRespond<'a> = &'a mut dyn FnMut(&str) -> Option<char>;

/// Drive the page as a subject would until the end screen (or until `on_respond` says stop):
/// Space through the text screens, the card matched to `PX_PER_MM_AT_1` x scale, the blind spot
/// at `BLIND_SPOT_MM`. Returns the last screen's name.
pub async fn drive(b: &Browser, scale: f64, on_respond: OnRespond<'_>) -> String {
    drive_for(b, scale, on_respond, SESSION_TIMEOUT).await
}

/// [`drive`] with its own time limit.
pub async fn drive_for(
    b: &Browser,
    scale: f64,
    on_respond: OnRespond<'_>,
    timeout: Duration,
) -> String {
    let t0 = Instant::now();
    let mut seen = 0;
    let card_target = (PX_PER_MM_AT_1 * scale * 85.6).round();
    let mut last = String::new();
    loop {
        assert!(
            t0.elapsed() < timeout,
            "the session took over {timeout:?} (at screen {last:?})"
        );
        let (screen, seq, data) = b.screen().await;
        last.clone_from(&screen);
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
            "done" | "consent" | "screened-out" => return screen,
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

/// Frame `n` of every stimulus in the set at `manifest`, decoded from its PNG as RGBA.
pub fn stimulus_frames(manifest: &Path, n: usize) -> Vec<(String, image::RgbaImage)> {
    let m = renderer::manifest::Manifest::load(manifest).unwrap();
    let folder = manifest.parent().unwrap();
    m.stimuli
        .iter()
        .map(|s| {
            let png = image::open(folder.join(&s.frame_paths[n]))
                .unwrap()
                .to_rgba8();
            (s.id.clone(), png)
        })
        .collect()
}

/// Hold frame `frame` of pair `pair` on the page and read the canvas back: each video's
/// rectangle must equal, byte for byte, frame `frame` of a stimulus PNG of the set (the one the
/// server chose; the page never learns which). Returns the stimuli matched.
pub async fn held_frame_is_a_stimulus(
    b: &Browser,
    scale: f64,
    manifest: &Path,
    pair: u32,
    frame: usize,
) -> Vec<String> {
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
    let pngs = stimulus_frames(manifest, frame);
    let mut matched = Vec::new();
    for side in 0..2 {
        let r = &held["rects"][side];
        let (x, y, w, h) = (
            r["x"].as_u64().unwrap(),
            r["y"].as_u64().unwrap(),
            r["w"].as_u64().unwrap(),
            r["h"].as_u64().unwrap(),
        );
        // Base64 keeps a 768x768 read-back small enough for WebDriver's JSON.
        let encoded = b
            .js(&format!(
                "const c = document.getElementById('canvas').getContext('2d'); \
                 const d = c.getImageData({x}, {y}, {w}, {h}).data; let s = ''; \
                 for (let i = 0; i < d.length; i += 0x8000) \
                   s += String.fromCharCode.apply(null, d.subarray(i, i + 0x8000)); \
                 return btoa(s)"
            ))
            .await;
        let pixels = base64_decode(encoded.as_str().unwrap());
        assert_eq!(pixels.len() as u64, w * h * 4);
        let found = pngs.iter().find(|(_, png)| {
            (png.width() as u64, png.height() as u64) == (w, h) && png.as_raw() == &pixels
        });
        match found {
            Some((id, _)) => matched.push(id.clone()),
            None => {
                let (id, png) = &pngs[0];
                let differ = pixels
                    .chunks(4)
                    .zip(png.pixels())
                    .filter(|(a, b)| *a != b.0.as_slice())
                    .count();
                panic!(
                    "pair {pair} side {side} frame {frame} at scale {scale}: the canvas equals no \
                     stimulus PNG ({differ} of {} pixels differ from {id}'s)",
                    w * h
                );
            }
        }
    }
    matched
}

pub fn base64_decode(s: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        _ => 63,
    };
    let bytes: Vec<u8> = s.bytes().filter(|&c| c != b'=').collect();
    let mut out = Vec::with_capacity(bytes.len() * 3 / 4);
    for chunk in bytes.chunks(4) {
        let v: Vec<u32> = chunk.iter().map(|&c| value(c) as u32).collect();
        let n = v.iter().fold(0u32, |acc, &x| acc << 6 | x) << (6 * (4 - v.len()));
        out.extend_from_slice(&n.to_be_bytes()[1..v.len()]);
    }
    out
}

/// Chromium's memory: the sum of the proportional set size (`Pss` of `/proc/PID/smaps_rollup`)
/// over every process under chromedriver (browser, GPU, renderer, utility), sampled every 100 ms.
pub struct PssSampler {
    stop: std::sync::Arc<std::sync::atomic::AtomicBool>,
    thread: std::thread::JoinHandle<u64>,
}

impl PssSampler {
    pub fn start(root: u32) -> Self {
        let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let flag = stop.clone();
        let thread = std::thread::spawn(move || {
            let mut peak = 0;
            while !flag.load(std::sync::atomic::Ordering::Relaxed) {
                let kib: u64 = descendants(root).into_iter().map(pss_kib).sum();
                peak = peak.max(kib * 1024);
                std::thread::sleep(Duration::from_millis(100));
            }
            peak
        });
        Self { stop, thread }
    }

    /// The peak in bytes.
    pub fn stop(self) -> u64 {
        self.stop.store(true, std::sync::atomic::Ordering::Relaxed);
        self.thread.join().unwrap()
    }
}

/// Every process below `root` (not `root` itself).
fn descendants(root: u32) -> Vec<u32> {
    let mut parent = std::collections::HashMap::new();
    for e in std::fs::read_dir("/proc").into_iter().flatten().flatten() {
        let Ok(pid) = e.file_name().to_string_lossy().parse::<u32>() else {
            continue;
        };
        let Ok(stat) = std::fs::read_to_string(format!("/proc/{pid}/stat")) else {
            continue;
        };
        let ppid = stat
            .rsplit_once(')')
            .and_then(|(_, rest)| rest.split_whitespace().nth(1)?.parse::<u32>().ok());
        if let Some(ppid) = ppid {
            parent.insert(pid, ppid);
        }
    }
    let under = |mut p: u32| {
        while let Some(&pp) = parent.get(&p) {
            if pp == root {
                return true;
            }
            p = pp;
        }
        false
    };
    parent.keys().copied().filter(|&p| under(p)).collect()
}

fn pss_kib(pid: u32) -> u64 {
    std::fs::read_to_string(format!("/proc/{pid}/smaps_rollup"))
        .ok()
        .and_then(|s| {
            let line = s.lines().find(|l| l.starts_with("Pss:"))?;
            line.split_whitespace().nth(1)?.parse().ok()
        })
        .unwrap_or(0)
}
