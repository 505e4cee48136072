//! No module cycles (issue 41 item 3): in each crate, no two source files import each other,
//! directly or round a loop, and neither do two top-level modules (folders such as `accel/`,
//! or single files such as `camera.rs`).
//!
//! Read from the sources alone, so it runs on a fresh CI machine. Each file's paths
//! (`use crate::..`, `use super::..`, `use self::..`, a child module's `use child::..`, and
//! `crate::`/`super::` paths in code) are resolved to the file of the longest module prefix
//! they name: `a/b.rs` or `a/b/mod.rs` for module `a::b`. A name that file re-exports
//! (`pub use`) is followed to where it comes from. A `pub use` in `lib.rs`, `main.rs` or a
//! `mod.rs` is a folder's face, followed but not counted as an import of its own. A module's
//! imports from its own submodules are not counted either: they are its parts (`mod x;` and
//! `use x::Y`), which see its private items; the submodules' imports of it are. Comments,
//! literals and `#[cfg(test)]` items are not read: a test may reach up to build what it tests.

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::path::Path;

/// The crates' source folders, from the workspace root.
const CRATES: [&str; 4] = ["renderer/src", "experiment/src", "analysis/src", "src"];

/// Cycles allowed for now: (source folder, its members: files or top-level modules). A cycle
/// all of whose members are in one entry passes. None: keep it that way.
const KNOWN_CYCLES: &[(&str, &[&str])] = &[];

/// Arrows: from -> to -> the names that tie them.
type Graph = BTreeMap<String, BTreeMap<String, BTreeSet<String>>>;

#[test]
fn no_module_cycles() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut report = String::new();
    for dir in CRATES {
        let mut sources = Vec::new();
        read_sources(&root.join(dir), Path::new(""), &mut sources);
        let files = file_graph(&sources);
        let folders = folder_graph(&files);
        for graph in [&files, &folders] {
            for cycle in cycles(graph) {
                let known = KNOWN_CYCLES.iter().any(|(d, members)| {
                    *d == dir && cycle.iter().all(|n| members.contains(&n.as_str()))
                });
                if !known {
                    report += &format!("in {dir}:\n{}", describe(graph, &cycle));
                }
            }
        }
    }
    assert!(report.is_empty(), "module cycles:\n{report}");
}

/// Every `.rs` file under `dir`, as (path relative to the source folder, text).
fn read_sources(dir: &Path, rel: &Path, out: &mut Vec<(String, String)>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir.join(rel))
        .unwrap_or_else(|e| panic!("{}: {e}", dir.join(rel).display()))
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        let rel = rel.join(path.file_name().unwrap());
        if path.is_dir() {
            read_sources(dir, &rel, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let text = std::fs::read_to_string(&path).unwrap();
            out.push((rel.to_str().unwrap().replace('\\', "/"), text));
        }
    }
}

/// The module path of a file: `a/b.rs` and `a/b/mod.rs` are `a::b`; `lib.rs`, `main.rs` the root.
fn module_of(file: &str) -> Vec<String> {
    let file = file.trim_end_matches(".rs");
    let file = file.trim_end_matches("/mod");
    if matches!(file, "lib" | "main") {
        return Vec::new();
    }
    file.split('/').map(String::from).collect()
}

fn is_face(file: &str) -> bool {
    file == "lib.rs" || file == "main.rs" || file.ends_with("/mod.rs")
}

/// One file's `use` declarations (whether public, the paths they name) and other paths.
struct Paths {
    uses: Vec<(bool, Vec<String>)>,
    inline: Vec<Vec<String>>,
}

