//! The procedure seam: what the session asks for its next main trial. A [`Procedure`]
//! (`seam`) holds one subject's state (the answers so far) and gives the trial to present now;
//! the session tells it each answer. Constant stimuli (`constant`, the thesis's planned list)
//! is one procedure; QUEST+ (`quest_plus`) and up-down staircases (`staircase`) are adaptive
//! tracks interleaved over the design's conditions (`interleave`). [`start`] makes the one a
//! design's `procedure` field names (`crate::design::procedure`, which names no
//! implementation).
//!
//! A procedure's state is a pure function of the design, the subject's seed and the answers in
//! order: [`replay`] rebuilds it from a log (resume, `analyze`'s validation), so a resumed
//! session presents the trial an uninterrupted one would have.

pub mod catch;
pub mod constant;
pub mod interleave;
pub mod quest_plus;
pub mod replay;
pub mod seam;
pub mod staircase;
pub mod start;

pub use replay::{Replay, replay};
pub use seam::{Procedure, TrackEstimate};
pub use start::{check, start};

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
