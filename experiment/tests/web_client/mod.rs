//! A simulated browser for the `blurlab serve` tests and the load benchmark: it claims a link,
//! posts display facts, leaves screens, fetches each video it is shown once (the current trial's,
//! then those of the next trials, as the browser fetches ahead), waits a think time and answers
//! with a simulated observer, retrying with back-off through dropped connections and server
//! restarts (the same answer again: the server acknowledges it once). The observer answers a shadow
//! session (same design, same subject, a memory log) that follows the server's: the browser itself
//! never learns what a trial shows.
#![allow(dead_code)]

use experiment::log::Timing;
use experiment::log::sink::MemoryLog;
use experiment::session::{Phase, Session, StartInfo};
use experiment::web::wire::{AnswerReply, ErrorBody, State};
use experiment::{Design, Observer};
use serde_json::json;
use std::time::{Duration, Instant};

/// A server that is started and stopped by a test.
pub struct Running {
    pub base: String,
    pub started: experiment::web::Started,
    stop: Option<tokio::sync::oneshot::Sender<()>>,
    task: Option<tokio::task::JoinHandle<anyhow::Result<()>>>,
}

impl Running {
    pub async fn start(config: &experiment::web::Config) -> Self {
        let server = experiment::web::Server::bind(config).await.unwrap();
        let started = server.started.clone();
        let (tx, rx) = tokio::sync::oneshot::channel::<()>();
        let task = tokio::spawn(server.run(async {
            let _ = rx.await;
        }));
        Self {
            base: format!("http://{}", started.addr),
            started,
            stop: Some(tx),
            task: Some(task),
        }
    }

    pub async fn stop(mut self) {
        if let Some(tx) = self.stop.take() {
            let _ = tx.send(());
        }
        if let Some(t) = self.task.take() {
            t.await.unwrap().unwrap();
        }
    }
}

/// A config on 127.0.0.1 with a free port.
pub fn config(
    design: &std::path::Path,
    out: &std::path::Path,
    enrol: u32,
) -> experiment::web::Config {
    experiment::web::Config {
        design: design.to_path_buf(),
        out: out.to_path_buf(),
        addr: "127.0.0.1:0".parse().unwrap(),
        enrol: Some(enrol),
        open_enrolment: None,
        base_url: None,
        client: Default::default(),
        limits: Default::default(),
        connections: Default::default(),
        check_hashes: true,
    }
}

/// The subject tokens of a study folder, in subject order.
pub fn tokens(out: &std::path::Path) -> Vec<(String, String)> {
    let t = experiment::web::tokens::Tokens::load_or_new(out).unwrap();
    t.subjects
        .into_iter()
        .map(|s| (s.subject, s.token))
        .collect()
}

/// What one simulated subject saw.
#[derive(Debug, Default)]
pub struct Outcome {
    /// Every acknowledged answer: (practice, trial, response).
    pub acked: Vec<(bool, u32, u8)>,
    /// Milliseconds from sending an answer to its acknowledgement (first try that got one).
    pub ack_ms: Vec<f64>,
    pub video_bytes: u64,
    /// Videos fetched (each distinct one once, unless a fetch failed).
    pub videos: u64,
    /// Ids fetched so far.
    pub fetched: std::collections::HashSet<String>,
    /// Requests that failed and were tried again (connection refused during a restart...).
    pub retries: u32,
}

pub struct SimBrowser {
    pub http: reqwest::Client,
    pub base: String,
    pub token: String,
    pub tab: String,
    pub subject: String,
    pub observer: Observer,
    /// A Mutex only to make the browser `Sync` (a session's log sink is `Send` only).
    shadow: std::sync::Mutex<Session>,
    pub think: Duration,
    /// Give up when the server cannot be reached for this long.
    pub patience: Duration,
}

/// An HTTP reply: status and JSON body.
pub struct Reply {
    pub status: u16,
    pub body: serde_json::Value,
}

