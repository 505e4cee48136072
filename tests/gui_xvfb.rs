//! The real app in a real X server (Xvfb + Mesa): start `blurlab run` on a rendered study,
//! press keys with xdotool, take screenshots with ImageMagick's `import`, and check that during
//! playback each video's current frame is on screen pixel for pixel — at the layout's whole-pixel
//! place, unscaled and unfiltered — at display scale factors 1 and 1.5; then answer and check
//! the log. Skips (with a message) when Xvfb, xdotool or import is missing, unless
//! `BLURLAB_REQUIRE_GUI_TESTS=1`, when it fails instead.
//!
//! `thesis_size_trial_under_xvfb` (ignored; run it in release) measures a thesis-size trial:
//! preload time, peak memory and frame pacing. See docs/benchmarks/experiment.md.
//! Set `BLURLAB_BENCH_DIR` to keep its rendered stimuli between runs.
#![cfg(feature = "gui")]

use experiment::Design;
use experiment::design::Layout;
use experiment::fixture::{Study, StudySpec, write_study};
use experiment::log::{SessionLog, Side};
use experiment::playback::frames::{RgbFrame, VideoSource, load_frame};
use experiment::playback::layout::{PxRect, VideoLayout};
use experiment::trials::{Trial, plan};
use renderer::manifest::Manifest;
use serde_json::json;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const TOOLS: [&str; 3] = ["Xvfb", "xdotool", "import"];

/// True when the tools are there; otherwise skip or, if required, fail.
fn gui_tools_present() -> bool {
    let missing: Vec<&str> = TOOLS
        .iter()
        .copied()
        .filter(|t| {
            !Command::new("sh")
                .args(["-c", &format!("command -v {t}")])
                .stdout(Stdio::null())
                .status()
                .is_ok_and(|s| s.success())
        })
        .collect();
    if missing.is_empty() {
        return true;
    }
    let msg = format!(
        "GUI test skipped: {} not installed (apt-get install xvfb xdotool imagemagick and the \
         Mesa/X11 libraries listed in .ci/run)",
        missing.join(", ")
    );
    if std::env::var("BLURLAB_REQUIRE_GUI_TESTS").as_deref() == Ok("1") {
        panic!("{msg}; BLURLAB_REQUIRE_GUI_TESTS=1 requires it");
    }
    eprintln!("{msg}");
    false
}

/// A child process killed when dropped (only ever our own children, by handle).
struct Guard(Child);

impl Drop for Guard {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// An Xvfb server on a free display number (Xvfb picks it and reports it on `-displayfd`).
struct Xvfb {
    server: Guard,
    display: String,
    runtime_dir: tempfile::TempDir,
}

impl Xvfb {
    fn start(width: u32, height: u32) -> Self {
        let mut child = Command::new("Xvfb")
            .args(["-displayfd", "1", "-nolisten", "tcp", "-screen", "0"])
            .arg(format!("{width}x{height}x24"))
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("start Xvfb");
        let mut line = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut line)
            .expect("Xvfb reports its display");
        let runtime_dir = tempfile::tempdir().unwrap();
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(runtime_dir.path(), std::fs::Permissions::from_mode(0o700))
            .unwrap();
        Self {
            server: Guard(child),
            display: format!(":{}", line.trim()),
            runtime_dir,
        }
    }

    fn command(&self, program: impl AsRef<std::ffi::OsStr>) -> Command {
        let mut c = Command::new(program);
        c.env("DISPLAY", &self.display)
            .env("XDG_RUNTIME_DIR", self.runtime_dir.path());
        c
    }

    fn screenshot(&self) -> image::RgbImage {
        let out = self
            .command("import")
            .args(["-window", "root", "png:-"])
            .output()
            .expect("run import");
        assert!(out.status.success(), "import failed: {out:?}");
        image::load_from_memory(&out.stdout).unwrap().into_rgb8()
    }

    fn xdotool(&self, args: &[&str]) -> String {
        let out = self.command("xdotool").args(args).output().unwrap();
        String::from_utf8_lossy(&out.stdout).trim().to_string()
    }

