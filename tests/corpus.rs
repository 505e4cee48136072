//! The malformed-input corpus (`tests/corpus/`, issue 16): every file there is a bad input a
//! user could hand the suite, and `tests/corpus/expected.tsv` holds, for each, a phrase its
//! error message must contain. Each file goes to the reader that would meet it in practice
//! (its folder says which, see `tests/corpus/README.md`); the test fails when a file is
//! accepted, when a reader panics, when a message misses its phrase or does not name the file,
//! and when a file has no row in the table (so the corpus cannot grow unchecked).
//!
//! `CORPUS_PRINT=1 cargo test --test corpus -- --nocapture` prints every message, to write
//! the row of a new case.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

const CORPUS: &str = "tests/corpus";
/// Inputs the corpus's bad files refer to; not cases themselves.
const SUPPORT: &str = "valid";

/// The error the reader of `kind` gives for `path` (`None` when it accepts the file).
fn read(kind: &str, path: &Path) -> Option<String> {
    let message = |r: Result<(), anyhow::Error>| r.err().map(|e| format!("{e:#}"));
    match kind {
        "scene" | "scene_text" => message(renderer::scene::Scene::load(path).map(drop)),
        "job" | "job_text" => message(renderer::job::Job::load(path).map(drop)),
        "manifest" => message(renderer::manifest::Manifest::load(path).map(drop)),
        "obj" => renderer::geometry::TriangleMesh::from_obj(path)
            .err()
            .map(|e| e.to_string()),
        "envmap" => {
            message(renderer::environment::Environment::load(path, 1.0, 0.0, None).map(drop))
        }
        "design" => message(experiment::Design::load(path).map(drop)),
        "observer" => message(experiment::Observer::load(path).map(drop)),
        "predicted" => message(experiment::predicted::PredictedTable::load(path).map(drop)),
        "log" => message(experiment::log::SessionLog::read(path).map(drop)),
        "analyze" | "counts" => message(
            analysis::data::Dataset::read_checked(&[path.to_path_buf()], None, false).map(drop),
        ),
        "cli" => run_cli(path),
        other => panic!("{CORPUS}/{other}: a folder this test does not know; add its reader"),
    }
}

/// Run the `blurlab` command line written in `path` (`{tmp}` becomes a fresh folder); its
/// standard error, when it failed as a usage or input error should (exit 1 or 2).
fn run_cli(path: &Path) -> Option<String> {
    let tmp = tempfile::tempdir().unwrap();
    let line = std::fs::read_to_string(path).unwrap();
    let line = line
        .trim()
        .replace("{tmp}", &tmp.path().display().to_string());
    let out = Command::new(env!("CARGO_BIN_EXE_blurlab"))
        .args(line.split_whitespace())
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    match out.status.code() {
        Some(0) => None,
        Some(1 | 2) => Some(format!("{} {stderr}", path.display())),
        other => panic!(
            "{}: exit {other:?} (a panic or a signal): {stderr}",
            path.display()
        ),
    }
}

/// `expected.tsv`: case path (relative to the corpus) -> phrase.
fn expectations() -> BTreeMap<String, String> {
    let text = std::fs::read_to_string(Path::new(CORPUS).join("expected.tsv")).unwrap();
    let mut rows = BTreeMap::new();
    for (i, line) in text.lines().enumerate() {
        if line.starts_with('#') || line.trim().is_empty() {
            continue;
        }
        let (case, phrase) = line
            .split_once('\t')
            .unwrap_or_else(|| panic!("expected.tsv:{}: expected `case<TAB>phrase`", i + 1));
        assert!(
            rows.insert(case.to_string(), phrase.to_string()).is_none(),
            "expected.tsv:{}: {case} listed twice",
            i + 1
        );
    }
    rows
}

/// Every case: (kind, path), sorted.
fn cases() -> Vec<(String, PathBuf)> {
    let mut cases = Vec::new();
    for kind in std::fs::read_dir(CORPUS).unwrap() {
        let kind = kind.unwrap().path();
        let name = kind.file_name().unwrap().to_string_lossy().into_owned();
        if !kind.is_dir() || name == SUPPORT {
            continue;
        }
        for file in std::fs::read_dir(&kind).unwrap() {
            cases.push((name.clone(), file.unwrap().path()));
        }
    }
    cases.sort();
    cases
}

#[test]
fn every_bad_input_gets_its_message() {
    let expected = expectations();
    let print = std::env::var_os("CORPUS_PRINT").is_some();
    let mut failures = Vec::new();
    let all = cases();
    assert!(
        all.len() >= 60,
        "the corpus holds {} cases; issue 16 asks for at least 60",
        all.len()
    );
    for (kind, path) in &all {
        let case = path
            .strip_prefix(CORPUS)
            .unwrap()
            .to_string_lossy()
            .into_owned();
        let Some(message) = read(kind, path) else {
            failures.push(format!("{case}: accepted"));
            continue;
        };
        if print {
            println!("{case}\t{message}");
        }
        let file = path.file_name().unwrap().to_string_lossy();
        if !message.contains(&*file) {
            failures.push(format!(
                "{case}: the message does not name the file: {message}"
            ));
        }
        match expected.get(&case) {
            None => failures.push(format!(
                "{case}: no row in expected.tsv; message: {message}"
            )),
            Some(phrase) if !message.contains(phrase) => {
                failures.push(format!("{case}: expected {phrase:?} in: {message}"))
            }
            Some(_) => {}
        }
    }
    for case in expected.keys() {
        if !all.iter().any(|(_, p)| p.ends_with(case)) {
            failures.push(format!(
                "expected.tsv lists {case}, which is not in the corpus"
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
