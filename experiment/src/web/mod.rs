//! `blurlab serve`: subject sessions in browsers (issue 39). The server runs each subject's
//! [`crate::Session`] over a synced log, exactly as the lab app does, and writes the same
//! `blurlab-session/1` log (`mode: "web"`); the browser shows what the server chose, through
//! opaque video ids, and reports what the subject pressed. Videos travel as lossless WebP frame
//! packs encoded once beside the stimulus set (`packs.rs`). See `docs/web.md`.

mod admin;
mod api;
pub mod assets;
pub mod budget;
pub mod connections;
pub mod error;
pub mod export;
pub mod guard;
mod inputs;
pub mod packs;
pub mod participant;
mod redirect;
mod startup;
mod stream;
pub mod study;
pub mod subject;
pub mod tokens;
pub mod video_ids;
pub mod wire;

use crate::design::Design;
use anyhow::{Context, Result};
use std::collections::HashMap;
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, RwLock};
use study::Study;
use subject::{Subject, VideoIds};
use tokens::Tokens;
use wire::ClientSettings;

/// Largest request body the API reads (an answer with a few thousand frame times fits easily).
pub const BODY_LIMIT: usize = 256 * 1024;

/// What `blurlab serve` is asked to do.
#[derive(Clone, Debug)]
pub struct Config {
    pub design: PathBuf,
    /// The study's folder: `sessions/`, `links.csv`, `web/tokens.json`.
    pub out: PathBuf,
    pub addr: SocketAddr,
    /// Make sure this many subject links exist (`w001`...), and write `links.csv`.
    pub enrol: Option<u32>,
    /// Open enrolment: `/join/{token}` creates subjects (`o001`...) up to this many.
    pub open_enrolment: Option<u32>,
    /// The URL subjects reach the server at (behind a proxy: its public https URL); default
    /// `http://ADDR`.
    pub base_url: Option<String>,
    /// How browsers fetch, keep and decode videos (`client.video_base`: a static server).
    pub client: ClientSettings,
    /// The budget a session is checked against (warnings).
    pub limits: budget::Limits,
    /// How long and how many connections may be held.
    pub connections: connections::Limits,
    /// Read every frame at start and compare the manifest's content hash (`--skip-hash-check`
    /// turns it off, as for `blurlab run`).
    pub check_hashes: bool,
}

/// What a started server tells its operator.
#[derive(Clone, Debug)]
pub struct Started {
    pub addr: SocketAddr,
    pub base_url: String,
    pub admin_url: String,
    pub admin_token: String,
    pub links_csv: Option<PathBuf>,
    pub join_url: Option<String>,
    /// The join URL with the platform's id parameters (the design's `online`), to paste into
    /// the platform's study settings.
    pub study_url: Option<String>,
    pub subjects: usize,
    pub sessions_dir: PathBuf,
    /// Videos encoded at this start, and reused from the cache.
    pub encoded: packs::Encoded,
    /// The per-session budget (printed at start, and by `--check`).
    pub budget: budget::Budget,
}

/// One subject as the server holds them.
#[derive(Debug)]
pub(crate) struct Entry {
    pub subject: Mutex<Subject>,
    pub videos: Arc<VideoIds>,
}

/// Everything the handlers share.
#[derive(Debug)]
pub(crate) struct App {
    pub study: Study,
    pub out: PathBuf,
    pub sessions_dir: PathBuf,
    pub by_token: RwLock<HashMap<String, Arc<Entry>>>,
    pub tokens: Mutex<Tokens>,
    pub per_link: guard::Limiter,
    pub per_address: guard::Limiter,
    /// Keys the subjects' video ids (`video_ids.rs`).
    pub video_key: String,
}

impl App {
    fn insert(&self, t: &tokens::SubjectToken) {
        let token = &t.token;
        let shared = self.study.client.video_base.is_some();
        let videos = Arc::new(VideoIds::new(&self.study, &self.video_key, token, shared));
        let mut s = Subject::new(&t.subject, &self.sessions_dir, videos.clone());
        s.participant = crate::log::Participant {
            ids: t.ids.clone(),
            consent: t.consent.clone(),
        };
        s.screened_out = t.screened_out.clone();
        let entry = Entry {
            videos,
            subject: Mutex::new(s),
        };
        self.by_token
            .write()
            .unwrap_or_else(|e| e.into_inner())
            .insert(token.to_string(), Arc::new(entry));
    }
}

/// A server bound to its address, ready to run.
pub struct Server {
    listener: tokio::net::TcpListener,
    connections: connections::Limits,
    app: Arc<App>,
    pub started: Started,
}

impl Server {
    /// Load the design and its stimuli (encoding the videos not yet encoded), check the budget,
    /// load the tokens (creating and enrolling as asked), and bind.
    pub async fn bind(config: &Config) -> Result<Self> {
        Self::bind_with(config, &mut |_, _, _| {}).await
    }

