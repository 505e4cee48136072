//! The repository stands alone: a user's clone has nothing beside it, so no tracked file
//! (outside `.ci/`, which may use what CI lays beside the clone) names a path outside the
//! repository or a development machine's absolute path; no generated file is tracked; and every
//! repository file that a document or a comment cites exists.

use std::path::Path;
use std::process::Command;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// The tracked files (`git ls-files`), or `None` after saying why the caller skips.
fn tracked() -> Option<Vec<String>> {
    let out = Command::new("git")
        .args(["ls-files", "-z"])
        .current_dir(ROOT)
        .output();
    match out {
        Ok(o) if o.status.success() => Some(
            String::from_utf8_lossy(&o.stdout)
                .split('\0')
                .filter(|f| !f.is_empty())
                .map(str::to_string)
                .collect(),
        ),
        _ => {
            eprintln!("skipped: {ROOT} is not a git checkout (or git is missing)");
            None
        }
    }
}

/// Tracked text files outside `.ci/`, with their text (files that are not UTF-8 are left out).
fn texts(files: &[String]) -> Vec<(&str, String)> {
    files
        .iter()
        .filter(|f| !f.starts_with(".ci/"))
        .filter_map(|f| {
            Some((
                f.as_str(),
                std::fs::read_to_string(Path::new(ROOT).join(f)).ok()?,
            ))
        })
        .collect()
}

/// What in `line` points outside the repository: the sibling `shared` folder of the machines
/// the project is developed on, or an absolute path under `/work`, `/root` or `/home` (at a
/// line's start or after a space, a backtick, `(`, `=` or a quote).
fn outside_path(line: &str) -> Option<&'static str> {
    let sibling = ["..", "shared"].join("/");
    if line.contains(&sibling) {
        return Some("the sibling folder `shared`");
    }
    for top in ["work", "root", "home"] {
        let needle = format!("/{top}/");
        let mut from = 0;
        while let Some(i) = line[from..].find(&needle) {
            let at = from + i;
            if at == 0 || line[..at].ends_with([' ', '`', '(', '=', '"']) {
                return Some("a development machine's absolute path");
            }
            from = at + 1;
        }
    }
    None
}

#[test]
fn no_tracked_file_points_outside_the_repository() {
    let Some(files) = tracked() else { return };
    let mut found = Vec::new();
    for (file, text) in texts(&files) {
        for (n, line) in text.lines().enumerate() {
            if let Some(what) = outside_path(line) {
                found.push(format!("{file}:{}: {what}: {line}", n + 1));
            }
        }
    }
    assert!(
        found.is_empty(),
        "state the fact in the project's docs, or name a setting (as BLURLAB_TEST_ASSETS):\n{}",
        found.join("\n")
    );
}

#[test]
fn the_outside_path_check_can_fail() {
    let sibling = ["..", "shared", "notes", "x.md"].join("/");
    let (work, home) = (format!("/{}/x", "work"), format!("a (/{}/u/y)", "home"));
    for bad in [format!("see `{sibling}`"), work, home] {
        assert!(outside_path(&bad).is_some(), "{bad}");
    }
    for good in [
        "/tmp/plane",
        "stimuli/work/x",
        "docs/home/",
        "--out /tmp/root/x",
    ] {
        assert_eq!(outside_path(good), None, "{good}");
    }
}

/// Generated files: Python's bytecode caches.
fn generated(file: &str) -> bool {
    file.ends_with(".pyc") || file.ends_with(".pyo") || file.contains("__pycache__/")
}

#[test]
fn no_generated_file_is_tracked() {
    let Some(files) = tracked() else { return };
    let found: Vec<&String> = files.iter().filter(|f| generated(f)).collect();
    assert!(
        found.is_empty(),
        "generated files are tracked: {found:?} (`git rm --cached`)"
    );
    assert!(generated(
        "bench/peers/__pycache__/scramble.cpython-311.pyc"
    ));
}