    /// Wait for the app's window (failing at once, with its messages, if the app exits).
    fn find_window(&self, name: &str, run: &mut Run, deadline: Instant) -> String {
        loop {
            let id = self.xdotool(&["search", "--name", name]);
            if let Some(id) = id.lines().next().filter(|l| !l.is_empty()) {
                return id.to_string();
            }
            if let Some(status) = run.app.0.try_wait().unwrap() {
                panic!(
                    "the app exited ({status}) before its window appeared:\n{}",
                    std::fs::read_to_string(&run.stderr).unwrap_or_default()
                );
            }
            assert!(
                Instant::now() < deadline,
                "the window {name:?} never appeared"
            );
            std::thread::sleep(Duration::from_millis(200));
        }
    }

    fn key(&self, window: &str, key: &str) {
        self.xdotool(&["windowfocus", "--sync", window, "key", key]);
    }
}

/// The videos of the study's single trial, decoded.
struct Expected {
    trial: Trial,
    layout: VideoLayout,
    frames: std::collections::HashMap<String, Vec<RgbFrame>>,
}

impl Expected {
    fn new(study: &Study, subject: &str, screen: (u32, u32)) -> Self {
        let design = Design::load(&study.design_path).unwrap();
        let trial = plan(&design, subject).main[0].clone();
        let manifest_path = study.stimuli_dir.join("manifest.json");
        let manifest = Manifest::load(&manifest_path).unwrap();
        let mut frames = std::collections::HashMap::new();
        let mut size = (0, 0);
        for id in trial.stimuli() {
            let v = VideoSource::from_manifest(&manifest, &manifest_path, id).unwrap();
            size = (v.width, v.height);
            let decoded = (0..v.frame_paths.len())
                .map(|f| load_frame(&v, f).unwrap())
                .collect();
            frames.insert(id.to_string(), decoded);
        }
        let f = &design.file;
        let layout =
            VideoLayout::new(Layout::Sequential, screen, size, f.playback.spacing_px).unwrap();
        Self {
            trial,
            layout,
            frames,
        }
    }

    /// The pair and frame index on screen, if the shot shows one exactly.
    fn match_shot(&self, shot: &image::RgbImage) -> Option<(u8, usize)> {
        for pair in [1u8, 2] {
            let left = &self.frames[self.trial.video(pair, Side::Left)];
            let right = &self.frames[self.trial.video(pair, Side::Right)];
            for k in 0..left.len() {
                if shows(shot, self.layout.rect(pair, Side::Left), &left[k])
                    && shows(shot, self.layout.rect(pair, Side::Right), &right[k])
                {
                    return Some((pair, k));
                }
            }
        }
        None
    }
}

/// The screen holds `frame` exactly in `r`, and the one-pixel ring around `r` is background
/// (black): no offset, no scaling, no filtering.
fn shows(shot: &image::RgbImage, r: PxRect, frame: &RgbFrame) -> bool {
    for y in 0..r.h {
        for x in 0..r.w {
            let i = 3 * (y * r.w + x) as usize;
            if shot.get_pixel(r.x + x, r.y + y).0 != frame.rgb[i..i + 3] {
                return false;
            }
        }
    }
    let black = |x: u32, y: u32| shot.get_pixel(x, y).0 == [0, 0, 0];
    (r.x - 1..=r.x + r.w).all(|x| black(x, r.y - 1) && black(x, r.y + r.h))
        && (r.y..r.y + r.h).all(|y| black(r.x - 1, y) && black(r.x + r.w, y))
}

/// The app under Xvfb on a study with one trial.
struct Run {
    app: Guard,
    stderr: PathBuf,
    log: PathBuf,
}

fn start_app(x: &Xvfb, study: &Study, scale: f32, subject: &str) -> Run {
    let stderr = study.root.join(format!("app-{scale}.stderr"));
    let sessions = study.root.join("sessions");
    // BLURLAB_EXPERIMENT_BIN runs another build of the app (e.g. main's, for a comparison): a
    // `blurlab` binary, or an older `experiment` one (both take `run` and the same flags).
    let bin = std::env::var_os("BLURLAB_EXPERIMENT_BIN")
        .map_or(PathBuf::from(env!("CARGO_BIN_EXE_blurlab")), PathBuf::from);
    let app = x
        .command(bin)
        .env("WINIT_X11_SCALE_FACTOR", scale.to_string())
        .args(["run", "--no-vsync", "--subject", subject, "--design"])
        .arg(&study.design_path)
        .arg("--out")
        .arg(&sessions)
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&stderr).unwrap())
        .spawn()
        .expect("start the app");
    Run {
        app: Guard(app),
        stderr,
        log: sessions.join(format!("{subject}.jsonl")),
    }
}

