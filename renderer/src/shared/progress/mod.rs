//! How long work says how far it is. The libraries of all three crates (rendering a frame, a
//! sequence or a job, display convergence, preflight, prediction, planning) report through
//! [`Progress`] and never draw anything themselves; the `blurlab` binary binds it to a terminal
//! bar (its `src/cli/progress.rs`), tests to a recorder, everything else to [`NoProgress`].
//!
//! This file depends on std only: the crates that will not compile the tracer still use it.

/// Where long work reports how far it is. Work counts in its own unit (samples, frames,
/// replications): [`Progress::start`] gives the total, [`Progress::advance`] what is done since
/// the last call; calls may come from several threads at once.
pub trait Progress: Sync {
    /// Work of `total` units begins (the count so far is 0).
    fn start(&self, total: u64);
    /// What is being done now, e.g. the frame being rendered.
    fn message(&self, text: &str);
    /// `n` more units are done.
    fn advance(&self, n: u64);
    /// The work is done.
    fn finish(&self);
}

/// Progress reported nowhere.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NoProgress;

impl Progress for NoProgress {
    fn start(&self, _total: u64) {}
    fn message(&self, _text: &str) {}
    fn advance(&self, _n: u64) {}
    fn finish(&self) {}
}