/// The repository paths that `line` cites: words starting with one of `tops` (the tracked
/// top-level folders that hold sources) or naming a Markdown file in capitals (as the README),
/// without placeholders (`<job>`, `{a,b}`, `*`, `$VAR`, `...`), cut at a `:` (a line number).
fn citations<'a>(line: &'a str, tops: &[String]) -> Vec<&'a str> {
    let is_cut = |c: char| c.is_whitespace() || "`'\"()[]<>,;|=".contains(c);
    line.split(is_cut)
        .map(|w| w.split(':').next().unwrap_or(w))
        .map(|w| w.trim_end_matches(['.', '!', '?', '/']))
        .filter(|w| {
            let in_top = tops
                .iter()
                .any(|t| w.len() > t.len() && w.starts_with(t.as_str()));
            let doc = w.ends_with(".md")
                && !w.contains('/')
                && w.chars().next().is_some_and(|c| c.is_ascii_uppercase());
            (in_top || doc) && !w.contains(['{', '}', '*', '$', '\\']) && !w.contains("..")
        })
        .collect()
}

/// Whether `cited` names a file or folder: from the repository's root, from the citing file's
/// folder or one above it, or from a workspace member's root (a crate's tests, cited by name
/// from its document in docs/).
fn exists(cited: &str, citing: &str) -> bool {
    let root = Path::new(ROOT);
    let mut bases = vec![root.to_path_buf()];
    bases.extend(["renderer", "experiment", "analysis"].map(|m| root.join(m)));
    let mut dir = Path::new(citing).parent();
    while let Some(d) = dir {
        bases.push(root.join(d));
        dir = d.parent();
    }
    bases.iter().any(|b| b.join(cited).exists())
}

/// Lines that cite files: every line of a document, the comment lines of code.
fn citing_lines(file: &str, text: &str) -> Vec<(usize, String)> {
    let comment = if file.ends_with(".rs") {
        Some("//")
    } else if [".sh", ".py", ".toml", ".txt"]
        .iter()
        .any(|e| file.ends_with(e))
    {
        Some("#")
    } else {
        None
    };
    text.lines()
        .enumerate()
        .filter(|(_, l)| {
            file.ends_with(".md") || comment.is_some_and(|c| l.trim_start().starts_with(c))
        })
        .map(|(n, l)| (n + 1, l.to_string()))
        .collect()
}

#[test]
fn every_cited_file_exists() {
    let Some(files) = tracked() else { return };
    // Top-level folders of sources; `stimuli/` and `results/` hold what the suite writes.
    let mut tops: Vec<String> = files
        .iter()
        .filter_map(|f| f.split_once('/').map(|(top, _)| format!("{top}/")))
        .filter(|t| t != "stimuli/")
        .collect();
    tops.sort();
    tops.dedup();
    let mut missing = Vec::new();
    for (file, text) in texts(&files) {
        for (n, line) in citing_lines(file, &text) {
            for cited in citations(&line, &tops) {
                if !exists(cited, file) {
                    missing.push(format!("{file}:{n}: {cited}"));
                }
            }
        }
    }
    assert!(
        missing.is_empty(),
        "cited and missing (say what is needed instead, or fix the path):\n{}",
        missing.join("\n")
    );
}

#[test]
fn the_citation_check_can_fail() {
    let tops = vec!["docs/".to_string(), "scenes/".to_string()];
    let line = "see DESIGN.md and `docs/nowhere.md`, docs/limits.md:12 or scenes/<job>/x.json";
    assert_eq!(
        citations(line, &tops),
        ["DESIGN.md", "docs/nowhere.md", "docs/limits.md"]
    );
    assert!(!exists("DESIGN.md", "docs/ARCHITECTURE.md"));
    assert!(!exists("docs/nowhere.md", "README.md"));
    assert!(exists("docs/limits.md", "README.md"));
    assert!(
        exists("tests/layers.rs", "docs/ARCHITECTURE.md"),
        "a member's tests/"
    );
}