fn trial_lines(log: &Path) -> usize {
    SessionLog::read(log).map_or(0, |l| l.trials.len())
}

/// Press Space until playback is on screen, then screenshot until both pairs were seen exactly.
fn watch_both_pairs(x: &Xvfb, window: &str, expected: &Expected, deadline: Instant) {
    let mut seen = [false, false];
    let mut last_space = Instant::now() - Duration::from_secs(10);
    let mut playing = false;
    let mut shot: Option<image::RgbImage> = None;
    while seen != [true, true] {
        if Instant::now() > deadline {
            let path = std::env::temp_dir().join("blurlab-gui-test-last-shot.png");
            if let Some(s) = &shot {
                s.save(&path).unwrap();
            }
            panic!(
                "pairs seen exactly on screen: {seen:?} (last screenshot: {})",
                path.display()
            );
        }
        if !playing && last_space.elapsed() > Duration::from_millis(1500) {
            x.key(window, "space");
            last_space = Instant::now();
        }
        let s = x.screenshot();
        if let Some((pair, _)) = expected.match_shot(&s) {
            seen[pair as usize - 1] = true;
            playing = true;
        }
        shot = Some(s);
    }
}

fn spec(width: u32, height: u32, frames: u32, loops: u32) -> StudySpec {
    StudySpec {
        name: "gui".into(),
        scenes: vec!["alpha".into()],
        point_sets: vec!["random".into()],
        time_filters: vec!["box".into()],
        levels: vec![1],
        reference_spp: 8,
        width,
        height,
        frames,
        fps: 30.0,
        design: json!({
            "repeats": 1, "practice": {"trials": 0}, "break_every": 0,
            "playback": {"loops": loops, "fixation_ms": 200, "gap_ms": 200, "spacing_px": 32}
        }),
    }
}

/// Answer the last of `trials` trials, close from the end screen, and return the finished log.
fn answer_and_close(
    x: &Xvfb,
    window: &str,
    run: &mut Run,
    deadline: Instant,
    trials: usize,
) -> SessionLog {
    while trial_lines(&run.log) < trials {
        assert!(Instant::now() < deadline, "the answer was never logged");
        x.key(window, "1");
        std::thread::sleep(Duration::from_millis(300));
    }
    loop {
        x.key(window, "space");
        std::thread::sleep(Duration::from_millis(300));
        if let Some(status) = run.app.0.try_wait().unwrap() {
            let err = std::fs::read_to_string(&run.stderr).unwrap();
            assert!(status.success(), "app failed: {status}\n{err}");
            let done = format!("{trials} of {trials} trials answered");
            assert!(err.contains(&done), "{err}");
            break;
        }
        assert!(
            Instant::now() < deadline,
            "the app did not close from the end screen"
        );
    }
    SessionLog::read(&run.log).unwrap()
}