fn file_graph(sources: &[(String, String)]) -> Graph {
    let mut modules: BTreeMap<Vec<String>, String> = BTreeMap::new();
    for (file, _) in sources {
        // The library's root wins over the binary's for `crate::`.
        if file != "main.rs" || !modules.contains_key(&Vec::new()) {
            modules.insert(module_of(file), file.clone());
        }
    }
    let absolute = |file: &str, path: &[String]| -> Option<Vec<String>> {
        let here = module_of(file);
        let (mut abs, rest) = match path.first().map(String::as_str)? {
            "crate" => (Vec::new(), &path[1..]),
            "self" => (here, &path[1..]),
            "super" => (here, path),
            first => {
                let child = [here.clone(), vec![first.to_string()]].concat();
                modules.contains_key(&child).then_some((here, path))?
            }
        };
        let mut rest = rest;
        while rest.first().is_some_and(|s| s == "super") {
            abs.pop();
            rest = &rest[1..];
        }
        abs.extend(rest.iter().filter(|s| *s != "self").cloned());
        Some(abs)
    };
    let paths: BTreeMap<&str, Paths> = sources
        .iter()
        .map(|(f, text)| (f.as_str(), paths_of(&code_of(text))))
        .collect();
    // Re-exports: file -> name -> the absolute path it stands for.
    let mut aliases: BTreeMap<&str, BTreeMap<String, Vec<String>>> = BTreeMap::new();
    for (file, p) in &paths {
        for (_, path) in p.uses.iter().filter(|(public, _)| *public) {
            if let (Some(abs), Some(name)) = (absolute(file, path), path.last()) {
                aliases.entry(file).or_default().insert(name.clone(), abs);
            }
        }
    }
    // The file a path names, and the name it takes there, re-exports followed.
    let resolve = |path: Vec<String>| -> Option<(String, String)> {
        let mut path = path;
        for _ in 0..8 {
            let n = (0..=path.len())
                .rev()
                .find(|n| modules.contains_key(&path[..*n]))?;
            let file = &modules[&path[..n]];
            let name = path.get(n).or(path.last()).cloned().unwrap_or_default();
            match aliases.get(file.as_str()).and_then(|a| a.get(&name)) {
                Some(target) if n < path.len() && *target != path => path = target.clone(),
                _ => return Some((file.clone(), name)),
            }
        }
        None
    };
    let mut graph = Graph::new();
    for (file, p) in &paths {
        let uses = p
            .uses
            .iter()
            .filter(|(public, _)| !(*public && is_face(file)));
        let named = uses.map(|(_, path)| path).chain(&p.inline);
        let here = module_of(file);
        for (to, name) in named.filter_map(|path| resolve(absolute(file, path)?)) {
            if !module_of(&to).starts_with(&here) {
                let arrow = graph.entry(file.to_string()).or_default();
                arrow.entry(to).or_default().insert(name);
            }
        }
    }
    graph
}

/// The arrows between top-level modules (`accel` for `accel/world.rs`; a root file its own).
fn folder_graph(files: &Graph) -> Graph {
    let top = |f: &str| match f.split_once('/') {
        Some((folder, _)) => folder.to_string(),
        None => f.trim_end_matches(".rs").to_string(),
    };
    let mut graph = Graph::new();
    for (from, arrows) in files {
        for (to, names) in arrows {
            let (a, b) = (top(from), top(to));
            if a != b && !["lib", "main"].contains(&b.as_str()) {
                let tie = names.iter().map(|n| format!("{from} -> {to}: {n}"));
                graph
                    .entry(a)
                    .or_default()
                    .entry(b)
                    .or_default()
                    .extend(tie);
            }
        }
    }
    graph
}

