//! Appending to a session log so that a crash at any instant loses at most the answer being
//! written: the header is written atomically (temporary file + rename), every later line is one
//! `write` of the whole line followed by `sync_data` before the caller moves on, and reopening
//! cuts off a torn last line before appending after it (otherwise the torn fragment would
//! become a corrupt line in the middle of the log).

use crate::log::{Header, LogLine};
use anyhow::{Context, Result};
use std::fs::{File, OpenOptions};
use std::io::{Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

/// How hard each line is pushed to disk.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Durability {
    /// `sync_data` after every line: the line survives a power cut (real subjects).
    Sync,
    /// Written to the operating system only: survives the process being killed, not a power
    /// cut. For simulated sessions, which are regenerated rather than resumed (a sync costs
    /// ~5 ms here, which would dominate a 12-subject simulation).
    Flush,
}

/// An open session log.
#[derive(Debug)]
pub struct LogWriter {
    file: File,
    path: PathBuf,
    durability: Durability,
}

impl LogWriter {
    /// Start a log holding only `header`, replacing whatever is at `path`.
    pub fn create(path: &Path, header: &Header, durability: Durability) -> Result<Self> {
        let line = line_bytes(&LogLine::Header(header.clone()))?;
        renderer::atomic::write_atomic(path, &line)?;
        Self::open_append(path, durability)
    }

    /// Reopen an existing log to append. A last line without its newline is either complete
    /// JSON (the crash hit between the line and its newline: the newline is added and the
    /// answer kept, as the reader keeps it) or torn (cut off, described in the warning).
    pub fn reopen(path: &Path, durability: Durability) -> Result<(Self, Option<String>)> {
        let bytes =
            std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
        let tail = tail_of(&bytes);
        let mut warning = None;
        if tail != Tail::Clean {
            let f = OpenOptions::new()
                .write(true)
                .open(path)
                .with_context(|| format!("cannot open {} to repair it", path.display()))?;
            let repaired = match tail {
                Tail::Torn { whole } => {
                    warning = Some(Tail::torn_warning(path, bytes.len() - whole));
                    f.set_len(whole as u64).and_then(|_| f.sync_all())
                }
                _ => {
                    let mut f = f;
                    f.seek(SeekFrom::End(0))
                        .and_then(|_| f.write_all(b"\n"))
                        .and_then(|_| f.sync_all())
                }
            };
            repaired
                .with_context(|| format!("cannot repair the last line of {}", path.display()))?;
        }
        Ok((Self::open_append(path, durability)?, warning))
    }

    fn open_append(path: &Path, durability: Durability) -> Result<Self> {
        let file = OpenOptions::new()
            .append(true)
            .open(path)
            .with_context(|| format!("cannot open session log {} to append", path.display()))?;
        Ok(Self {
            file,
            path: path.to_path_buf(),
            durability,
        })
    }

    /// Append one line and push it to disk (per [`Durability`]) before returning.
    pub fn append(&mut self, line: &LogLine) -> Result<()> {
        let bytes = line_bytes(line)?;
        self.file
            .write_all(&bytes)
            .and_then(|_| self.file.flush())
            .and_then(|_| match self.durability {
                Durability::Sync => self.file.sync_data(),
                Durability::Flush => Ok(()),
            })
            .with_context(|| format!("cannot write to session log {}", self.path.display()))
    }

    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// One log line's bytes: its JSON and a newline.
pub fn line_bytes(line: &LogLine) -> Result<Vec<u8>> {
    let mut bytes = serde_json::to_vec(line)?;
    bytes.push(b'\n');
    Ok(bytes)
}

/// How a log's bytes end, for reopening.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tail {
    /// Empty, or ending in a newline.
    Clean,
    /// The last line is whole JSON without its newline (add it: the reader keeps the line).
    MissingNewline,
    /// The last line was cut off; the whole lines end at `whole`.
    Torn { whole: usize },
}

impl Tail {
    /// The account of a cut-off last line of `len` bytes.
    pub fn torn_warning(log: &Path, len: usize) -> String {
        format!(
            "{}: removed an incomplete last line ({len} bytes; the session was interrupted \
             while writing it, so that answer was not kept and its trial is shown again)",
            log.display()
        )
    }
}

