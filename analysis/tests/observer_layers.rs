//! The observer's layers point one way (issue 50): the model (`observer/model/`: display, CSF,
//! channels, bands, masking, pooling, the decision stages, d' to proportion correct) imports
//! nothing of the analysis outside itself: no statistics, no runs over stimulus sets
//! (`predict/`), no sessions. The data sets and their fits (`observer/datasets/`) import the
//! model and each other (Meese's absolute thresholds are at ModelFest's presentation), nothing
//! else of the analysis. Of the other crates each layer names only what it is listed with
//! below. This test reads the sources and fails, naming file, line and path, on any other
//! import. Test code (`#[cfg(test)]` items) is not read: a test may reach up to build what it
//! tests.

use std::path::{Path, PathBuf};

/// A layer: its folder under `src/`, the module paths (from the crate root) it may import,
/// and the other crates' modules it may name.
struct Layer {
    folder: &'static str,
    inside: &'static [&'static str],
    crates: &'static [&'static str],
}

const LAYERS: [Layer; 2] = [
    Layer {
        folder: "observer/model",
        inside: &["observer::model"],
        // The display's description (a design's `display` block), the standard normal and
        // the two-pair rule the simulated observers answer by, the counter-based hash of the
        // decision rules' simulations, and the one way enums are named.
        crates: &[
            "experiment::display",
            "experiment::predicted",
            "renderer::hash",
            "renderer::named",
        ],
    },
    Layer {
        folder: "observer/datasets",
        inside: &["observer::model", "observer::datasets"],
        // Long fits report how far they are.
        crates: &["renderer::progress"],
    },
];

#[test]
fn the_observer_imports_nothing_above_it() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut report = Vec::new();
    for layer in &LAYERS {
        let mut files = Vec::new();
        sources(&src.join(layer.folder), &mut files);
        assert!(
            files.len() >= 3,
            "{}: only {} files",
            layer.folder,
            files.len()
        );
        for file in &files {
            let rel = file
                .strip_prefix(&src)
                .unwrap()
                .to_str()
                .unwrap()
                .replace('\\', "/");
            let text = std::fs::read_to_string(file).unwrap();
            for (line, path) in imports(&rel, &text) {
                if !allowed(layer, &path) {
                    report.push(format!("src/{rel}:{line}: {path}"));
                }
            }
        }
    }
    assert!(
        report.is_empty(),
        "imports outside the observer's layers:\n{}",
        report.join("\n")
    );
}

/// The resolver itself, on the cases it must tell apart: a test that cannot fail would pass
/// on a resolver that finds nothing.
#[test]
fn the_resolver_finds_imports_outside_the_layer() {
    let text = "use super::bands::Fft2;\n\
                use super::super::super::super::jnd::Threshold;\n\
                use crate::observer::model::csf;\n\
                // use crate::predict::stimuli;\n\
                fn f() { crate::report::Report::x(); experiment::log::read(); }\n\
                #[cfg(test)]\nmod tests {\n    use crate::predict::x;\n}\n";
    let found: Vec<String> = imports("observer/model/video/linear.rs", text)
        .into_iter()
        .map(|(_, p)| p)
        .collect();
    assert_eq!(
        found,
        [
            "observer::model::video::bands",
            "jnd",
            "observer::model::csf",
            "report",
            "experiment::log::read",
        ]
    );
    let model = &LAYERS[0];
    let bad: Vec<&String> = found.iter().filter(|p| !allowed(model, p)).collect();
    assert_eq!(bad, ["jnd", "report", "experiment::log::read"]);
}

fn allowed(layer: &Layer, path: &str) -> bool {
    let under = |prefix: &str| path == prefix || path.starts_with(&format!("{prefix}::"));
    if path.starts_with("experiment::") || path.starts_with("renderer::") {
        return layer.crates.iter().any(|c| under(c));
    }
    layer.inside.iter().any(|c| under(c))
}

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The module path of a file under `src/`: `a/b.rs` and `a/b/mod.rs` are `a::b`.
fn module_of(file: &str) -> Vec<String> {
    let m = file.trim_end_matches(".rs").trim_end_matches("/mod");
    m.split('/').map(String::from).collect()
}

/// Every path a file's code names in the crate (`crate::`, `super::`, `self::`, resolved
/// from the crate root, up to the first name after the prefix) or in the workspace's other
/// crates (`experiment::x`, `renderer::x`), with its line; comments and `#[cfg(test)]` items
/// left out.
fn imports(file: &str, text: &str) -> Vec<(usize, String)> {
    let module = module_of(file);
    let mut out = Vec::new();
    for (i, code) in code_lines(text) {
        let bytes = code.as_bytes();
        let mut at = 0;
        while at < code.len() {
            let starts_word = at == 0 || !is_ident(bytes[at - 1] as char);
            let rest = &code[at..];
            let found = if !starts_word {
                None
            } else if let Some(r) = rest.strip_prefix("crate::") {
                Some((Vec::new(), r))
            } else if rest.starts_with("super::") || rest.starts_with("self::") {
                let mut m = module.clone();
                let mut r = rest;
                if let Some(s) = r.strip_prefix("self::") {
                    r = s;
                }
                while let Some(s) = r.strip_prefix("super::") {
                    m.pop();
                    r = s;
                }
                Some((m, r))
            } else {
                ["experiment::", "renderer::"]
                    .iter()
                    .find(|p| rest.starts_with(*p))
                    .map(|p| (vec![p.trim_end_matches("::").to_string()], &rest[p.len()..]))
            };
            let Some((mut path, r)) = found else {
                at += rest.chars().next().map_or(1, char::len_utf8);
                continue;
            };
            // Names up to the first that is not followed by `::` (the item itself) or a
            // group; at least one name after the prefix.
            let mut r = r;
            loop {
                let name: String = r.chars().take_while(|&c| is_ident(c)).collect();
                if name.is_empty() {
                    break;
                }
                path.push(name.clone());
                match r[name.len()..].strip_prefix("::") {
                    Some(next) if next.starts_with(|c: char| c.is_ascii_lowercase()) => r = next,
                    _ => break,
                }
            }
            out.push((i + 1, path.join("::")));
            at += rest.len() - r.len() + 1;
        }
    }
    out
}

fn is_ident(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// The lines of code: comments cut, `#[cfg(test)]` items (the attribute, the item's lines
/// and its closing brace) dropped.
fn code_lines(text: &str) -> Vec<(usize, &str)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        if lines[i].trim() == "#[cfg(test)]" {
            let mut depth = 0i32;
            let mut opened = false;
            i += 1;
            while i < lines.len() {
                let code = lines[i].split("//").next().unwrap_or("");
                depth += code.matches('{').count() as i32 - code.matches('}').count() as i32;
                opened |= code.contains('{');
                i += 1;
                if (opened && depth <= 0) || (!opened && code.trim_end().ends_with(';')) {
                    break;
                }
            }
            continue;
        }
        out.push((i, lines[i].split("//").next().unwrap_or("")));
        i += 1;
    }
    out
}