#[test]
fn stimulus_frames_reach_the_screen_pixel_for_pixel_at_scale_1_and_1_5() {
    if !gui_tools_present() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    // Odd sizes, so any half-pixel centring error would show.
    let study = write_study(dir.path(), &spec(97, 61, 20, 2)).unwrap();
    let screen = (1280, 720);
    let x = Xvfb::start(screen.0, screen.1);
    for (i, scale) in [1.0f32, 1.5].into_iter().enumerate() {
        let subject = format!("t{i}");
        let expected = Expected::new(&study, &subject, screen);
        // Generous for a loaded 2-core CI machine; a passing run takes about 7 s per scale.
        let deadline = Instant::now() + Duration::from_secs(90);
        let mut run = start_app(&x, &study, scale, &subject);
        let window = x.find_window(&format!("blurlab gui {subject}"), &mut run, deadline);
        watch_both_pairs(&x, &window, &expected, deadline);
        let log = answer_and_close(&x, &window, &mut run, deadline, 1);

        let display = log.header.display.expect("display in header");
        assert_eq!((display.width, display.height), screen);
        assert_eq!(display.pixels_per_point, scale);
        assert!(display.refresh_interval_ms > 0.0);
        let t = &log.trials[0];
        assert!(expected.trial.matches(t));
        assert_eq!(t.response, 1);
        assert_eq!(t.correct, expected.trial.diff_pair == 1);
        assert_eq!(t.timing.onsets_ms.len(), 2);
        // Every frame of both pairs was either drawn or counted as dropped.
        assert_eq!(
            t.timing.frame_times_ms.len() as u32 + t.timing.dropped_frames,
            2 * 20 * 2
        );
        assert!(
            t.timing.preload_ms > 0.0,
            "preload {} ms",
            t.timing.preload_ms
        );
        // The test presses "1" every 300 ms without seeing the screen, so a press can land in
        // the frame that begins the response step: its response time is then exactly 0 (a CI
        // run saw it once). Negative or non-finite would be a bug.
        assert!(
            t.timing.rt_ms >= 0.0 && t.timing.rt_ms.is_finite(),
            "rt {} ms",
            t.timing.rt_ms
        );
        assert!(t.timing.frame_times_ms.windows(2).all(|w| w[1] > w[0]));
    }
}

/// Interval statistics of the drawn frames within each pair, milliseconds.
fn pacing(t: &experiment::log::TrialRecord) -> (f64, f64, f64) {
    let mut d: Vec<f64> = Vec::new();
    let split = t.timing.onsets_ms[1];
    for part in [
        t.timing
            .frame_times_ms
            .iter()
            .filter(|&&x| x < split)
            .copied()
            .collect::<Vec<_>>(),
        t.timing
            .frame_times_ms
            .iter()
            .filter(|&&x| x >= split)
            .copied()
            .collect(),
    ] {
        d.extend(part.windows(2).map(|w| w[1] - w[0]));
    }
    d.sort_by(f64::total_cmp);
    let q = |p: f64| d[((d.len() - 1) as f64 * p).round() as usize];
    (q(0.5), q(0.95), d[d.len() - 1])
}

/// CPU seconds (user + system) a process has used so far.
fn cpu_seconds(pid: u32) -> f64 {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
    let Some(rest) = stat.rfind(')').map(|i| &stat[i + 2..]) else {
        return 0.0;
    };
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |i: usize| f.get(i).and_then(|v| v.parse::<f64>().ok()).unwrap_or(0.0);
    // Fields 14 and 15 of /proc/<pid>/stat (utime, stime), in 1/100 s clock ticks.
    (ticks(11) + ticks(12)) / 100.0
}

fn unix_now() -> f64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap()
        .as_secs_f64()
}

/// Samples (unix time, app CPU s, Xvfb CPU s) every 20 ms until dropped.
struct CpuSampler {
    stop: std::sync::Arc<std::sync::atomic::AtomicBool>,
    thread: Option<std::thread::JoinHandle<Vec<(f64, f64, f64)>>>,
}

impl CpuSampler {
    fn start(app: u32, xvfb: u32) -> Self {
        let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let flag = stop.clone();
        let thread = std::thread::spawn(move || {
            let mut v = Vec::new();
            while !flag.load(std::sync::atomic::Ordering::Relaxed) {
                v.push((unix_now(), cpu_seconds(app), cpu_seconds(xvfb)));
                std::thread::sleep(Duration::from_millis(20));
            }
            v
        });
        Self {
            stop,
            thread: Some(thread),
        }
    }

    fn finish(mut self) -> Vec<(f64, f64, f64)> {
        self.stop.store(true, std::sync::atomic::Ordering::Relaxed);
        self.thread.take().unwrap().join().unwrap()
    }
}

/// CPU seconds used between two unix times (nearest samples; tick resolution 10 ms).
fn cpu_between(samples: &[(f64, f64, f64)], from: f64, to: f64) -> (f64, f64) {
    let at = |t: f64| {
        samples
            .iter()
            .min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs()))
            .copied()
            .unwrap_or_default()
    };
    let (a, b) = (at(from), at(to));
    (b.1 - a.1, b.2 - a.2)
}

/// Peak resident memory of a process, MiB (VmHWM).
fn peak_rss_mib(pid: u32) -> f64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    status
        .lines()
        .find(|l| l.starts_with("VmHWM:"))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|kb| kb.parse::<f64>().ok())
        .map_or(0.0, |kb| kb / 1024.0)
}

