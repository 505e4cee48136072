//! One subject's session on the server: the [`Session`] machine over a synced [`FileLog`], the
//! claim of the one tab that may answer, the idempotency record of acknowledged answers and the
//! subject's opaque video ids. Everything here is synchronous (it writes and syncs the log): the
//! HTTP layer calls it on tokio's blocking threads.

use super::error::ApiError;
use super::inputs::{check_answer, check_display, check_tab_id};
use super::study::Study;
use super::wire::{Ack, Answer, AnswerReply, DisplayFacts, Feedback, Progress, State, TrialView};
use crate::log::writer::Durability;
use crate::log::{BrowserDisplay, Display, SessionLog, Side};
use crate::session::{Phase, Session, StartInfo};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A claim lapses after this long without a call from its tab; a reload then takes over.
pub const LEASE: Duration = Duration::from_secs(20);

pub const OTHER_TAB: &str = "this session is open in another tab or window";

/// A subject's names for the study's videos, both ways: `id -> stimulus` (the video route) and
/// `stimulus -> id` (the state). Fixed for the session; shared with the video route, which must
/// not wait for a log sync to look one up.
#[derive(Debug, Default)]
pub struct VideoIds {
    pub stimulus_of: HashMap<String, String>,
    pub id_of: HashMap<String, String>,
}

impl VideoIds {
    /// The ids subject `token` sees (`video_ids::session_id`), or with `shared` the study's
    /// export names, the same for every subject (videos on a static server).
    pub fn new(study: &Study, key: &str, token: &str, shared: bool) -> Self {
        let mut ids = Self::default();
        for (stimulus, served) in study.videos() {
            let sha = &served.pack.sha256;
            let id = if shared {
                super::video_ids::export_name(key, sha)
            } else {
                super::video_ids::session_id(key, token, sha)
            };
            ids.stimulus_of.insert(id.clone(), stimulus.to_string());
            ids.id_of.insert(stimulus.to_string(), id);
        }
        ids
    }
}

#[derive(Debug)]
struct Lease {
    tab: String,
    seen: Instant,
}

/// What the admin page shows of one subject.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SubjectProgress {
    pub subject: String,
    pub started: bool,
    pub finished: bool,
    pub practice_done: usize,
    pub done: usize,
    pub planned: usize,
    /// Main trials answered in this run of the server, and over how many seconds.
    #[serde(skip)]
    pub run_answers: u32,
    #[serde(skip)]
    pub run_seconds: f64,
    /// A platform participant's id (the design's `online`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub participant: Option<String>,
    /// Why the participant was screened out before any trial.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub screened_out: Option<String>,
    /// The design's exclusion criteria this subject fails so far (`crate::screening`).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub flags: Vec<String>,
}

#[derive(Debug)]
pub struct Subject {
    pub name: String,
    pub(super) log_path: PathBuf,
    session: Option<Session>,
    /// `start` was called in this run (header or resume line written).
    started: bool,
    /// Every acknowledged answer: (practice, index) -> correct.
    answered: HashMap<(bool, u32), bool>,
    lease: Option<Lease>,
    pub videos: Arc<VideoIds>,
    first_answer: Option<Instant>,
    run_answers: u32,
    /// A platform participant's ids and consent (`participant.rs`), for the header.
    pub(crate) participant: crate::log::Participant,
    /// Why the participant was screened out before any trial.
    pub(crate) screened_out: Option<String>,
}

impl Subject {
    pub fn new(name: &str, sessions_dir: &std::path::Path, videos: Arc<VideoIds>) -> Self {
        Self {
            name: name.to_string(),
            log_path: sessions_dir.join(format!("{name}.jsonl")),
            session: None,
            started: false,
            answered: HashMap::new(),
            lease: None,
            videos,
            first_answer: None,
            run_answers: 0,
            participant: crate::log::Participant::default(),
            screened_out: None,
        }
    }

    /// Open the session (reading its log) if not yet open.
    pub(super) fn open(&mut self, study: &Study) -> Result<(), ApiError> {
        self.session(study).map(|_| ())
    }

    /// The tab holds the claim (renewed).
    pub(super) fn check_claim(&mut self, tab: &str) -> Result<(), ApiError> {
        self.check_tab(tab, false)
    }