impl Reply {
    pub fn error(&self) -> String {
        serde_json::from_value::<ErrorBody>(self.body.clone())
            .map(|e| e.error)
            .unwrap_or_default()
    }
}

pub async fn post(
    http: &reqwest::Client,
    url: &str,
    body: serde_json::Value,
) -> reqwest::Result<Reply> {
    let r = http.post(url).body(body.to_string()).send().await?;
    let status = r.status().as_u16();
    let bytes = r.bytes().await?;
    Ok(Reply {
        status,
        body: serde_json::from_slice(&bytes).unwrap_or(serde_json::Value::Null),
    })
}

pub fn display_facts(tab: &str) -> serde_json::Value {
    json!({"tab": tab, "screen_px": [1920, 1080], "window_px": [1920, 1080],
           "device_pixel_ratio": 1.0, "px_per_mm": 3.78, "viewing_distance_mm": 600.0,
           "pixels_per_degree": 39.6, "refresh_interval_ms": 16.7,
           "user_agent": "blurlab-sim", "fullscreen": true})
}

impl SimBrowser {
    pub fn new(
        http: reqwest::Client,
        base: &str,
        design: &Design,
        observer: &Observer,
        subject: &str,
        token: &str,
        think: Duration,
    ) -> Self {
        let mut shadow =
            Session::open_with(design, subject, Box::new(MemoryLog::new("shadow.jsonl"))).unwrap();
        shadow
            .start(StartInfo {
                mode: "simulated".into(),
                display: None,
                observer: None,
                started_unix: 0.0,
            })
            .unwrap();
        Self {
            http,
            base: base.to_string(),
            token: token.to_string(),
            tab: format!("tab-{subject}"),
            subject: subject.to_string(),
            observer: observer.clone(),
            shadow: std::sync::Mutex::new(shadow),
            think,
            patience: Duration::from_secs(60),
        }
    }

    fn url(&self, rest: &str) -> String {
        format!("{}/api/s/{}/{rest}", self.base, self.token)
    }

    /// POST with retries through connection failures and 5xx; the reply otherwise.
    async fn post_retrying(
        &self,
        rest: &str,
        body: serde_json::Value,
        out: &mut Outcome,
    ) -> anyhow::Result<Reply> {
        let since = Instant::now();
        let mut wait = Duration::from_millis(50);
        loop {
            match post(&self.http, &self.url(rest), body.clone()).await {
                Ok(r) if r.status < 500 && r.status != 429 => return Ok(r),
                Ok(_) | Err(_) if since.elapsed() < self.patience => {
                    out.retries += 1;
                    tokio::time::sleep(wait).await;
                    wait = (wait * 2).min(Duration::from_millis(500));
                }
                Ok(r) => anyhow::bail!("{}: {} {}", self.subject, r.status, r.body),
                Err(e) => anyhow::bail!("{}: {e}", self.subject),
            }
        }
    }

    fn state_of(r: &Reply, what: &str) -> anyhow::Result<State> {
        if r.status != 200 {
            anyhow::bail!("{what}: {} {}", r.status, r.body);
        }
        Ok(serde_json::from_value(r.body.clone())?)
    }

    /// Claim the session (again) and get past the display check.
    async fn sync(&self, out: &mut Outcome) -> anyhow::Result<State> {
        let r = self
            .post_retrying("claim", json!({"tab": self.tab}), out)
            .await?;
        let mut st = Self::state_of(&r, "claim")?;
        if st.phase == "display_check" {
            let r = self
                .post_retrying("display", display_facts(&self.tab), out)
                .await?;
            st = Self::state_of(&r, "display")?;
        }
        Ok(st)
    }

    /// Fetch the trial's videos and the next trials' (each id once); false if one fails.
    async fn fetch_videos(&self, st: &State, out: &mut Outcome) -> bool {
        let Some(t) = &st.trial else { return true };
        let ids: Vec<&String> = t.pairs.iter().flatten().chain(st.ahead.iter()).collect();
        for id in ids {
            if out.fetched.contains(id) {
                continue;
            }
            let url = self.url(&format!("video/{id}"));
            match self.http.get(&url).send().await {
                Ok(r) if r.status() == 200 => match r.bytes().await {
                    Ok(b) => {
                        out.video_bytes += b.len() as u64;
                        out.videos += 1;
                        out.fetched.insert(id.clone());
                    }
                    Err(_) => return false,
                },
                _ => return false,
            }
        }
        true
    }

