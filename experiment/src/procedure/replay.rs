//! A procedure's state rebuilt from a log: the answers fed back in order, each logged trial
//! checked against the one the procedure would have presented.

use super::seam::Procedure;
use crate::log::TrialRecord;
use crate::trials::Trial;

/// What the procedure presented where each logged main trial stands.
#[derive(Clone, Debug, PartialEq)]
pub struct Replay {
    /// The procedure's trial at each record, in order, up to and including the first record
    /// that is not it (none there when the procedure had finished).
    pub expected: Vec<Trial>,
    /// Position (among the records given) of the first record that is not the procedure's
    /// trial; the procedure has taken the answers before it.
    pub mismatch: Option<usize>,
}

impl Replay {
    /// The records answered into the procedure.
    pub fn answered(&self) -> usize {
        self.mismatch.unwrap_or(self.expected.len())
    }
}

/// Feed `records` (main trials, in log order) to `procedure`, each checked against the trial
/// it would present; stops at the first that differs. The one replay of a log: the session
/// resuming it, `analyze`'s validation and its adaptive estimates.
pub fn replay<'a>(
    procedure: &mut dyn Procedure,
    records: impl IntoIterator<Item = &'a TrialRecord>,
) -> Replay {
    let mut expected = Vec::new();
    for (at, r) in records.into_iter().enumerate() {
        let Some(t) = procedure.current().cloned() else {
            return Replay {
                expected,
                mismatch: Some(at),
            };
        };
        let same = t.matches(r);
        expected.push(t);
        if !same {
            return Replay {
                expected,
                mismatch: Some(at),
            };
        }
        procedure.answer(r.correct);
    }
    Replay {
        expected,
        mismatch: None,
    }
}
