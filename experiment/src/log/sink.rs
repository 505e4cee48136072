//! Where a session's log lines go: the [`LogSink`] seam between the session machine and storage.
//! The app and `blurlab simulate` write a file ([`FileLog`]: the header written atomically,
//! every line pushed to disk before the session moves on, a torn last line repaired on reopen,
//! `log::writer`); `plan` and the efficiency runs keep each simulated log in memory
//! ([`MemoryLog`]) and read it back without touching the file system. Both hold the same bytes
//! for the same lines, and repair a torn tail the same way, so a simulation's dataset does not
//! depend on where its logs went.

use crate::log::writer::{Durability, LogWriter, Tail, line_bytes, tail_of};
use crate::log::{Header, LogLine};
use anyhow::{Result, bail};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// A session log's storage.
pub trait LogSink: std::fmt::Debug + Send {
    /// What names the log in messages (a file's path; a memory log's name).
    fn name(&self) -> &Path;
    /// The log's bytes when the session opens it; `None` when there is no log yet.
    fn existing(&self) -> Result<Option<Vec<u8>>>;
    /// Start a log holding only `header`, replacing whatever was there.
    fn create(&mut self, header: &Header) -> Result<()>;
    /// Continue the existing log. A last line without its newline is kept when it is whole
    /// JSON and cut off otherwise; the account of a cut is returned.
    fn reopen(&mut self) -> Result<Option<String>>;
    /// Append one line; it is stored (per the sink's durability) when this returns.
    fn append(&mut self, line: &LogLine) -> Result<()>;
}

/// A log file (the app, `blurlab simulate`, resume).
#[derive(Debug)]
pub struct FileLog {
    path: PathBuf,
    durability: Durability,
    writer: Option<LogWriter>,
}

impl FileLog {
    pub fn new(path: &Path, durability: Durability) -> Self {
        Self {
            path: path.to_path_buf(),
            durability,
            writer: None,
        }
    }
}

impl LogSink for FileLog {
    fn name(&self) -> &Path {
        &self.path
    }

    fn existing(&self) -> Result<Option<Vec<u8>>> {
        if !self.path.exists() {
            return Ok(None);
        }
        std::fs::read(&self.path)
            .map(Some)
            .map_err(|e| anyhow::anyhow!("cannot read session log {}: {e}", self.path.display()))
    }

    fn create(&mut self, header: &Header) -> Result<()> {
        self.writer = Some(LogWriter::create(&self.path, header, self.durability)?);
        Ok(())
    }

    fn reopen(&mut self) -> Result<Option<String>> {
        let (w, warning) = LogWriter::reopen(&self.path, self.durability)?;
        self.writer = Some(w);
        Ok(warning)
    }

    fn append(&mut self, line: &LogLine) -> Result<()> {
        match self.writer.as_mut() {
            Some(w) => w.append(line),
            None => bail!("session log {} is not open", self.path.display()),
        }
    }
}

/// A log in memory: `plan`'s and the efficiency runs' simulated sessions, read back with
/// [`crate::log::SessionLog::parse`]. Clones share the bytes, so the caller keeps a clone to
/// read what the session wrote.
#[derive(Clone, Debug, Default)]
pub struct MemoryLog {
    name: PathBuf,
    bytes: Arc<Mutex<Vec<u8>>>,
}

impl MemoryLog {
    /// An empty log; `name` (e.g. `s01.jsonl`) stands for its path in messages.
    pub fn new(name: &str) -> Self {
        Self {
            name: PathBuf::from(name),
            bytes: Arc::default(),
        }
    }

    /// A log that already holds `bytes` (a session to continue).
    pub fn with_bytes(name: &str, bytes: Vec<u8>) -> Self {
        let log = Self::new(name);
        *log.lock() = bytes;
        log
    }

    /// The bytes written so far.
    pub fn bytes(&self) -> Vec<u8> {
        self.lock().clone()
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Vec<u8>> {
        // A panic while holding the lock leaves whole lines only (each is one extend).
        self.bytes.lock().unwrap_or_else(|e| e.into_inner())
    }
}

impl LogSink for MemoryLog {
    fn name(&self) -> &Path {
        &self.name
    }

    fn existing(&self) -> Result<Option<Vec<u8>>> {
        let bytes = self.lock();
        Ok((!bytes.is_empty()).then(|| bytes.clone()))
    }

    fn create(&mut self, header: &Header) -> Result<()> {
        *self.lock() = line_bytes(&LogLine::Header(header.clone()))?;
        Ok(())
    }

    fn reopen(&mut self) -> Result<Option<String>> {
        let mut bytes = self.lock();
        Ok(match tail_of(&bytes) {
            Tail::Clean => None,
            Tail::MissingNewline => {
                bytes.push(b'\n');
                None
            }
            Tail::Torn { whole } => {
                let warning = Tail::torn_warning(&self.name, bytes.len() - whole);
                bytes.truncate(whole);
                Some(warning)
            }
        })
    }

    fn append(&mut self, line: &LogLine) -> Result<()> {
        let line = line_bytes(line)?;
        self.lock().extend_from_slice(&line);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::log::writer::tests::header;

    fn resume() -> LogLine {
        LogLine::Resume(crate::log::writer::tests::resume())
    }

    /// A file log and a memory log given the same lines, then the same damaged bytes, hold the
    /// same bytes and give the same account: a clean end, a whole last line missing its newline
    /// (kept), a torn last line (cut).
    #[test]
    fn file_and_memory_logs_store_and_repair_alike() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.jsonl");
        let mut file = FileLog::new(&path, Durability::Flush);
        let mut memory = MemoryLog::new("s.jsonl");
        assert_eq!(file.existing().unwrap(), None);
        assert_eq!(memory.existing().unwrap(), None);
        for sink in [&mut file as &mut dyn LogSink, &mut memory] {
            sink.create(&header()).unwrap();
            sink.append(&resume()).unwrap();
        }
        let whole = std::fs::read(&path).unwrap();
        assert_eq!(memory.bytes(), whole);
        assert_eq!(file.existing().unwrap(), Some(whole.clone()));
        let resume_line = line_bytes(&resume()).unwrap();
        let unterminated = [&whole[..], &resume_line[..resume_line.len() - 1]].concat();
        let torn = [&whole[..], b"{\"kind\":\"trial\",\"ind"].concat();
        for (damaged, repaired, cut) in [
            (whole.clone(), whole.clone(), None),
            (
                unterminated.clone(),
                [&whole[..], &resume_line].concat(),
                None,
            ),
            (torn, whole.clone(), Some("20 bytes")),
        ] {
            std::fs::write(&path, &damaged).unwrap();
            let mut file = FileLog::new(&path, Durability::Flush);
            let mut memory = MemoryLog::with_bytes("s.jsonl", damaged);
            let full_name = path.display().to_string();
            let a = file
                .reopen()
                .unwrap()
                .map(|w| w.replace(&full_name, "s.jsonl"));
            let b = memory.reopen().unwrap();
            assert_eq!(a, b);
            assert_eq!(a.is_some(), cut.is_some());
            if let (Some(a), Some(cut)) = (a, cut) {
                assert!(a.starts_with("s.jsonl: removed") && a.contains(cut), "{a}");
            }
            assert_eq!(std::fs::read(&path).unwrap(), repaired);
            assert_eq!(memory.bytes(), repaired);
        }
    }
}
