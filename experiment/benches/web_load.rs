//! Load benchmark of `blurlab serve` (issues 39, 48): simulated subjects (the simulated
//! observer, answering over HTTP with a think time, fetching each video they are shown once,
//! ahead of the trial that shows it) against one server process; optionally `kill -9` of the server K times during the load, each time
//! restarted. Then every log is checked: each acknowledged answer is in it exactly once, no
//! trial is logged twice, and every session is finished.
//!
//! ```text
//! cargo build --release -p blurlab
//! nice -n 10 cargo bench -p experiment --features web --bench web_load -- \
//!     --server target/release/blurlab --design scenes/demo/design.json \
//!     --subjects 200 --think-ms 1500 [--kills 10] --out /tmp/web_load
//! ```
//! (The demo design's stimuli must be rendered where the design points, or pass a design copy.)

use experiment::log::SessionLog;
use experiment::{Design, Observer};
use std::path::{Path, PathBuf};
use std::process::{Child, Command};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};
use web_client::SimBrowser;

#[path = "../tests/web_client/mod.rs"]
mod web_client;

struct Args {
    server: PathBuf,
    design: PathBuf,
    subjects: u32,
    think_ms: u64,
    kills: u32,
    out: PathBuf,
}

fn args() -> Args {
    let mut a = Args {
        server: "target/release/blurlab".into(),
        design: "scenes/demo/design.json".into(),
        subjects: 200,
        think_ms: 1500,
        kills: 0,
        out: std::env::temp_dir().join("web_load"),
    };
    let argv: Vec<String> = std::env::args().skip(1).collect();
    let mut i = 0;
    while i < argv.len() {
        let v = argv.get(i + 1).cloned().unwrap_or_default();
        match argv[i].as_str() {
            "--server" => a.server = v.into(),
            "--design" => a.design = v.into(),
            "--subjects" => a.subjects = v.parse().expect("--subjects N"),
            "--think-ms" => a.think_ms = v.parse().expect("--think-ms MS"),
            "--kills" => a.kills = v.parse().expect("--kills K"),
            "--out" => a.out = v.into(),
            "--bench" => {
                i += 1;
                continue;
            }
            other => panic!("unknown argument {other}"),
        }
        i += 2;
    }
    a
}

fn spawn_server(a: &Args, addr: &str) -> Child {
    Command::new(&a.server)
        .args(["serve", "--design"])
        .arg(&a.design)
        .arg("--out")
        .arg(&a.out)
        .args(["--addr", addr, "--enrol", &a.subjects.to_string()])
        .stdout(std::process::Stdio::null())
        .spawn()
        .expect("start the server binary (--server)")
}

/// User plus system CPU time of a process, in clock ticks (100 a second on Linux).
fn cpu_ticks(pid: u32) -> u64 {
    std::fs::read_to_string(format!("/proc/{pid}/stat"))
        .ok()
        .and_then(|s| {
            // Fields after the command name (which may hold spaces) start at field 3.
            let rest = s.rsplit_once(')')?.1;
            let f: Vec<&str> = rest.split_whitespace().collect();
            Some(f.get(11)?.parse::<u64>().ok()? + f.get(12)?.parse::<u64>().ok()?)
        })
        .unwrap_or(0)
}

fn rss_kib(pid: u32) -> u64 {
    std::fs::read_to_string(format!("/proc/{pid}/status"))
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmRSS:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse().ok())
        })
        .unwrap_or(0)
}

async fn wait_up(http: &reqwest::Client, base: &str) {
    // (A first start encodes the videos: run `blurlab serve --check` on the design before.)
    for _ in 0..400 {
        if http
            .get(format!("{base}/assets/style.css"))
            .send()
            .await
            .is_ok()
        {
            return;
        }
        tokio::time::sleep(Duration::from_millis(25)).await;
    }
    panic!("the server did not come up at {base}");
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    sorted[((sorted.len() - 1) as f64 * p).round() as usize]
}

