//! Lexical path arithmetic (no file system access, so it works on paths that do not exist yet
//! and keeps messages readable): `a/./b/../c` -> `a/c`, and one path relative to a folder.

use std::path::{Component, Path, PathBuf};

/// `a/b/../c` -> `a/c` without touching the file system (a leading `..` is kept).
pub fn lexical_normal(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir
                if matches!(out.components().next_back(), Some(Component::Normal(_))) =>
            {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// `target` relative to the folder `base` (both absolute and lexically normal).
pub fn relative(target: &Path, base: &Path) -> PathBuf {
    let t: Vec<Component> = target.components().collect();
    let b: Vec<Component> = base.components().collect();
    let common = t.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut out = PathBuf::new();
    for _ in common..b.len() {
        out.push("..");
    }
    for c in &t[common..] {
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_and_relative_paths() {
        assert_eq!(lexical_normal(Path::new("/a/./b/../c")), Path::new("/a/c"));
        assert_eq!(
            lexical_normal(Path::new("../a/./b/../../c")),
            Path::new("../c")
        );
        let r = |t: &str, b: &str| relative(Path::new(t), Path::new(b));
        assert_eq!(r("/a/b/m.obj", "/a/c"), Path::new("../b/m.obj"));
        assert_eq!(r("/a/b/m.obj", "/a"), Path::new("b/m.obj"));
        assert_eq!(r("/a/b", "/a/b"), Path::new(""));
    }
}
