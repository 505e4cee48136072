//! CPU time of the calling thread, shared by the timing examples (included with `#[path]`).

use anyhow::{Context, Result};

/// CPU time of the calling thread, nanoseconds (first field of its schedstat).
pub fn thread_cpu_ns() -> Result<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat")
        .context("reading /proc/thread-self/schedstat (Linux only)")?;
    let first = text.split_whitespace().next().unwrap_or_default();
    first
        .parse()
        .with_context(|| format!("unexpected schedstat contents {text:?}"))
}