    /// [`Server::bind`], telling `progress(k, n, stimulus)` each video as its encoding starts.
    pub async fn bind_with(
        config: &Config,
        progress: &mut dyn FnMut(usize, usize, &str),
    ) -> Result<Self> {
        let (study, budget) = load_study(config, progress)?;
        let sessions_dir = config.out.join("sessions");
        std::fs::create_dir_all(&sessions_dir)
            .with_context(|| format!("cannot create folder {}", sessions_dir.display()))?;
        let mut tokens = Tokens::load_or_new(&config.out)?;
        let video_key = tokens.video_key()?;
        if let Some(n) = config.enrol {
            renderer::limits::check_count(
                "--enrol",
                n as u64,
                1,
                renderer::limits::MAX_SUBJECTS as u64,
            )?;
            tokens.enrol("w", n)?;
        }
        match config.open_enrolment {
            Some(cap) => match &mut tokens.open {
                Some(o) => o.cap = cap,
                None => {
                    tokens.open = Some(tokens::OpenEnrolment {
                        token: tokens::new_token()?,
                        cap,
                    })
                }
            },
            None => tokens.open = None,
        }
        startup::check_logs(
            &sessions_dir,
            tokens.subjects.iter().map(|s| s.subject.as_str()),
            &study.design,
        )?;
        tokens.save(&config.out)?;
        let listener = tokio::net::TcpListener::bind(config.addr)
            .await
            .with_context(|| format!("cannot listen on {}", config.addr))?;
        let addr = listener.local_addr()?;
        let base_url = config
            .base_url
            .clone()
            .unwrap_or_else(|| format!("http://{addr}"))
            .trim_end_matches('/')
            .to_string();
        // Rewritten whenever it exists, so it never lists links the tokens no longer open.
        let links_csv = match config.enrol.is_some() || config.out.join("links.csv").exists() {
            true => Some(tokens.write_links(&config.out, &base_url)?),
            false => None,
        };
        let started = Started {
            addr,
            admin_url: format!("{base_url}/admin?token={}", tokens.admin),
            admin_token: tokens.admin.clone(),
            links_csv,
            join_url: tokens
                .open
                .as_ref()
                .map(|o| format!("{base_url}/join/{}", o.token)),
            study_url: match (&study.design.file.online, &tokens.open) {
                (Some(o), Some(open)) => {
                    Some(format!("{base_url}/join/{}{}", open.token, o.study_query()))
                }
                _ => None,
            },
            subjects: tokens.subjects.len(),
            sessions_dir: sessions_dir.clone(),
            base_url,
            encoded: study.encoded,
            budget,
        };
        let app = App {
            study,
            out: config.out.clone(),
            sessions_dir,
            by_token: RwLock::default(),
            tokens: Mutex::new(tokens.clone()),
            per_link: guard::Limiter::new(guard::PER_LINK),
            per_address: guard::Limiter::new(guard::PER_ADDRESS_UNKNOWN),
            video_key,
        };
        for s in &tokens.subjects {
            app.insert(s);
        }
        Ok(Self {
            listener,
            connections: config.connections,
            app: Arc::new(app),
            started,
        })
    }

    /// Serve until `shutdown` completes.
    pub async fn run(self, shutdown: impl Future<Output = ()> + Send + 'static) -> Result<()> {
        let csp = guard::csp(self.app.study.client.video_base.as_deref());
        let router = api::router(self.app, csp);
        connections::serve(self.listener, router, self.connections, shutdown)
            .await
            .context("the HTTP server stopped")
    }
}

/// The design's study with its videos encoded, and its budget (not checked).
pub fn measure_study(
    config: &Config,
    progress: &mut dyn FnMut(usize, usize, &str),
) -> Result<(Study, budget::Budget)> {
    anyhow::ensure!(
        config.client.lookahead_frames >= 1,
        "--lookahead-frames is 0; expected at least 1"
    );
    let design = Design::load(&config.design)?;
    // Every stimulus the design shows exists, decodes to the manifest's size and frame count,
    // and (by default) hashes as rendered, before anyone is told the server is up: a fault
    // found in front of a subject is one no retry fixes.
    let checks = crate::preflight::PreflightOptions {
        check_hashes: config.check_hashes,
    };
    crate::preflight::preflight(&design, checks, &renderer::progress::NoProgress)
        .into_result()
        .with_context(|| {
            format!(
                "{}: the design's stimuli are not ready to serve",
                config.design.display()
            )
        })?;
    let study = Study::load(design, config.client.clone(), progress)?;
    let budget = budget::Budget::of(&study, config.limits);
    Ok((study, budget))
}

/// [`measure_study`], refusing a design no browser can hold (`budget::Budget::refusal`).
pub fn load_study(
    config: &Config,
    progress: &mut dyn FnMut(usize, usize, &str),
) -> Result<(Study, budget::Budget)> {
    let (study, budget) = measure_study(config, progress)?;
    if let Some(why) = budget.refusal() {
        anyhow::bail!("{}: {why}", config.design.display());
    }
    Ok((study, budget))
}

/// `blurlab serve`: bind, tell `report` what started, serve until Ctrl-C.
pub fn serve_until_interrupted(
    config: &Config,
    progress: &mut dyn FnMut(usize, usize, &str),
    report: impl FnOnce(&Started),
) -> Result<()> {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .context("cannot start the async runtime")?;
    runtime.block_on(async {
        let server = Server::bind_with(config, progress).await?;
        report(&server.started);
        server
            .run(async {
                let _ = tokio::signal::ctrl_c().await;
            })
            .await
    })
}

/// The session log of `subject` under `out`.
pub fn log_path(out: &Path, subject: &str) -> PathBuf {
    out.join("sessions").join(format!("{subject}.jsonl"))
}