/// The text with comments and string and character literals blanked (line breaks kept) and
/// `#[cfg(test)]` items dropped.
fn code_of(text: &str) -> String {
    let c: Vec<char> = text.chars().collect();
    let ident = |i: usize| c[i].is_alphanumeric() || c[i] == '_';
    let (mut out, mut i) = (String::new(), 0);
    // Moves from `from` to `to`, keeping the line breaks passed over.
    let skip = |out: &mut String, from: usize, to: usize| {
        out.extend(c[from..to.min(c.len())].iter().filter(|&&ch| ch == '\n'));
        to
    };
    while i < c.len() {
        let next = |k: usize| c.get(i + k).copied().unwrap_or(' ');
        let raw_hashes = (c[i] == 'r' && (i == 0 || !ident(i - 1) || c[i - 1] == 'b'))
            .then(|| (1..).take_while(|&k| next(k) == '#').count())
            .filter(|&h| next(h + 1) == '"');
        if c[i] == '/' && next(1) == '/' {
            i = (i..c.len()).find(|&k| c[k] == '\n').unwrap_or(c.len());
        } else if c[i] == '/' && next(1) == '*' {
            let mut depth = 0;
            let mut k = i;
            while k < c.len() {
                if c[k] == '/' && c.get(k + 1) == Some(&'*') {
                    (depth, k) = (depth + 1, k + 2);
                } else if c[k] == '*' && c.get(k + 1) == Some(&'/') {
                    (depth, k) = (depth - 1, k + 2);
                    if depth == 0 {
                        break;
                    }
                } else {
                    k += 1;
                }
            }
            i = skip(&mut out, i, k);
        } else if let Some(h) = raw_hashes {
            let close: String = std::iter::once('"').chain("#".repeat(h).chars()).collect();
            let body: String = c[i + h + 2..].iter().collect();
            let len = body
                .find(&close)
                .map_or(body.len(), |k| body[..k].chars().count());
            out.push_str("\"\"");
            i = skip(&mut out, i, i + h + 2 + len + 1 + h);
        } else if c[i] == '"' {
            let mut k = i + 1;
            while k < c.len() && c[k] != '"' {
                k += if c[k] == '\\' { 2 } else { 1 };
            }
            out.push_str("\"\"");
            i = skip(&mut out, i, k + 1);
        } else if c[i] == '\'' && next(1) == '\\' {
            // `'\''`, `'\n'`, `'\u{7f}'`: the escaped character is at i + 2.
            let end = (i + 3..c.len()).find(|&k| c[k] == '\'').unwrap_or(c.len());
            i = end + 1;
        } else if c[i] == '\'' && next(2) == '\'' {
            i += 3;
        } else {
            out.push(c[i]);
            i += 1;
        }
    }
    drop_test_items(&out)
}

/// Drops each `#[cfg(test)]` item: its first line, the deeper lines under it and its closing
/// lines at its own indentation (the sources are rustfmt's, so indentation shows nesting).
fn drop_test_items(code: &str) -> String {
    let lines: Vec<&str> = code.lines().collect();
    let indent = |l: &str| l.len() - l.trim_start().len();
    let ends = |l: &str| l.trim_end().ends_with([';', ',', '}']);
    let (mut kept, mut i) = (Vec::new(), 0);
    while i < lines.len() {
        if lines[i].trim() != "#[cfg(test)]" {
            kept.push(lines[i]);
            i += 1;
            continue;
        }
        let k = indent(lines[i]);
        i += 1;
        while i < lines.len() && lines[i].trim_start().starts_with("#[") {
            i += 1;
        }
        let mut open = i < lines.len() && !ends(lines[i]);
        i += 1;
        while open {
            while i < lines.len() && (lines[i].trim().is_empty() || indent(lines[i]) > k) {
                i += 1;
            }
            let closing = ['}', ')', ']', '{'];
            open = i < lines.len()
                && indent(lines[i]) == k
                && (lines[i].trim_start().starts_with(closing) || lines[i].trim() == "where");
            if open {
                open = !ends(lines[i]);
                i += 1;
            }
        }
    }
    kept.join("\n")
}