    /// The session has a log: begun in this run or an earlier one.
    pub(super) fn has_started(&self) -> bool {
        self.started || self.session.as_ref().is_some_and(|s| s.resumed())
    }

    pub(super) fn current_state(&mut self, study: &Study) -> State {
        self.state(study)
    }

    /// Open the session (reading its log, if any) the first time it is needed.
    fn session(&mut self, study: &Study) -> Result<&mut Session, ApiError> {
        if self.session.is_none() {
            let s = Session::open(&study.design, &self.name, &self.log_path, Durability::Sync)
                .map_err(|e| ApiError::internal(&e))?;
            if s.resumed() {
                let log = SessionLog::read(&self.log_path).map_err(|e| ApiError::internal(&e))?;
                if log.header.mode != "web" {
                    return Err(ApiError::conflict(format!(
                        "the log of this session holds a {:?} session, not a web one; ask the \
                         experimenter",
                        log.header.mode
                    )));
                }
                for t in &log.trials {
                    self.answered.insert((t.practice, t.index), t.correct);
                }
            }
            self.session = Some(s);
        }
        Ok(self.session.as_mut().expect("opened above"))
    }

    /// Whether the log has a header (the subject has begun), without opening the session.
    pub fn progress(&self, study: &Study) -> SubjectProgress {
        let (started, finished, practice_done, done, planned) = match &self.session {
            Some(s) => {
                let (d, p) = s.progress();
                (
                    self.started || s.resumed(),
                    s.phase() == Phase::Finished || s.is_complete(),
                    s.practice_progress().0,
                    d,
                    p,
                )
            }
            None => {
                let log = SessionLog::read(&self.log_path).ok();
                let planned = log
                    .as_ref()
                    .map_or(study.design.main_trial_count() as usize, |l| {
                        l.header.trials_planned as usize
                    });
                let done = log.as_ref().map_or(0, |l| l.main_trials().count());
                let practice = log
                    .as_ref()
                    .map_or(0, |l| l.trials.len() - l.main_trials().count());
                (
                    log.is_some(),
                    log.is_some() && done >= planned,
                    practice,
                    done,
                    planned,
                )
            }
        };
        SubjectProgress {
            subject: self.name.clone(),
            started,
            finished,
            practice_done,
            done,
            planned,
            run_answers: self.run_answers,
            run_seconds: self.first_answer.map_or(0.0, |t| t.elapsed().as_secs_f64()),
            participant: study
                .design
                .file
                .online
                .as_ref()
                .and_then(|o| self.participant.ids.get(&o.id_param()).cloned()),
            screened_out: self.screened_out.clone(),
            flags: self.flags(study, started),
        }
    }

    /// The tab `tab` may act: it holds the claim, or no live claim is held by another. A call
    /// from the holder renews the claim.
    fn check_tab(&mut self, tab: &str, take_over: bool) -> Result<(), ApiError> {
        check_tab_id(tab)?;
        let now = Instant::now();
        match &mut self.lease {
            Some(l) if l.tab == tab => l.seen = now,
            Some(l) if now.duration_since(l.seen) < LEASE => {
                return Err(ApiError::conflict(OTHER_TAB));
            }
            _ if take_over => {
                self.lease = Some(Lease {
                    tab: tab.to_string(),
                    seen: now,
                })
            }
            _ => {
                return Err(ApiError::conflict(
                    "this tab's claim on the session lapsed; claim it again (reload the page)",
                ));
            }
        }
        Ok(())
    }

    pub fn claim(&mut self, study: &Study, tab: &str) -> Result<State, ApiError> {
        self.session(study)?;
        self.check_tab(tab, true)?;
        Ok(self.state(study))
    }

    pub fn get_state(&mut self, study: &Study, tab: &str) -> Result<State, ApiError> {
        self.session(study)?;
        self.check_tab(tab, false)?;
        Ok(self.state(study))
    }

