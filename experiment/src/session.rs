//! The session state machine, shared by the app and the simulator (no GUI types):
//!
//! ```text
//! Instructions -> Practice(0..p) -> PracticeDone -> Trial(0..n) -> Finished
//!                                       every `break_every` trials: Break -> Trial
//! ```
//!
//! Screens (instructions, end of practice, breaks) are left with [`Session::advance`]; a trial
//! is left with [`Session::answer`], which stores the trial's log line before the next phase
//! exists. [`Session::open`] on an existing log continues at the next unanswered trial of the
//! same list, after checking that the log belongs to this subject and this exact design and
//! that every logged trial is the planned one.
//!
//! The log is behind [`LogSink`]: a file for the app and `blurlab simulate`
//! ([`Session::open`]), memory for `plan` and other simulations that keep nothing on disk
//! ([`Session::open_with`] and a [`crate::log::sink::MemoryLog`]).

use crate::design::{Design, Task};
use crate::log::sink::{FileLog, LogSink};
use crate::log::writer::{Durability, whole_lines_len};
use crate::log::{Display, Header, LOG_FORMAT, LogLine, Resume, SessionLog, Timing, TrialRecord};
use crate::procedure::{self, Procedure, TrackEstimate};
use crate::trials::{self, Trial};
use anyhow::{Result, bail};
use std::path::Path;

/// Where a session is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    Instructions,
    /// Presenting practice trial `i` (index into [`Session::practice`]).
    Practice(usize),
    /// Practice is over; the main trials come next.
    PracticeDone,
    /// Presenting main trial `i` (the `i`-th the procedure gives).
    Trial(usize),
    Break,
    Finished,
}

/// How a session is started: what goes into the header (or the resume line).
#[derive(Clone, Debug)]
pub struct StartInfo {
    /// `gui`, `web` or `simulated`.
    pub mode: String,
    pub display: Option<Display>,
    pub observer: Option<serde_json::Value>,
    /// Seconds since the Unix epoch (simulations use 0 so their logs are reproducible).
    pub started_unix: f64,
}

/// The outcome of one answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Answered {
    pub correct: bool,
    pub practice: bool,
}

/// One subject's session over one design.
#[derive(Debug)]
pub struct Session {
    design: Design,
    subject: String,
    /// The subject's seed (see [`Design::subject_seed`]).
    seed: u64,
    /// The practice trials (the main ones come from the procedure).
    practice: Vec<Trial>,
    /// Gives the main trials, one at a time, from the answers so far.
    procedure: Box<dyn Procedure>,
    log: Box<dyn LogSink>,
    /// The log found at `open`, if it had a header.
    existing: Option<SessionLog>,
    /// The header or the resume line is written.
    started: bool,
    practice_done: usize,
    main_done: usize,
    phase: Phase,
    warnings: Vec<String>,
    /// Goes into a new log's header (`set_participant`).
    participant: Option<crate::log::Participant>,
}

/// The text a log names its program with.
pub fn app_version() -> String {
    format!("blurlab {}", env!("CARGO_PKG_VERSION"))
}

/// Subjects name files: letters, digits, `-` and `_` only.
pub fn check_subject(subject: &str) -> Result<()> {
    if subject.is_empty()
        || !subject
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
    {
        bail!("subject {subject:?}: expected letters, digits, `-` or `_` (it names the log file)");
    }
    Ok(())
}

impl Session {
    /// Prepare a session logged to the file `log_path`, reading it if it exists (nothing is
    /// written yet).
    pub fn open(
        design: &Design,
        subject: &str,
        log_path: &Path,
        durability: Durability,
    ) -> Result<Self> {
        Self::open_with(
            design,
            subject,
            Box::new(FileLog::new(log_path, durability)),
        )
    }

    /// Prepare a session logged to `log`, reading what it holds (nothing is written yet).
    pub fn open_with(design: &Design, subject: &str, log: Box<dyn LogSink>) -> Result<Self> {
        check_subject(subject)?;
        if design.file.task != Task::TwoPair {
            bail!(
                "{}: field `task` is {}; sessions present the two-pair task only (a design with \
                 another task describes data collected elsewhere, for `blurlab analyze --design`)",
                design.path.display(),
                design.file.task
            );
        }
        let seed = design.subject_seed(subject);
        let mut s = Session {
            design: design.clone(),
            subject: subject.to_string(),
            seed,
            practice: trials::practice_trials(design, seed),
            procedure: procedure::start(design, subject),
            log,
            existing: None,
            started: false,
            practice_done: 0,
            main_done: 0,
            phase: Phase::Instructions,
            warnings: Vec::new(),
            participant: None,
        };
        if let Some(bytes) = s.log.existing()? {
            s.read_existing(bytes)?;
        }
        Ok(s)
    }

