//! Which decision stage a prediction runs, and why: the design's layout says how a subject sees
//! each pair, and that says what the observer can compare. Videos side by side (the thesis's
//! sequential layout: one pair, a gap, the other pair; or the grid: all four at once) cannot be
//! subtracted place by place, so the observer compares how noisy each looks
//! ([`DecisionStage::SideBySide`]); a test shown in place of its reference (an overlay or
//! flicker layout, none in the suite yet) can be subtracted ([`DecisionStage::Difference`]).
//! `--decision` overrides the layout.
//!
//! The side-by-side stage reduces to detection against a blank field (ModelFest 0.995 dB with
//! the difference stage's fit, under the standard observer's 1.13), fits Meese et al.'s
//! cross-orientation masking better (4.03 dB against 6.83) and puts the thesis's frame 93
//! within 1.0-1.9x of the thesis's JNDs where `difference` is 3-9x off (`docs/predict.md`,
//! `docs/replication.md` section 4, BENCHMARKS.md).

use crate::observer::model::decision_stage::DecisionStage;
use experiment::design::Layout;

/// The stage run and the reason, as the report states it.
#[derive(Clone, Debug, PartialEq)]
pub struct StageChoice {
    pub stage: DecisionStage,
    pub reason: String,
}

impl StageChoice {
    /// The stage for a design's layout (`None`: no design, the thesis's trials).
    pub fn for_layout(layout: Option<Layout>) -> Self {
        let reason = match layout {
            Some(Layout::Sequential) => {
                "the design's layout is sequential: each pair's two videos side by side, \
                 the pairs one after the other"
            }
            Some(Layout::Grid) => "the design's layout is a grid: all four videos side by side",
            None => "no design: the thesis's trials, each pair's two videos side by side",
        };
        Self {
            stage: DecisionStage::SideBySide,
            reason: format!(
                "{reason}: the observer cannot subtract one video from the other place by \
                 place, so it compares how noisy each looks (the side-by-side stage, \
                 docs/predict.md; --decision difference runs the subtracting one)"
            ),
        }
    }

    /// The stage the command line asked for.
    pub fn given(stage: DecisionStage) -> Self {
        Self {
            stage,
            reason: "chosen with --decision, over the design's layout".into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn side_by_side_layouts_run_the_side_by_side_stage() {
        for l in [Some(Layout::Sequential), Some(Layout::Grid), None] {
            let s = StageChoice::for_layout(l);
            assert_eq!(s.stage, DecisionStage::SideBySide, "{l:?}");
            assert!(s.reason.contains("side by side"), "{}", s.reason);
            assert_eq!(s.stage.name(), "side-by-side");
        }
        let given = StageChoice::given(DecisionStage::Difference);
        assert_eq!(given.stage.name(), "difference");
        assert!(given.reason.contains("--decision"));
    }
}