/// Press `key` (Space once a second, answers every 0.3 s) until `done`.
fn press_until(x: &Xvfb, window: &str, key: &str, deadline: Instant, done: impl Fn() -> bool) {
    let every = Duration::from_millis(if key == "space" { 1000 } else { 300 });
    while !done() {
        assert!(
            Instant::now() < deadline,
            "still pressing {key} at the deadline"
        );
        x.key(window, key);
        std::thread::sleep(every);
    }
}

/// A measurement's study: in `BLURLAB_BENCH_DIR`, which keeps the rendered stimuli between runs
/// (the job runner resumes, so a second run renders nothing), else in the temporary folder
/// returned; earlier sessions removed.
fn bench_study(spec: &StudySpec) -> (tempfile::TempDir, Study) {
    let temp = tempfile::tempdir().unwrap();
    let root =
        std::env::var_os("BLURLAB_BENCH_DIR").map_or(temp.path().to_path_buf(), PathBuf::from);
    let _ = std::fs::remove_dir_all(root.join("sessions"));
    let t0 = Instant::now();
    let study = write_study(&root, spec).unwrap();
    eprintln!("stimuli ready in {:.1} s", t0.elapsed().as_secs_f64());
    (temp, study)
}

#[test]
#[ignore = "measurement: renders 2 x 210 frames of 768x768; run in release, see docs/benchmarks/experiment.md"]
fn thesis_size_trial_under_xvfb() {
    if !gui_tools_present() {
        return;
    }
    let (_temp, study) = bench_study(&spec(768, 768, 210, 1));
    // Decoding alone (what the rayon pool does during a preload), for the breakdown.
    let design = Design::load(&study.design_path).unwrap();
    let trial = plan(&design, "m1").main[0].clone();
    let manifest_path = study.stimuli_dir.join("manifest.json");
    let manifest = Manifest::load(&manifest_path).unwrap();
    let jobs: Vec<(VideoSource, usize)> = trial
        .stimuli()
        .iter()
        .flat_map(|id| {
            let v = VideoSource::from_manifest(&manifest, &manifest_path, id).unwrap();
            (0..v.frame_paths.len()).map(move |f| (v.clone(), f))
        })
        .collect();
    let t1 = Instant::now();
    let bytes: usize = {
        use rayon::prelude::*;
        jobs.par_iter()
            .map(|(v, f)| load_frame(v, *f).unwrap().rgb.len())
            .sum()
    };
    eprintln!(
        "decoding {} frames ({} MiB RGB) on the rayon pool: {:.0} ms",
        jobs.len(),
        bytes >> 20,
        t1.elapsed().as_secs_f64() * 1000.0
    );
    let screen = (1920, 1080);
    let x = Xvfb::start(screen.0, screen.1);
    let deadline = Instant::now() + Duration::from_secs(300);
    let mut run = start_app(&x, &study, 1.0, "m1");
    let window = x.find_window("blurlab gui m1", &mut run, deadline);
    let sampler = CpuSampler::start(run.app.0.id(), x.server.0.id());
    // No screenshots here: they would compete with playback for the CPU. Start the session
    // (the header appears), then answer once the presentation is over.
    press_until(&x, &window, "space", deadline, || run.log.exists());
    press_until(&x, &window, "1", deadline, || trial_lines(&run.log) == 1);
    let peak = peak_rss_mib(run.app.0.id());
    let samples = sampler.finish();
    let log = answer_and_close(&x, &window, &mut run, deadline, 1);
    let t = &log.trials[0];
    let (median, p95, max) = pacing(t);
    // CPU spent during playback (first drawn frame to last), per drawn frame: what a quiet
    // core would need to keep up, whatever else the machine was doing.
    let origin = log.header.started_unix;
    let from = origin + t.timing.onsets_ms[0] / 1000.0;
    let to = origin + t.timing.frame_times_ms.last().unwrap() / 1000.0;
    let (app_cpu, xvfb_cpu) = cpu_between(&samples, from, to);
    let drawn = t.timing.frame_times_ms.len() as f64;
    eprintln!(
        "playback {:.1} s: app CPU {:.2} s ({:.1} ms per drawn frame), Xvfb CPU {:.2} s ({:.1} ms \
         per drawn frame); load average {}",
        to - from,
        app_cpu,
        1000.0 * app_cpu / drawn,
        xvfb_cpu,
        1000.0 * xvfb_cpu / drawn,
        std::fs::read_to_string("/proc/loadavg")
            .unwrap_or_default()
            .trim()
    );
    eprintln!(
        "thesis-size trial (2 videos x 210 frames of 768x768, 30 fps, Xvfb {}x{}, glow/llvmpipe, \
         no vsync): preload {:.0} ms, peak RSS {:.0} MiB, refresh interval measured {:.2} ms, \
         frames drawn {}, dropped {}, frame interval median {:.2} ms, p95 {:.2} ms, max {:.2} ms",
        screen.0,
        screen.1,
        t.timing.preload_ms,
        peak,
        log.header.display.as_ref().unwrap().refresh_interval_ms,
        t.timing.frame_times_ms.len(),
        t.timing.dropped_frames,
        median,
        p95,
        max
    );
}