    /// Log the browser's display facts and start (or continue) the session.
    pub fn display(&mut self, study: &Study, facts: &DisplayFacts) -> Result<State, ApiError> {
        self.session(study)?;
        self.check_tab(&facts.tab, false)?;
        if self.screened_out.is_some() {
            return Ok(self.state(study));
        }
        if study.consent.is_some() && self.participant.consent.is_none() && !self.has_started() {
            return Err(ApiError::conflict(
                "consent comes before the display check; reload the page",
            ));
        }
        check_display(facts, study.min_window_px)?;
        if !self.has_started()
            && let Some(why) = study.design.file.online.as_ref().and_then(|o| {
                o.screening.violation(
                    facts.pixels_per_degree,
                    facts.viewing_distance_mm,
                    facts.refresh_interval_ms,
                )
            })
        {
            self.screened_out = Some(format!("display check: {why}"));
            return Ok(self.state(study));
        }
        if !self.started {
            let display = Display {
                width: facts.screen_px[0],
                height: facts.screen_px[1],
                pixels_per_point: facts.device_pixel_ratio as f32,
                refresh_interval_ms: facts.refresh_interval_ms,
                browser: Some(BrowserDisplay {
                    window_px: facts.window_px,
                    device_pixel_ratio: facts.device_pixel_ratio,
                    px_per_mm: facts.px_per_mm,
                    viewing_distance_mm: facts.viewing_distance_mm,
                    pixels_per_degree: facts.pixels_per_degree,
                    user_agent: facts.user_agent.chars().take(400).collect(),
                    fullscreen: facts.fullscreen,
                }),
            };
            let started_unix = std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(0.0, |d| d.as_secs_f64());
            let participant = self.participant.clone();
            let session = self.session(study)?;
            if participant != crate::log::Participant::default() {
                session.set_participant(participant);
            }
            session
                .start(StartInfo {
                    mode: "web".into(),
                    display: Some(display),
                    observer: None,
                    started_unix,
                })
                .map_err(|e| ApiError::internal(&e))?;
            self.started = true;
        }
        Ok(self.state(study))
    }

    /// Leave the instructions or a break. A repeat (the phase already left) changes nothing.
    pub fn advance(&mut self, study: &Study, tab: &str, from: &str) -> Result<State, ApiError> {
        self.session(study)?;
        self.check_tab(tab, false)?;
        let session = self.session.as_mut().expect("opened");
        let here = match (from, session.phase()) {
            ("instructions", Phase::Instructions) => true,
            ("break", Phase::Break | Phase::PracticeDone) => true,
            ("instructions" | "break", _) => false,
            _ => {
                return Err(ApiError::bad_request(format!(
                    "field `from` is {from:?}; expected \"instructions\" or \"break\""
                )));
            }
        };
        if here && self.started {
            session.advance();
        }
        Ok(self.state(study))
    }

    /// Store an answer (its log line synced) and acknowledge it; the same answer again is
    /// acknowledged again and writes nothing.
    pub fn answer(&mut self, study: &Study, a: &Answer) -> Result<AnswerReply, ApiError> {
        self.session(study)?;
        check_tab_id(&a.tab)?;
        let ack = Ack {
            session: 1,
            practice: a.practice,
            trial: a.trial,
        };
        if self.screened_out.is_some() {
            return Err(ApiError::conflict(
                "this participant was screened out; no trials follow",
            ));
        }
        if a.session != 1 {
            return Err(ApiError::conflict(format!(
                "field `session` is {}; this link has session 1 only",
                a.session
            )));
        }
        let feedback_on = study.design.file.practice.feedback;
        let feedback = |practice: bool, correct: bool| {
            (practice && feedback_on).then_some(Feedback { correct })
        };
        if let Some(&correct) = self.answered.get(&(a.practice, a.trial)) {
            return Ok(AnswerReply {
                ack,
                feedback: feedback(a.practice, correct),
                state: self.state(study),
            });
        }
        // Not a replay: only the tab holding the claim may answer. (A replay is acknowledged
        // without the claim: after a server restart the claim is gone, and the browser must
        // still learn that the answer it sent before the crash is stored.)
        self.check_tab(&a.tab, false)?;
        let current = self
            .session
            .as_ref()
            .and_then(|s| s.trial())
            .map(|t| (t.practice, t.index));
        if !self.started || current != Some((a.practice, a.trial)) {
            return Err(ApiError::conflict(format!(
                "{} trial {} is not the trial being presented; reload the state and answer the \
                 current trial",
                if a.practice { "practice" } else { "main" },
                a.trial
            )));
        }
        check_answer(a, study.frames_shown)?;
        let mut timing = a.timing.clone();
        // Logs from browsers have always carried both, 0 when the browser did not say.
        timing.late_frames.get_or_insert(0);
        timing.refresh_interval_ms.get_or_insert(0.0);
        let session = self.session.as_mut().expect("opened");
        let answered = session
            .answer(a.response, timing)
            .map_err(|e| ApiError::internal(&e))?;
        self.answered
            .insert((a.practice, a.trial), answered.correct);
        if !a.practice {
            self.first_answer.get_or_insert_with(Instant::now);
            self.run_answers += 1;
        }
        Ok(AnswerReply {
            ack,
            feedback: feedback(a.practice, answered.correct),
            state: self.state(study),
        })
    }