fn main() {
    let a = args();
    let _ = std::fs::remove_dir_all(&a.out);
    let design = Design::load(&a.design).unwrap();
    let observer = Observer::parse(
        Path::new("o.json"),
        r#"{"format": "blurlab-observer/1", "name": "o", "slope": 1.5,
            "thresholds": [{"spp": 20}]}"#,
    )
    .unwrap();
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let addr = format!("127.0.0.1:{port}");
    let base = format!("http://{addr}");
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .unwrap();
    let mut server = spawn_server(&a, &addr);
    let http = reqwest::Client::builder()
        .pool_max_idle_per_host(400)
        .build()
        .unwrap();
    rt.block_on(wait_up(&http, &base));
    let tokens = web_client::tokens(&a.out);
    let done = Arc::new(AtomicBool::new(false));
    let max_rss = Arc::new(AtomicU64::new(0));
    let pid = Arc::new(AtomicU64::new(server.id() as u64));
    // Memory and CPU sampler (CPU summed over the server processes, across kills).
    let sampler = {
        let (done, max_rss, pid) = (done.clone(), max_rss.clone(), pid.clone());
        std::thread::spawn(move || {
            let (mut seen_pid, mut ticks, mut before) = (0u32, 0u64, 0u64);
            while !done.load(Ordering::Relaxed) {
                let p = pid.load(Ordering::Relaxed) as u32;
                if p != seen_pid {
                    before += ticks;
                    (seen_pid, ticks) = (p, 0);
                }
                ticks = ticks.max(cpu_ticks(p));
                max_rss.fetch_max(rss_kib(p), Ordering::Relaxed);
                std::thread::sleep(Duration::from_millis(100));
            }
            before + ticks
        })
    };
    let start = Instant::now();
    let tasks: Vec<_> = tokens
        .iter()
        .enumerate()
        .map(|(i, (subject, token))| {
            let mut b = SimBrowser::new(
                http.clone(),
                &base,
                &design,
                &observer,
                subject,
                token,
                Duration::from_millis(a.think_ms),
            );
            b.patience = Duration::from_secs(120);
            // Stagger the starts over one think time, as arrivals would be.
            let delay = Duration::from_millis(a.think_ms * i as u64 / a.subjects.max(1) as u64);
            rt.spawn(async move {
                tokio::time::sleep(delay).await;
                b.run().await
            })
        })
        .collect();
    // Kill -9 and restart the server `kills` times, evenly over the expected session length.
    let trials = design.main_trial_count() as u64 + design.file.practice.trials as u64;
    let expected = Duration::from_millis(trials * (a.think_ms + 150));
    let mut kill_log = Vec::new();
    for k in 0..a.kills {
        std::thread::sleep(expected / (a.kills + 1));
        server.kill().unwrap(); // SIGKILL
        server.wait().unwrap();
        let down = Instant::now();
        server = spawn_server(&a, &addr);
        pid.store(server.id() as u64, Ordering::Relaxed);
        rt.block_on(wait_up(&http, &base));
        kill_log.push((
            k + 1,
            start.elapsed().as_secs_f64(),
            down.elapsed().as_secs_f64(),
        ));
    }
    let outcomes: Vec<_> = rt.block_on(async {
        let mut v = Vec::new();
        for t in tasks {
            v.push(t.await.unwrap());
        }
        v
    });
    let elapsed = start.elapsed().as_secs_f64();
    done.store(true, Ordering::Relaxed);
    let cpu_s = sampler.join().unwrap() as f64 / 100.0;
    let _ = server.kill();
    let _ = server.wait();

    // Every acknowledged answer in its log exactly once; every session finished.
    let (mut acked, mut lost, mut duplicated, mut unfinished, mut failed) = (0, 0, 0, 0, 0);
    let mut ack_ms = Vec::new();
    let (mut bytes, mut videos, mut retries) = (0u64, 0u64, 0u64);
    for ((subject, _), outcome) in tokens.iter().zip(outcomes) {
        let o = match outcome {
            Ok(o) => o,
            Err(e) => {
                eprintln!("{subject}: {e:#}");
                failed += 1;
                continue;
            }
        };
        let log =
            SessionLog::read(&a.out.join("sessions").join(format!("{subject}.jsonl"))).unwrap();
        let mut seen = std::collections::HashMap::new();
        for t in &log.trials {
            *seen
                .entry((t.practice, t.index, t.response))
                .or_insert(0u32) += 1;
        }
        duplicated += seen.values().filter(|&&n| n > 1).count();
        for &(p, i, r) in &o.acked {
            if seen.get(&(p, i, r)) != Some(&1) {
                lost += 1;
            }
        }
        if log.main_trials().count() < log.header.trials_planned as usize {
            unfinished += 1;
        }
        acked += o.acked.len();
        ack_ms.extend(o.ack_ms);
        bytes += o.video_bytes;
        videos += o.videos;
        retries += o.retries as u64;
    }
    ack_ms.sort_by(f64::total_cmp);
    println!(
        "web_load: {} subjects, design {}, think {} ms, {} kills",
        a.subjects,
        design.name(),
        a.think_ms,
        a.kills
    );
    println!(
        "  elapsed {elapsed:.1} s; answers acknowledged {acked}; lost {lost}; duplicated {duplicated}; unfinished sessions {unfinished}; failed subjects {failed}"
    );
    println!(
        "  ack latency ms: p50 {:.1}, p99 {:.1}, max {:.1}",
        percentile(&ack_ms, 0.5),
        percentile(&ack_ms, 0.99),
        ack_ms.last().copied().unwrap_or(f64::NAN)
    );
    println!(
        "  videos served {videos} ({:.1} MB), {:.2} MB/s; bytes per session {:.0}, per trial {:.0}",
        bytes as f64 / 1e6,
        bytes as f64 / 1e6 / elapsed,
        bytes as f64 / a.subjects.max(1) as f64,
        bytes as f64 / acked.max(1) as f64
    );
    println!(
        "  server peak RSS {:.1} MB; server CPU {cpu_s:.1} s ({:.0}% of one core); client retries {retries}",
        max_rss.load(Ordering::Relaxed) as f64 / 1024.0,
        100.0 * cpu_s / elapsed
    );
    for (k, at, restart) in kill_log {
        println!("  kill {k} at {at:.1} s, back up in {restart:.2} s");
    }
    if lost + duplicated + unfinished + failed > 0 {
        std::process::exit(1);
    }
}
