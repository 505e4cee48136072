//! The renderer's layers point one way (issue 15): `job/` and `convert` over everything else.
//! Rendering one frame or one sequence (`render/`, `film`, `frame_io`, the scene, the tracer,
//! sampling, the environment map) never reaches into the batch layer. (The command line is
//! the `blurlab` binary's, outside this crate.) This test reads the sources and fails on such
//! an import.

use std::path::{Path, PathBuf};

/// Modules above the rest: they may import anything.
const UPPER: &[&str] = &["job", "convert.rs", "lib.rs"];

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

#[test]
fn lower_layers_do_not_import_the_job_layer() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    for entry in std::fs::read_dir(&src).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if UPPER.contains(&name.as_str()) {
            continue;
        }
        if path.is_dir() {
            sources(&path, &mut files);
        } else {
            files.push(path);
        }
    }
    assert!(files.len() > 40, "found only {} source files", files.len());
    let mut upward = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        for (i, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            if code.contains("crate::job") {
                upward.push(format!("{}:{}: {}", file.display(), i + 1, line.trim()));
            }
        }
    }
    assert!(upward.is_empty(), "upward imports:\n{}", upward.join("\n"));
}

/// The library reports through `progress` and never draws: `progress/mod.rs` uses std alone
/// (the crates that will not compile the tracer use it), and indicatif and a terminal binding
/// are named nowhere (the bar is the `blurlab` binary's, `src/cli/progress.rs`).
#[test]
fn progress_is_std_only_and_the_library_never_draws() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let core = std::fs::read_to_string(src.join("shared/progress/mod.rs")).unwrap();
    for line in core.lines() {
        let code = line.split("//").next().unwrap_or("").trim();
        assert!(
            !code.contains("crate::") && !code.contains("indicatif"),
            "progress/mod.rs: {line}"
        );
        if code.starts_with("use ") {
            assert!(code.starts_with("use std::"), "progress/mod.rs: {line}");
        }
    }
    let mut files = Vec::new();
    sources(&src, &mut files);
    let mut drawing = Vec::new();
    for file in &files {
        let rel = file.strip_prefix(&src).unwrap();
        let text = std::fs::read_to_string(file).unwrap();
        for (i, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            if code.contains("indicatif") || code.contains("terminal::") {
                drawing.push(format!("{}:{}: {}", rel.display(), i + 1, line.trim()));
            }
        }
    }
    assert!(
        drawing.is_empty(),
        "terminal bars in the library:\n{}",
        drawing.join("\n")
    );
}

/// The shared vocabulary (`src/shared/`: ids, conditions, manifest, limits, digests, ...)
/// imports nothing of the crate outside that folder: the experiment and the analysis build it
/// without the tracer, and the folder shows what every crate may lean on.
#[test]
fn the_shared_vocabulary_imports_nothing_of_the_tracer() {
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/shared");
    let members: Vec<String> = std::fs::read_dir(&shared)
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    assert!(members.contains(&"manifest".to_string()), "{members:?}");
    let mut files = Vec::new();
    sources(&shared, &mut files);
    let mut outside = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        for (i, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            for (at, _) in code.match_indices("crate::") {
                let name: String = code[at + 7..]
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if name != "shared" && !members.contains(&name) {
                    outside.push(format!("{}:{}: {}", file.display(), i + 1, line.trim()));
                }
            }
        }
    }
    assert!(
        outside.is_empty(),
        "imports from outside shared/:\n{}",
        outside.join("\n")
    );
}