/// The trial after an answer that decides it: a weighted staircase over levels 1 and 2 (one
/// condition) starts at level 2 and, answered wrong, steps to level 1, so the second trial's
/// test video is new and could not be loaded during the answer; its reference is the first
/// trial's. The subject is the first whose second trial shows the new video in pair 1 (loaded
/// against the clock from the fixation on: the harder case).
#[test]
#[ignore = "measurement: renders 3 x 210 frames of 768x768, see docs/benchmarks/experiment.md"]
fn thesis_size_adaptive_next_trial_under_xvfb() {
    if !gui_tools_present() {
        return;
    }
    let mut spec = spec(768, 768, 210, 1);
    spec.levels = vec![1, 2];
    spec.design["procedure"] = json!({"staircase": {
        "rule": {"weighted": {"target": 0.75}}, "interleaved": 1, "trials": 2
    }});
    let (_temp, study) = bench_study(&spec);
    let design = Design::load(&study.design_path).unwrap();
    let (subject, wrong) = (1..100)
        .find_map(|i| {
            let subject = format!("m{i}");
            let mut p = experiment::procedure::start(&design, &subject);
            let first = p.current().unwrap().clone();
            p.answer(false);
            let second = p.current().unwrap();
            let new_in_pair_1 =
                second.test_stimulus != first.test_stimulus && second.diff_pair == 1;
            new_in_pair_1.then(|| (subject, (3 - first.diff_pair).to_string()))
        })
        .expect("a subject whose second trial shows a new video in pair 1");
    let x = Xvfb::start(1920, 1080);
    let deadline = Instant::now() + Duration::from_secs(300);
    let mut run = start_app(&x, &study, 1.0, &subject);
    let window = x.find_window(&format!("blurlab gui {subject}"), &mut run, deadline);
    press_until(&x, &window, "space", deadline, || run.log.exists());
    press_until(&x, &window, &wrong, deadline, || trial_lines(&run.log) == 1);
    press_until(&x, &window, "1", deadline, || trial_lines(&run.log) == 2);
    let peak = peak_rss_mib(run.app.0.id());
    let log = answer_and_close(&x, &window, &mut run, deadline, 2);
    let (first, t) = (&log.trials[0], &log.trials[1]);
    assert!(!first.correct && t.test_stimulus != first.test_stimulus && t.diff_pair == 1);
    let (median, p95, max) = pacing(t);
    eprintln!(
        "adaptive next trial (one new 768x768 video of 210 frames in pair 1, 30 fps, Xvfb, \
         glow/llvmpipe, no vsync): preload {:.0} ms (first trial, both videos: {:.0} ms), peak \
         RSS {:.0} MiB, frames drawn {}, dropped {} (first trial {}), frame interval median \
         {:.2} ms, p95 {:.2} ms, max {:.2} ms; load average {}",
        t.timing.preload_ms,
        first.timing.preload_ms,
        peak,
        t.timing.frame_times_ms.len(),
        t.timing.dropped_frames,
        first.timing.dropped_frames,
        median,
        p95,
        max,
        std::fs::read_to_string("/proc/loadavg")
            .unwrap_or_default()
            .trim()
    );
}
