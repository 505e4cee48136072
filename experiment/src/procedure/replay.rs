//! A procedure's state rebuilt from a log: the answers fed back in order, each logged trial
//! checked against the one the procedure would have presented.

use super::seam::Procedure;
use crate::log::TrialRecord;
use crate::trials::Trial;

/// A logged main trial that is not the one the procedure put there.
#[derive(Clone, Debug, PartialEq)]
pub struct Mismatch {
    /// Position among the main records given to [`replay`].
    pub at: usize,
    /// What the procedure would have presented there (`None`: it had finished).
    pub expected: Option<Trial>,
}

/// Feed `records` (main trials, in log order) to `procedure`, each checked against the trial
/// it would present; stops at the first that differs.
pub fn replay<'a>(
    procedure: &mut dyn Procedure,
    records: impl IntoIterator<Item = &'a TrialRecord>,
) -> Result<(), Mismatch> {
    for (at, r) in records.into_iter().enumerate() {
        match procedure.current() {
            Some(t) if t.matches(r) => procedure.answer(r.correct),
            other => {
                return Err(Mismatch {
                    at,
                    expected: other.cloned(),
                });
            }
        }
    }
    Ok(())
}
