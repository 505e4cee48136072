//! Progress bars of the long-running commands (`predict`, `plan`) on stderr.

use indicatif::{ProgressBar, ProgressStyle};

/// A bar of `total` steps, or a hidden one.
pub fn bar(total: u64, what: &str, show: bool) -> ProgressBar {
    if !show {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(total);
    if let Ok(style) = ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} ({eta} left)") {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_message(what.to_string());
    bar
}