    /// The state to show, with fresh handles when the trial changed.
    fn state(&mut self, study: &Study) -> State {
        let session = self.session.as_ref().expect("opened before state");
        let (pd, pp) = session.practice_progress();
        let (done, planned) = session.progress();
        let phase = session.phase();
        let (phase, message) = if self.screened_out.is_some() {
            (
                "screened_out",
                Some(
                    "Thank you for your interest. This study cannot continue on this computer \
                     or setup, so it ends here; no answers were recorded."
                        .to_string(),
                ),
            )
        } else if !self.started
            && !session.resumed()
            && self.participant.consent.is_none()
            && let Some(text) = &study.consent
        {
            ("consent", Some(text.text.clone()))
        } else if !self.started {
            ("display_check", None)
        } else {
            match phase {
                Phase::Instructions => ("instructions", Some(study.design.instructions())),
                Phase::Practice(_) => ("practice", None),
                Phase::Trial(_) => ("main", None),
                Phase::PracticeDone => (
                    "break",
                    Some("Practice is over. The main trials come next.".to_string()),
                ),
                Phase::Break => (
                    "break",
                    Some(format!(
                        "Take a short break. {done} of {planned} trials done."
                    )),
                ),
                Phase::Finished => (
                    "done",
                    Some(study.debriefing.as_ref().map_or_else(
                        || "The session is complete. Thank you!".to_string(),
                        |t| t.text.clone(),
                    )),
                ),
            }
        };
        let trial = if self.started {
            session.trial().cloned()
        } else {
            None
        };
        let view = trial.map(|t| TrialView {
            practice: t.practice,
            index: t.index,
            pairs: [1u8, 2].map(|p| [Side::Left, Side::Right].map(|s| self.id(t.video(p, s)))),
        });
        let ahead = self.ahead(study, session);
        let redirect = super::redirect::redirect(study, &self.participant, &self.name, phase);
        State {
            redirect,
            phase: phase.into(),
            session: 1,
            video: study.video.clone(),
            playback: study.playback.clone(),
            keys: study.keys.clone(),
            min_window_px: study.min_window_px,
            progress: Progress {
                practice_done: pd,
                practice_planned: pp,
                done,
                planned,
            },
            trial: view,
            ahead,
            client: study.client.clone(),
            message,
        }
    }

    /// The id this subject sees for stimulus `id` (every stimulus a trial shows has one).
    fn id(&self, stimulus: &str) -> String {
        self.videos.id_of.get(stimulus).cloned().unwrap_or_default()
    }

    /// Ids of the next trials' videos that the current trial does not show, first needed first.
    fn ahead(&self, study: &Study, session: &Session) -> Vec<String> {
        let n = study.client.fetch_ahead_trials as usize;
        let upcoming = session.upcoming(n + 1);
        // At a trial, the first upcoming trial is the current one; at a screen, the next one.
        let (current, rest): (Vec<String>, &[crate::trials::Trial]) =
            match (session.trial(), upcoming.split_first()) {
                (Some(_), Some((now, rest))) => {
                    (now.stimuli().iter().map(|s| self.id(s)).collect(), rest)
                }
                _ => (Vec::new(), &upcoming[..]),
            };
        let mut out: Vec<String> = Vec::new();
        for t in rest.iter().take(n) {
            for s in t.stimuli() {
                let id = self.id(s);
                if !current.contains(&id) && !out.contains(&id) {
                    out.push(id);
                }
            }
        }
        out
    }
}