/// The `use` declarations of `code` (each a list of paths) and the `crate::`, `super::` and
/// `self::` paths in the rest of it.
fn paths_of(code: &str) -> Paths {
    let mut p = Paths {
        uses: Vec::new(),
        inline: Vec::new(),
    };
    let mut rest = String::new();
    let mut lines = code.lines();
    while let Some(line) = lines.next() {
        let t = line.trim_start();
        let public = t.starts_with("pub");
        let after_vis = if public {
            t.strip_prefix("pub")
                .map(|s| {
                    s.strip_prefix('(')
                        .map_or(s, |s| &s[s.find(')').unwrap() + 1..])
                })
                .unwrap()
                .trim_start()
        } else {
            t
        };
        let Some(tree) = after_vis.strip_prefix("use ") else {
            rest += line;
            rest.push('\n');
            continue;
        };
        let mut tree = tree.to_string();
        while !tree.contains(';') {
            tree += lines.next().unwrap_or(";");
        }
        let tree: String = tree[..tree.find(';').unwrap()]
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ");
        for path in expand(&tree) {
            p.uses.push((public, path));
        }
    }
    let c: Vec<char> = rest.chars().collect();
    let ident = |k: usize| k < c.len() && (c[k].is_alphanumeric() || c[k] == '_');
    for start in ["crate::", "super::", "self::"] {
        for (at, _) in rest.match_indices(start) {
            let at = rest[..at].chars().count();
            if at > 0 && (ident(at - 1) || c[at - 1] == '$' || c[at - 1] == ':') {
                continue;
            }
            let (mut path, mut k) = (Vec::new(), at);
            loop {
                let end = (k..=c.len()).find(|&e| !ident(e)).unwrap();
                path.push(c[k..end].iter().collect::<String>());
                if c.get(end..end + 2) == Some(&[':', ':']) && ident(end + 2) {
                    k = end + 2;
                } else {
                    break;
                }
            }
            p.inline.push(path);
        }
    }
    p
}

/// The paths of a use tree: `a::{b, c::{d as e, *}}` is `a::b`, `a::c::e`... (a renamed
/// import keeps its source name's path; `*` names the module).
fn expand(tree: &str) -> Vec<Vec<String>> {
    let tree = tree.trim();
    let Some(open) = tree.find('{') else {
        let name = tree.split(" as ").next().unwrap().trim();
        let segs = name.split("::").map(|s| s.trim().to_string());
        return vec![segs.filter(|s| !s.is_empty() && s != "*").collect()];
    };
    let head: Vec<String> = tree[..open]
        .split("::")
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .collect();
    let inner = &tree[open + 1..tree.rfind('}').unwrap()];
    let (mut parts, mut depth, mut from) = (Vec::new(), 0, 0);
    for (i, ch) in inner.char_indices() {
        match ch {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&inner[from..i]);
                from = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&inner[from..]);
    let parts = parts.into_iter().filter(|s| !s.trim().is_empty());
    parts
        .flat_map(expand)
        .map(|tail| [head.clone(), tail].concat())
        .collect()
}

/// The graph's strongly connected parts of two or more nodes (Tarjan), each sorted.
fn cycles(graph: &Graph) -> Vec<Vec<String>> {
    struct Walk<'a> {
        graph: &'a Graph,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        found: Vec<Vec<String>>,
    }
    fn visit<'a>(w: &mut Walk<'a>, v: &'a str) {
        let i = w.index.len();
        w.index.insert(v, i);
        w.low.insert(v, i);
        w.stack.push(v);
        for to in w.graph.get(v).into_iter().flat_map(|a| a.keys()) {
            if !w.index.contains_key(to.as_str()) {
                visit(w, to);
                w.low.insert(v, w.low[v].min(w.low[to.as_str()]));
            } else if w.stack.contains(&to.as_str()) {
                w.low.insert(v, w.low[v].min(w.index[to.as_str()]));
            }
        }
        if w.low[v] == w.index[v] {
            let at = w.stack.iter().rposition(|&n| n == v).unwrap();
            let mut part: Vec<String> = w.stack.drain(at..).map(String::from).collect();
            if part.len() > 1 {
                part.sort();
                w.found.push(part);
            }
        }
    }
    let mut w = Walk {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        found: Vec::new(),
    };
    for v in graph.keys() {
        if !w.index.contains_key(v.as_str()) {
            visit(&mut w, v);
        }
    }
    w.found
}