    fn read_existing(&mut self, bytes: Vec<u8>) -> Result<()> {
        let path = self.log.name().to_path_buf();
        let path = &path;
        if whole_lines_len(&bytes) == 0 {
            // Not even the header is whole (it is written atomically, so only an outside
            // truncation does this): nothing was answered, start afresh.
            self.warnings.push(format!(
                "{}: holds no complete line; starting the session afresh",
                path.display()
            ));
            return Ok(());
        }
        let log = SessionLog::parse(path, bytes)?;
        let h = &log.header;
        if h.subject != self.subject {
            bail!(
                "{}: field `subject` is {:?}, not {:?}; each subject has their own log file",
                path.display(),
                h.subject,
                self.subject
            );
        }
        if h.design_hash != self.design.hash {
            bail!(
                "{}: was written with design {:?} (hash {}), but {} now has hash {}: a changed \
                 design changes the trial list, so this session cannot be continued with it. \
                 Restore the design file, or write the new design's sessions to another folder",
                path.display(),
                h.design,
                h.design_hash,
                self.design.path.display(),
                self.design.hash
            );
        }
        self.check_trials(&log)?;
        self.warnings.extend(log.warnings.iter().cloned());
        self.existing = Some(log);
        Ok(())
    }

    /// Every logged trial must be the one the design put there, in order: practice first, then
    /// the main trials, which are replayed into the procedure (an adaptive one is then in the
    /// state an uninterrupted session would have).
    fn check_trials(&mut self, log: &SessionLog) -> Result<()> {
        let practice = log.trials.iter().take_while(|r| r.practice).count();
        let (practice, main) = log.trials.split_at(practice);
        let wrong = |r: &TrialRecord| {
            anyhow::anyhow!(
                "{}: logged {} trial {} ({}) is not the trial this design and seed put there; \
                 the log does not belong to this trial list",
                log.path.display(),
                if r.practice { "practice" } else { "main" },
                r.index,
                r.test_stimulus
            )
        };
        for (i, r) in practice.iter().enumerate() {
            if !self.practice.get(i).is_some_and(|t| t.matches(r)) {
                return Err(wrong(r));
            }
        }
        self.practice_done = practice.len();
        // The main trials up to a practice trial among them, which comes too late.
        let until_practice = main.iter().take_while(|r| !r.practice);
        let replayed = procedure::replay(self.procedure.as_mut(), until_practice);
        self.main_done = replayed.answered();
        match main.get(self.main_done) {
            Some(r) => Err(wrong(r)),
            None => Ok(()),
        }
    }

    /// Write the header (new log) or a resume line (continued log); the session is then at
    /// its instructions screen.
    pub fn start(&mut self, info: StartInfo) -> Result<()> {
        if self.started {
            bail!("session {} already started", self.log.name().display());
        }
        if let Some(log) = &self.existing {
            if log.header.mode != info.mode {
                bail!(
                    "{}: field `mode` is {:?}, but this session is {:?}: a log holds one \
                     kind of answers (a person's or a simulated observer's), and `analyze` \
                     must not mix them. Write this session to another folder",
                    self.log.name().display(),
                    log.header.mode,
                    info.mode
                );
            }
            if let Some(warning) = self.log.reopen()? {
                // The writer's account of the torn line (what it removed) replaces the reader's.
                self.warnings
                    .retain(|x| !x.contains("incomplete last line"));
                self.warnings.push(warning);
            }
            self.log.append(&LogLine::Resume(Resume {
                started_unix: info.started_unix,
                app_version: app_version(),
                practice_done: self.practice_done as u32,
                trials_done: self.main_done as u32,
                display: info.display,
                warnings: self.warnings.clone(),
            }))?;
        } else {
            let header = Header {
                format: LOG_FORMAT.into(),
                subject: self.subject.clone(),
                session: 1,
                design: self.design.name().to_string(),
                design_hash: self.design.hash.clone(),
                seed: self.seed,
                app_version: app_version(),
                mode: info.mode,
                started_unix: info.started_unix,
                trials_planned: self.procedure.planned(),
                display: info.display,
                observer: info.observer,
                participant: self.participant.clone(),
            };
            self.log.create(&header)?;
        }
        self.started = true;
        self.phase = Phase::Instructions;
        Ok(())
    }

    /// A web participant's ids and consent, for the header [`Session::start`] writes.
    pub fn set_participant(&mut self, p: crate::log::Participant) {
        self.participant = Some(p);
    }

    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// The trial being presented, if the phase is a trial.
    pub fn trial(&self) -> Option<&Trial> {
        match self.phase {
            Phase::Practice(i) => self.practice.get(i),
            Phase::Trial(_) => self.procedure.current(),
            _ => None,
        }
    }

