//! The procedure seam: what the session asks for its next main trial. A [`Procedure`] holds
//! one subject's state (the answers so far) and gives the trial to present now; the session
//! tells it each answer. Constant stimuli (`constant`, the thesis's planned list) is one
//! procedure; QUEST+ (`quest_plus`) and up-down staircases (`staircase`) are adaptive tracks
//! interleaved over the design's conditions (`interleave`).
//!
//! A procedure's state is a pure function of the design, the subject's seed and the answers in
//! order: [`replay`] rebuilds it from a log (resume, `analyze`'s validation), so a resumed
//! session presents the trial an uninterrupted one would have.

pub mod constant;
pub mod interleave;
pub mod quest_plus;
pub mod spec;
pub mod staircase;

use crate::design::Design;
use crate::log::TrialRecord;
use crate::trials::{self, Trial};
pub use spec::{
    ProcedureSpec, QuestPlusSpec, SlopePrior, StairRule, StaircaseSpec, ThresholdRange,
};

/// One subject's main trials, chosen as the answers come in.
pub trait Procedure: std::fmt::Debug + Send {
    /// The main trial to present now (its `index` is the number answered); `None` when done.
    fn current(&self) -> Option<&Trial>;
    /// The answer to [`Procedure::current`]: the procedure moves on.
    fn answer(&mut self, correct: bool);
    /// The trial after the current one when no answer to the current one can change it (what
    /// the app may load while the subject answers); `None` when it depends on the answer.
    fn after_current(&self) -> Option<Trial>;
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
    pub condition: trials::Condition,
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

/// A fresh procedure for `subject` under `design`.
pub fn start(design: &Design, subject: &str) -> Box<dyn Procedure> {
    let seed = design.subject_seed(subject);
    match &design.file.procedure {
        ProcedureSpec::ConstantStimuli => Box::new(constant::ConstantStimuli::new(
            trials::plan(design, subject).main,
        )),
        ProcedureSpec::QuestPlus(q) => Box::new(quest_plus::procedure(design, seed, q)),
        ProcedureSpec::Staircase(s) => Box::new(staircase::procedure(design, seed, s)),
    }
}

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

#[cfg(test)]
pub(crate) mod tests {
    use crate::design::Design;
    use crate::design::tests::SMALL;
    use std::path::Path;

    /// The small test design (2 scenes x 2 point sets x 1 time filter, levels 1, 8, 27) with
    /// `procedure` (JSON) and `levels`.
    pub(crate) fn adaptive(procedure: &str, levels: &[u32]) -> Design {
        let mut v: serde_json::Value = serde_json::from_str(SMALL).unwrap();
        v["procedure"] = serde_json::from_str(procedure).unwrap();
        v["levels"] = serde_json::json!(levels);
        Design::parse(Path::new("designs/adaptive.json"), &v.to_string()).unwrap()
    }

    #[test]
    fn an_adaptive_design_is_refused_with_the_field_named() {
        let mut v: serde_json::Value = serde_json::from_str(SMALL).unwrap();
        for (procedure, field) in [
            (
                r#"{"quest_plus": {"trials": 0}}"#,
                "procedure.quest_plus.trials",
            ),
            (
                r#"{"quest_plus": {"lapse": 0.3}}"#,
                "procedure.quest_plus.lapse",
            ),
            (
                r#"{"quest_plus": {"stop_width": -1}}"#,
                "procedure.quest_plus.stop_width",
            ),
            (
                r#"{"quest_plus": {"threshold": {"lowest": 27, "highest": 8}}}"#,
                "procedure.quest_plus.threshold",
            ),
            (
                r#"{"quest_plus": {"threshold": {"lowest": 0.1, "highest": 8}}}"#,
                "procedure.quest_plus.threshold",
            ),
            (
                r#"{"staircase": {"interleaved": 0}}"#,
                "procedure.staircase.interleaved",
            ),
            (
                r#"{"staircase": {"rule": {"weighted": {"target": 0.4}}}}"#,
                "procedure.staircase.rule.weighted.target",
            ),
        ] {
            v["procedure"] = serde_json::from_str(procedure).unwrap();
            let e = Design::parse(Path::new("d.json"), &v.to_string()).unwrap_err();
            assert!(format!("{e:#}").contains(field), "{procedure}: {e:#}");
        }
        v["procedure"] = serde_json::json!({"quest_plus": {"trial": 3}});
        let e = Design::parse(Path::new("d.json"), &v.to_string()).unwrap_err();
        assert!(format!("{e:#}").contains("trial"), "{e:#}");
    }

    #[test]
    fn main_trial_count_is_the_adaptive_most() {
        let d = adaptive(
            r#"{"staircase": {"interleaved": 3, "trials": 5}}"#,
            &[1, 8, 27],
        );
        assert_eq!(d.main_trial_count(), 4 * 3 * 5);
        let d = adaptive(r#"{"quest_plus": {"trials": 7}}"#, &[1, 8]);
        assert_eq!(d.main_trial_count(), 4 * 7);
    }
}
