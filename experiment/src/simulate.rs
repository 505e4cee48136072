//! Simulated subjects: the real session machine and log writer, answered by an [`Observer`].
//! Logs are a pure function of the design, the observer and the subject names (the header's
//! start time is 0), so a simulation rerun gives byte-identical files. [`simulate`] writes log
//! files (`blurlab simulate`); [`simulate_in_memory`] keeps the same bytes in memory
//! ([`MemoryLog`]) and reads them back, for `plan` and other runs that need no files.

use crate::design::Design;
use crate::log::SessionLog;
use crate::log::Timing;
use crate::log::sink::{LogSink, MemoryLog};
use crate::log::writer::Durability;
use crate::observer::Observer;
use crate::session::{Phase, Session, StartInfo};
use anyhow::{Context, Result, bail};
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// The name of simulated subject `i` (0-based): `s01`, `s02`, ...
pub fn subject_name(i: usize) -> String {
    format!("s{:02}", i + 1)
}

/// Simulate `subjects` subjects (`s01`...), writing `out_dir/<subject>.jsonl` for each
/// (replacing earlier simulations of the same names). Returns the log paths in subject order.
pub fn simulate(
    design: &Design,
    observer: &Observer,
    subjects: usize,
    out_dir: &Path,
) -> Result<Vec<PathBuf>> {
    let most = renderer::limits::MAX_SUBJECTS as u64;
    renderer::limits::check_count("the number of subjects", subjects as u64, 1, most)?;
    observer.check_covers(design)?;
    std::fs::create_dir_all(out_dir)
        .with_context(|| format!("cannot create folder {}", out_dir.display()))?;
    (0..subjects)
        .into_par_iter()
        .map(|i| {
            let subject = subject_name(i);
            let path = out_dir.join(format!("{subject}.jsonl"));
            simulate_subject(design, observer, &subject, &path)?;
            Ok(path)
        })
        .collect()
}

/// One simulated subject's whole session into a fresh log at `path`.
pub fn simulate_subject(
    design: &Design,
    observer: &Observer,
    subject: &str,
    path: &Path,
) -> Result<()> {
    if path.exists() {
        refuse_a_persons_log(path)?;
        std::fs::remove_file(path).with_context(|| format!("cannot replace {}", path.display()))?;
    }
    let session = Session::open(design, subject, path, Durability::Flush)?;
    run(session, observer)
}

/// [`simulate`] into memory: the subjects' logs, read back, in the order a folder of their
/// files is read (by file name). Nothing touches the file system.
pub fn simulate_in_memory(
    design: &Design,
    observer: &Observer,
    subjects: usize,
) -> Result<Vec<SessionLog>> {
    let most = renderer::limits::MAX_SUBJECTS as u64;
    renderer::limits::check_count("the number of subjects", subjects as u64, 1, most)?;
    observer.check_covers(design)?;
    let mut logs: Vec<SessionLog> = (0..subjects)
        .into_par_iter()
        .map(|i| simulate_subject_in_memory(design, observer, &subject_name(i)))
        .collect::<Result<_>>()?;
    logs.sort_by(|a, b| a.path.cmp(&b.path));
    Ok(logs)
}

/// One simulated subject's whole session in a [`MemoryLog`] named `<subject>.jsonl`, read back.
pub fn simulate_subject_in_memory(
    design: &Design,
    observer: &Observer,
    subject: &str,
) -> Result<SessionLog> {
    let log = MemoryLog::new(&format!("{subject}.jsonl"));
    simulate_subject_to(design, observer, subject, Box::new(log.clone()))?;
    SessionLog::parse(log.name(), log.bytes())
}

/// One simulated subject's whole session into `log`, which must hold no session yet.
pub fn simulate_subject_to(
    design: &Design,
    observer: &Observer,
    subject: &str,
    log: Box<dyn LogSink>,
) -> Result<()> {
    run(Session::open_with(design, subject, log)?, observer)
}

/// Start a fresh simulated session (time 0) and answer it to its end.
fn run(mut session: Session, observer: &Observer) -> Result<()> {
    session.start(StartInfo {
        mode: "simulated".into(),
        display: None,
        observer: Some(serde_json::to_value(&observer.file)?),
        started_unix: 0.0,
    })?;
    answer_all(&mut session, observer)
}

/// A simulation replaces its own earlier logs, never a person's: a log whose header says
/// another mode than `simulated` (or that cannot be read as a log) is left alone.
fn refuse_a_persons_log(path: &Path) -> Result<()> {
    let first = std::fs::read(path)
        .ok()
        .and_then(|b| b.split(|&c| c == b'\n').next().map(<[u8]>::to_vec))
        .unwrap_or_default();
    let mode = serde_json::from_slice::<serde_json::Value>(&first)
        .ok()
        .and_then(|v| v.get("mode").and_then(|m| m.as_str()).map(str::to_string));
    match mode.as_deref() {
        Some("simulated") => Ok(()),
        other => bail!(
            "{}: {}; a simulation replaces only its own logs. Simulate into another folder",
            path.display(),
            match other {
                Some(m) => format!("holds a session of mode {m:?} (a person's answers)"),
                None => "is not a simulated session log".to_string(),
            }
        ),
    }
}

/// Drive a started session to its end with the observer's answers.
pub fn answer_all(session: &mut Session, observer: &Observer) -> Result<()> {
    loop {
        match session.phase() {
            Phase::Instructions | Phase::PracticeDone | Phase::Break => session.advance(),
            Phase::Practice(_) | Phase::Trial(_) => {
                let trial = session.trial().expect("a trial phase has a trial");
                let response = observer.respond(trial, session.subject())?;
                session.answer(response, Timing::default())?;
            }
            Phase::Finished => return Ok(()),
        }
    }
}