    /// The trial after the current one (what to load next), if no answer to the current one
    /// can change it.
    pub fn next_trial(&self) -> Option<Trial> {
        match self.phase {
            Phase::Practice(i) => self
                .practice
                .get(i + 1)
                .or_else(|| self.procedure.current())
                .cloned(),
            Phase::Trial(_) => self.procedure.after_current(),
            _ => None,
        }
    }

    /// Up to `n` trials from the one presented now (or presented next, at a screen phase) that
    /// no answer can change: the practice trials left, then the main ones as far as the
    /// procedure knows them (constant stimuli: all; adaptive: the next if it is certain).
    pub fn upcoming(&self, n: usize) -> Vec<Trial> {
        let mut out = Vec::new();
        if self.phase == Phase::Finished {
            return out;
        }
        if self.main_done == 0 {
            out.extend(
                self.practice
                    .iter()
                    .skip(self.practice_done)
                    .take(n)
                    .cloned(),
            );
            // The first main trial depends on no answer.
        }
        if out.len() < n
            && let Some(t) = self.procedure.current()
        {
            out.push(t.clone());
            out.extend(self.procedure.ahead(n - out.len()));
        }
        out.truncate(n);
        out
    }

    /// Leave a screen phase (instructions, end of practice, break) for the next trial.
    pub fn advance(&mut self) {
        if matches!(
            self.phase,
            Phase::Instructions | Phase::PracticeDone | Phase::Break
        ) {
            self.phase = self.next_trial_phase();
        }
    }

    fn next_trial_phase(&self) -> Phase {
        if self.main_done == 0 && self.practice_done < self.practice.len() {
            Phase::Practice(self.practice_done)
        } else if self.procedure.current().is_some() {
            Phase::Trial(self.main_done)
        } else {
            Phase::Finished
        }
    }

    /// Record the subject's answer (pair 1 or 2) to the current trial. The log line is stored
    /// (on disk, for a file log) when this returns; then the session moves on.
    pub fn answer(&mut self, response: u8, timing: Timing) -> Result<Answered> {
        let Some(trial) = self.trial() else {
            bail!("no trial is being presented (phase {:?})", self.phase);
        };
        if response != 1 && response != 2 {
            bail!("response {response}: expected pair 1 or 2");
        }
        let record = record(trial, response, timing);
        let answered = Answered {
            correct: record.correct,
            practice: record.practice,
        };
        if !self.started {
            bail!("session not started: call start() before answering");
        }
        self.log.append(&LogLine::Trial(record))?;
        self.phase = if answered.practice {
            self.practice_done += 1;
            if self.practice_done < self.practice.len() {
                Phase::Practice(self.practice_done)
            } else if self.procedure.current().is_none() {
                Phase::Finished
            } else {
                Phase::PracticeDone
            }
        } else {
            self.procedure.answer(answered.correct);
            self.main_done += 1;
            let every = self.design.file.break_every as usize;
            if self.procedure.current().is_none() {
                Phase::Finished
            } else if every > 0 && self.main_done.is_multiple_of(every) {
                Phase::Break
            } else {
                Phase::Trial(self.main_done)
            }
        };
        Ok(answered)
    }

    /// Main trials answered and planned (an adaptive procedure's most).
    pub fn progress(&self) -> (usize, usize) {
        (self.main_done, self.procedure.planned() as usize)
    }

    pub fn practice_progress(&self) -> (usize, usize) {
        (self.practice_done, self.practice.len())
    }

    /// Every main trial is answered (the procedure has no more).
    pub fn is_complete(&self) -> bool {
        self.procedure.current().is_none()
    }

    /// The adaptive tracks' estimates so far (empty for constant stimuli).
    pub fn estimates(&self) -> Vec<TrackEstimate> {
        self.procedure.estimates()
    }

    /// The session continues an earlier log.
    pub fn resumed(&self) -> bool {
        self.existing.is_some()
    }

    /// What was tolerated when the log was reopened.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// The practice trials (the main ones come from the procedure: see [`Session::trial`]).
    pub fn practice(&self) -> &[Trial] {
        &self.practice
    }

    pub fn design(&self) -> &Design {
        &self.design
    }

    pub fn subject(&self) -> &str {
        &self.subject
    }

    /// The log's file (a memory log's name).
    pub fn log_path(&self) -> &Path {
        self.log.name()
    }
}

fn record(t: &Trial, response: u8, timing: Timing) -> TrialRecord {
    TrialRecord {
        index: t.index,
        practice: t.practice,
        scene: t.condition.scene.clone(),
        point_set: t.condition.point_set,
        time_filter: t.condition.time_filter,
        level: t.level,
        test_stimulus: t.test_stimulus.clone(),
        reference_stimulus: t.reference_stimulus.clone(),
        diff_pair: t.diff_pair,
        test_side: t.test_side,
        response,
        correct: response == t.diff_pair,
        timing,
        catch: t.catch,
    }
}
