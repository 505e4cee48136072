//! Fixtures shared by the session tests (`mod support;` in each): a design and an observer
//! parsed from text, a log path in a temporary folder, and a simulated session started on it.

use experiment::log::writer::Durability;
use experiment::session::{Session, StartInfo};
use experiment::{Design, Observer};
use std::path::{Path, PathBuf};

pub struct Fixture {
    _dir: tempfile::TempDir,
    pub design: Design,
    pub observer: Observer,
    /// Subject s01's log (not written yet).
    pub path: PathBuf,
}

/// The design `design` (written as design.json, so it resolves like a real one) and the
/// observer `observer`.
pub fn fixture(design: &str, observer: &str) -> Fixture {
    let dir = tempfile::tempdir().unwrap();
    let design_path = dir.path().join("design.json");
    std::fs::write(&design_path, design).unwrap();
    Fixture {
        design: Design::load(&design_path).unwrap(),
        observer: Observer::parse(Path::new("o.json"), observer).unwrap(),
        path: dir.path().join("s01.jsonl"),
        _dir: dir,
    }
}

/// A simulated session's start (time 0, so logs are reproducible).
pub fn info() -> StartInfo {
    StartInfo {
        mode: "simulated".into(),
        display: None,
        observer: None,
        started_unix: 0.0,
    }
}

/// Subject s01's session over `design` with its log at `path`, opened and started.
pub fn start(design: &Design, path: &Path, durability: Durability) -> Session {
    let mut s = Session::open(design, "s01", path, durability).unwrap();
    s.start(info()).unwrap();
    s
}
