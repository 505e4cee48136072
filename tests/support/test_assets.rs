//! Optional third-party test assets: real models and maps that nobody here made (public OBJ
//! models, EXR skies, the thesis's own `CedarCity.hdr`), which the project may not ship. The
//! tests that use them find them in the folder the `BLURLAB_TEST_ASSETS` setting names
//! (README.md, "Quick start") and skip, saying so, without it. Included by path from each test that
//! uses them, so the setting is read one way everywhere.

use std::path::PathBuf;

/// The environment variable naming the assets' folder.
pub const SETTING: &str = "BLURLAB_TEST_ASSETS";

/// The assets' folder, or `None` after saying why the caller skips.
pub fn folder() -> Option<PathBuf> {
    let Some(dir) = std::env::var_os(SETTING).map(PathBuf::from) else {
        eprintln!("skipped: {SETTING} is not set (optional third-party test assets; README.md)");
        return None;
    };
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!("skipped: {SETTING}={} is not a folder", dir.display());
        None
    }
}

/// The asset `name` in that folder, or `None` after saying why the caller skips.
#[allow(dead_code)] // not every test that includes this file uses one asset by name
pub fn asset(name: &str) -> Option<PathBuf> {
    let file = folder()?.join(name);
    if file.is_file() {
        Some(file)
    } else {
        eprintln!("skipped: no {} ({SETTING})", file.display());
        None
    }
}
