//! The procedure seam: what the session asks for its next main trial. A [`Procedure`] holds
//! one subject's state (the answers so far) and gives the trial to present now; the session
//! tells it each answer.

use crate::trials::{Condition, Trial};

/// One subject's main trials, chosen as the answers come in.
pub trait Procedure: std::fmt::Debug + Send {
    /// The main trial to present now (its `index` is the number answered); `None` when done.
    fn current(&self) -> Option<&Trial>;
    /// The answer to [`Procedure::current`]: the procedure moves on.
    fn answer(&mut self, correct: bool);
    /// The trial after the current one when no answer to the current one can change it (what
    /// the app may load while the subject answers); `None` when it depends on the answer.
    fn after_current(&self) -> Option<Trial>;
    /// Up to `n` trials after the current one that no answer can change (what a browser may
    /// fetch ahead); by default only [`Procedure::after_current`].
    fn ahead(&self, n: usize) -> Vec<Trial> {
        self.after_current().into_iter().take(n).collect()
    }
    /// The most main trials the procedure can present (the log header's `trials_planned`).
    fn planned(&self) -> u32;
    /// Main trials answered.
    fn done(&self) -> u32;
    /// Each track's estimate so far (adaptive procedures; empty for constant stimuli).
    fn estimates(&self) -> Vec<TrackEstimate> {
        Vec::new()
    }
}

/// What an adaptive track concludes about its condition's threshold.
#[derive(Clone, Debug, PartialEq)]
pub struct TrackEstimate {
    pub condition: Condition,
    /// The track within its condition (0 for QUEST+).
    pub track: u32,
    pub trials: u32,
    /// The threshold in spp (QUEST+: posterior mean of ln threshold, exponentiated, at
    /// p = 0.75; staircases: the geometric mean of the reversal levels, at the rule's target).
    pub threshold: f64,
    /// 95% posterior interval of the threshold in spp (QUEST+ only).
    pub interval: Option<(f64, f64)>,
    /// Posterior mean slope per ln spp (QUEST+ only).
    pub slope: Option<f64>,
    /// The proportion correct `threshold` refers to.
    pub target: f64,
}
