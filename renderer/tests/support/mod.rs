//! Helpers shared by the tests that run the `render` binary.

use std::path::Path;
use std::process::Command;

/// Run `render ARGS`, require success, return its standard output.
pub fn render(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_render"))
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "render {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// A path as a command-line argument.
pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}
