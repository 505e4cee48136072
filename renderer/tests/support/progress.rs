//! A [`Progress`] that records what work tells it, for the tests of who reports what.

use renderer::progress::Progress;
use std::sync::Mutex;

/// What work reported: every start's total, every advance, the messages, whether it finished.
#[derive(Clone, Debug, Default)]
pub struct Seen {
    pub totals: Vec<u64>,
    pub advances: Vec<u64>,
    pub messages: Vec<String>,
    pub finished: bool,
}

/// Records what it is told, from any thread.
#[derive(Default)]
pub struct Recorder(Mutex<Seen>);

impl Recorder {
    pub fn seen(&self) -> Seen {
        self.0.lock().unwrap().clone()
    }
}

impl Progress for Recorder {
    fn start(&self, total: u64) {
        self.0.lock().unwrap().totals.push(total);
    }
    fn message(&self, text: &str) {
        self.0.lock().unwrap().messages.push(text.to_string());
    }
    fn advance(&self, n: u64) {
        self.0.lock().unwrap().advances.push(n);
    }
    fn finish(&self) {
        self.0.lock().unwrap().finished = true;
    }
}