    /// Run the whole session; every answer acknowledged is in `acked`.
    pub async fn run(self) -> anyhow::Result<Outcome> {
        let mut out = Outcome::default();
        let mut st = self.sync(&mut out).await?;
        loop {
            let shadow_phase = {
                let mut sh = self.shadow.lock().unwrap();
                while matches!(
                    sh.phase(),
                    Phase::Instructions | Phase::PracticeDone | Phase::Break
                ) {
                    sh.advance();
                }
                sh.phase()
            };
            match st.phase.as_str() {
                "done" => {
                    anyhow::ensure!(
                        shadow_phase == Phase::Finished,
                        "{}: server done early",
                        self.subject
                    );
                    return Ok(out);
                }
                "instructions" | "break" => {
                    let from = if st.phase == "instructions" {
                        "instructions"
                    } else {
                        "break"
                    };
                    let r = self
                        .post_retrying("advance", json!({"tab": self.tab, "from": from}), &mut out)
                        .await?;
                    st = match Self::state_of(&r, "advance") {
                        Ok(s) => s,
                        Err(_) => self.sync(&mut out).await?,
                    };
                }
                "practice" | "main" => {
                    let view = st.trial.clone().expect("a trial phase has a trial");
                    let shadow_trial = self
                        .shadow
                        .lock()
                        .unwrap()
                        .trial()
                        .cloned()
                        .expect("shadow at a trial");
                    anyhow::ensure!(
                        (shadow_trial.practice, shadow_trial.index) == (view.practice, view.index),
                        "{}: server presents {:?}, the shadow {:?}",
                        self.subject,
                        (view.practice, view.index),
                        (shadow_trial.practice, shadow_trial.index)
                    );
                    if !self.fetch_videos(&st, &mut out).await {
                        out.retries += 1;
                        tokio::time::sleep(Duration::from_millis(100)).await;
                        st = self.sync(&mut out).await?;
                        continue;
                    }
                    tokio::time::sleep(self.think).await;
                    let response = self.observer.respond(&shadow_trial, &self.subject)?;
                    let body = json!({"tab": self.tab, "session": 1, "practice": view.practice,
                        "trial": view.index, "response": response, "timing": {"rt_ms": 600.0,
                        "onsets_ms": [0.0, 1200.0], "frame_times_ms": [0.0, 16.7, 33.3],
                        "dropped_frames": 0, "late_frames": 0, "refresh_interval_ms": 16.7,
                        "preload_ms": 12.0}});
                    let sent = Instant::now();
                    let r = self.post_retrying("answer", body, &mut out).await?;
                    if r.status == 409 {
                        // The server restarted (claim and display lost) or this tab's claim
                        // lapsed: claim again, and answer the trial it presents (this one).
                        st = self.sync(&mut out).await?;
                        continue;
                    }
                    anyhow::ensure!(
                        r.status == 200,
                        "{}: answer {} {}",
                        self.subject,
                        r.status,
                        r.body
                    );
                    out.ack_ms.push(sent.elapsed().as_secs_f64() * 1e3);
                    let reply: AnswerReply = serde_json::from_value(r.body)?;
                    anyhow::ensure!(
                        reply.ack.trial == view.index && reply.ack.practice == view.practice
                    );
                    out.acked.push((view.practice, view.index, response));
                    self.shadow
                        .lock()
                        .unwrap()
                        .answer(response, Timing::default())?;
                    st = reply.state;
                }
                // A replayed answer acknowledged by a restarted server, before any claim.
                "display_check" => st = self.sync(&mut out).await?,
                other => anyhow::bail!("{}: phase {other:?}", self.subject),
            }
        }
    }
}