/// How `bytes` end (see [`Tail`]).
pub fn tail_of(bytes: &[u8]) -> Tail {
    let whole = whole_lines_len(bytes);
    if whole == bytes.len() {
        Tail::Clean
    } else if serde_json::from_slice::<LogLine>(&bytes[whole..]).is_ok() {
        Tail::MissingNewline
    } else {
        Tail::Torn { whole }
    }
}

/// Length of the prefix made of whole (newline-terminated) lines.
pub fn whole_lines_len(bytes: &[u8]) -> usize {
    bytes.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::log::{LOG_FORMAT, SessionLog};

    /// A header and a resume line for log-storage tests (`log::sink` uses them too).
    pub(crate) fn header() -> Header {
        Header {
            format: LOG_FORMAT.into(),
            subject: "s".into(),
            session: 1,
            design: "d".into(),
            design_hash: "h".into(),
            seed: 1,
            app_version: "t".into(),
            mode: "simulated".into(),
            started_unix: 0.0,
            trials_planned: 0,
            display: None,
            observer: None,
            participant: None,
        }
    }

    pub(crate) fn resume() -> crate::log::Resume {
        crate::log::Resume {
            started_unix: 0.0,
            app_version: "t".into(),
            practice_done: 0,
            trials_done: 0,
            display: None,
            warnings: vec![],
        }
    }

    #[test]
    fn reopen_cuts_a_torn_tail_and_appends_after_the_last_whole_line() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.jsonl");
        drop(LogWriter::create(&path, &header(), Durability::Sync).unwrap());
        let whole = std::fs::read(&path).unwrap();
        let mut torn = whole.clone();
        torn.extend_from_slice(b"{\"kind\":\"trial\",\"ind");
        std::fs::write(&path, &torn).unwrap();

        let (mut w, warning) = LogWriter::reopen(&path, Durability::Sync).unwrap();
        assert!(warning.unwrap().contains("20 bytes"));
        assert_eq!(std::fs::read(&path).unwrap(), whole);
        w.append(&LogLine::Resume(resume())).unwrap();
        let log = SessionLog::read(&path).unwrap();
        assert!(log.warnings.is_empty());
        assert_eq!(log.resumes.len(), 1);
    }

    #[test]
    fn a_clean_log_reopens_without_warning_and_grows_by_whole_lines() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.jsonl");
        drop(LogWriter::create(&path, &header(), Durability::Flush).unwrap());
        let (mut w, warning) = LogWriter::reopen(&path, Durability::Flush).unwrap();
        assert!(warning.is_none());
        w.append(&LogLine::Resume(resume())).unwrap();
        let log = SessionLog::read(&path).unwrap();
        assert_eq!(log.resumes, vec![resume()]);
        assert!(std::fs::read(&path).unwrap().ends_with(b"\n"));
    }

    #[test]
    fn a_whole_last_line_missing_only_its_newline_is_kept() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.jsonl");
        drop(LogWriter::create(&path, &header(), Durability::Flush).unwrap());
        let mut bytes = std::fs::read(&path).unwrap();
        bytes.extend(serde_json::to_vec(&LogLine::Resume(resume())).unwrap());
        std::fs::write(&path, &bytes).unwrap();
        // The reader keeps it; the writer must agree and keep it too.
        assert_eq!(SessionLog::read(&path).unwrap().resumes.len(), 1);
        let (_, warning) = LogWriter::reopen(&path, Durability::Flush).unwrap();
        assert!(warning.is_none());
        bytes.push(b'\n');
        assert_eq!(std::fs::read(&path).unwrap(), bytes);
    }

    #[test]
    fn whole_lines_prefix() {
        assert_eq!(whole_lines_len(b""), 0);
        assert_eq!(whole_lines_len(b"abc"), 0);
        assert_eq!(whole_lines_len(b"a\nb"), 2);
        assert_eq!(whole_lines_len(b"a\nb\n"), 4);
    }
}