/// A shortest loop through the part's first node (`a.rs -> b.rs -> a.rs`), then every arrow
/// inside the part with the names that tie it.
fn describe(graph: &Graph, part: &[String]) -> String {
    let inside = |n: &String| part.contains(n);
    let start = &part[0];
    let mut came_from: BTreeMap<&String, &String> = BTreeMap::new();
    let mut queue = VecDeque::from([start]);
    'search: while let Some(v) = queue.pop_front() {
        for to in graph[v].keys().filter(|n| inside(n)) {
            if to == start {
                came_from.insert(start, v);
                break 'search;
            }
            if !came_from.contains_key(to) {
                came_from.insert(to, v);
                queue.push_back(to);
            }
        }
    }
    let mut path = vec![start.clone()];
    let mut v = came_from[start];
    while v != start {
        path.push(v.clone());
        v = came_from[v];
    }
    path.push(start.clone());
    path.reverse();
    let mut text = format!("  {}\n", path.join(" -> "));
    for from in part {
        for (to, names) in graph[from].iter().filter(|(n, _)| inside(n)) {
            let names: Vec<_> = names.iter().map(String::as_str).collect();
            text += &format!("    {from} -> {to}: {}\n", names.join(", "));
        }
    }
    text
}

fn sources(files: &[(&str, &str)]) -> Vec<(String, String)> {
    files
        .iter()
        .map(|(f, t)| (f.to_string(), t.to_string()))
        .collect()
}

#[test]
fn a_loop_of_imports_is_found_and_named() {
    let files = file_graph(&sources(&[
        ("lib.rs", "pub mod a;\npub mod b;\n"),
        ("a.rs", "use crate::b::{B, helper};\npub struct A;\n"),
        ("b/mod.rs", "mod inner;\npub use inner::B;\n"),
        ("b/inner.rs", "pub struct B(crate::a::A);\n"),
    ]));
    assert_eq!(cycles(&files), [["a.rs", "b/inner.rs"]]);
    let text = describe(&files, &cycles(&files)[0]);
    assert!(text.starts_with("  a.rs -> b/inner.rs -> a.rs\n"), "{text}");
    assert!(text.contains("b/inner.rs -> a.rs: A"), "{text}");
    assert!(text.contains("a.rs -> b/inner.rs: B"), "{text}");
    assert!(files["a.rs"]["b/mod.rs"].contains("helper"), "{files:?}");
    assert_eq!(cycles(&folder_graph(&files)), [["a", "b"]]);
}

#[test]
fn one_way_imports_parts_tests_and_comments_pass() {
    let files = file_graph(&sources(&[
        ("lib.rs", "pub mod a;\npub mod b;\n"),
        (
            "a.rs",
            "use super::b::B; // crate::b\n/// [`crate::b`]\npub struct A(B);\n\
             #[cfg(test)]\nmod tests {\n    use crate::b::tests;\n}\n",
        ),
        (
            "b/mod.rs",
            "mod c;\nuse c::C;\npub struct B(C);\nconst S: &str = \"crate::a::A\";\n\
             const Q: [char; 2] = ['\\'', '\"'];\nconst R: &str = r#\"crate::a\"#;\n\
             #[cfg(test)]\nfn check(\n    a: crate::a::A,\n) -> u32 {\n    0\n}\n",
        ),
        ("b/c.rs", "pub struct C(Option<Box<super::B>>);\n"),
    ]));
    assert!(cycles(&files).is_empty(), "{files:?}");
    assert_eq!(files["a.rs"].keys().collect::<Vec<_>>(), ["b/mod.rs"]);
    assert_eq!(files["b/c.rs"].keys().collect::<Vec<_>>(), ["b/mod.rs"]);
    assert!(!files.contains_key("b/mod.rs"), "{files:?}");
}
