//! The design file's `procedure` field: how the main trials' levels are chosen. Absent, it is
//! the thesis's method of constant stimuli (`levels` x `repeats`); the adaptive procedures pick
//! each trial's level from the design's `levels` (the rendered ones) given the earlier answers.
//! Defaults the thesis does not give are chosen here and written down in `docs/experiment.md`.
//! These are the field's types and the checks of its own values; they name no implementation
//! (`crate::procedure` reads them, and `crate::procedure::check` the checks that need one).

use anyhow::{Result, bail};
use serde::{Deserialize, Serialize};

/// Most trials one adaptive track may run.
pub const MAX_TRACK_TRIALS: u32 = 10_000;

/// How the main trials' levels are chosen.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(rename_all = "snake_case")]
pub enum ProcedureSpec {
    /// The thesis's method: every condition x level `repeats` times, shuffled.
    #[default]
    ConstantStimuli,
    /// QUEST+ (Watson 2017), one per condition.
    QuestPlus(QuestPlusSpec),
    /// Transformed or weighted up-down staircases, `interleaved` per condition.
    Staircase(StaircaseSpec),
}

impl ProcedureSpec {
    /// The name the design file gives the procedure.
    pub fn name(&self) -> &'static str {
        match self {
            ProcedureSpec::ConstantStimuli => "constant_stimuli",
            ProcedureSpec::QuestPlus(_) => "quest_plus",
            ProcedureSpec::Staircase(_) => "staircase",
        }
    }

    pub fn is_constant(&self) -> bool {
        *self == ProcedureSpec::ConstantStimuli
    }

    /// The adaptive tracks per condition (0 for constant stimuli).
    pub fn tracks_per_condition(&self) -> u32 {
        match self {
            ProcedureSpec::ConstantStimuli => 0,
            ProcedureSpec::QuestPlus(_) => 1,
            ProcedureSpec::Staircase(s) => s.interleaved,
        }
    }

    /// The most trials one track runs (0 for constant stimuli).
    pub fn trials_per_track(&self) -> u32 {
        match self {
            ProcedureSpec::ConstantStimuli => 0,
            ProcedureSpec::QuestPlus(q) => q.trials,
            ProcedureSpec::Staircase(s) => s.trials,
        }
    }

    /// Checks of the fields against the design's `levels`; the message names the field.
    pub fn validate(&self, levels: &[u32]) -> Result<()> {
        let trials = self.trials_per_track();
        if !self.is_constant() && !(1..=MAX_TRACK_TRIALS).contains(&trials) {
            bail!(
                "field `procedure.{}.trials` is {trials}; expected 1 to {MAX_TRACK_TRIALS} trials \
                 per track",
                self.name()
            );
        }
        match self {
            ProcedureSpec::ConstantStimuli => Ok(()),
            ProcedureSpec::QuestPlus(q) => q.validate(levels),
            ProcedureSpec::Staircase(s) => s.validate(),
        }
    }
}

/// QUEST+ over the rendered levels with the two-pair task's psychometric function (guess rate
/// 1/2; `experiment::psychometric::p_correct`, threshold at p = 0.75): the threshold and the slope
/// are estimated, the lapse rate is fixed.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct QuestPlusSpec {
    /// Most trials per condition.
    pub trials: u32,
    /// Stop a condition early once the 95% posterior interval of ln threshold is narrower than
    /// this (ln spp; 0.5 is a factor 1.65 between its ends). Absent: stop on `trials` only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stop_width: Option<f64>,
    /// The lapse rate of the model (fixed, not estimated).
    pub lapse: f64,
    /// Log-normal prior of the slope (per ln spp).
    pub slope: SlopePrior,
    /// The threshold's prior: flat in ln spp between these levels (spp), nothing outside.
    /// Absent: flat from one below ln(lowest level) to one above ln(highest level).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub threshold: Option<ThresholdRange>,
    /// What the placement of trials aims to learn.
    #[serde(skip_serializing_if = "QuestGoal::is_joint")]
    pub goal: QuestGoal,
}

/// The posterior whose expected entropy QUEST+ minimises when it places a trial (Watson 2017
/// lets the entropy be taken over any marginal: the parameters of interest, the others
/// nuisance).
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum QuestGoal {
    /// Threshold and slope together (the paper's default).
    #[default]
    Joint,
    /// The threshold's marginal only: the slope is a nuisance.
    Threshold,
}

impl QuestGoal {
    fn is_joint(&self) -> bool {
        *self == QuestGoal::Joint
    }
}

impl Default for QuestPlusSpec {
    fn default() -> Self {
        Self {
            trials: 32,
            stop_width: None,
            lapse: 0.02,
            slope: SlopePrior::default(),
            threshold: None,
            goal: QuestGoal::Joint,
        }
    }
}

impl QuestPlusSpec {
    fn validate(&self, levels: &[u32]) -> Result<()> {
        if !(0.0..0.25).contains(&self.lapse) {
            bail!(
                "field `procedure.quest_plus.lapse` is {}; expected 0 <= lapse < 0.25",
                renderer::limits::shortest(self.lapse)
            );
        }
        if let Some(w) = self.stop_width
            && !(w.is_finite() && w > 0.0)
        {
            bail!(
                "field `procedure.quest_plus.stop_width` is {}; expected a width > 0 in ln spp",
                renderer::limits::shortest(w)
            );
        }

        let s = &self.slope;
        if !(s.median.is_finite() && s.median > 0.0 && s.median <= 100.0) {
            bail!(
                "field `procedure.quest_plus.slope.median` is {}; expected 0 < slope <= 100",
                renderer::limits::shortest(s.median)
            );
        }
        if !(s.sd_ln.is_finite() && (0.0..=3.0).contains(&s.sd_ln)) {
            bail!(
                "field `procedure.quest_plus.slope.sd_ln` is {}; expected 0 to 3",
                renderer::limits::shortest(s.sd_ln)
            );
        }
        if let Some(t) = &self.threshold {
            t.validate(levels)?;
        }
        Ok(())
    }
}

/// A range of thresholds (spp), ends included.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ThresholdRange {
    pub lowest: f64,
    pub highest: f64,
}

impl ThresholdRange {
    /// The range must hold a point of the threshold grid, which spans the levels and a factor
    /// e beyond them ([`grid_range`]).
    fn validate(&self, levels: &[u32]) -> Result<()> {
        let (lo, hi) = (self.lowest, self.highest);
        let (grid_lo, grid_hi) = grid_range(levels);
        let (grid_lo, grid_hi) = (grid_lo.exp(), grid_hi.exp());
        if !(lo.is_finite() && hi.is_finite() && grid_lo <= lo && lo < hi && hi <= grid_hi) {
            bail!(
                "field `procedure.quest_plus.threshold` is {{\"lowest\": {lo}, \"highest\": \
                 {hi}}}; expected {grid_lo:.3} <= lowest < highest <= {grid_hi:.1} spp (the \
                 levels and a factor e beyond them)"
            );
        }
        Ok(())
    }
}

/// The ends (ln spp) of QUEST+'s threshold grid, and so of the prior when `threshold` is
/// absent: a factor e beyond the lowest and the highest level.
pub fn grid_range(levels: &[u32]) -> (f64, f64) {
    let lowest = levels.iter().min().copied().unwrap_or(1);
    let highest = levels.iter().max().copied().unwrap_or(1);
    ((lowest as f64).ln() - 1.0, (highest as f64).ln() + 1.0)
}

/// The slope's prior: ln slope normal with this median and standard deviation.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct SlopePrior {
    pub median: f64,
    pub sd_ln: f64,
}

impl Default for SlopePrior {
    fn default() -> Self {
        // The thesis observer's slope (scenes/thesis/observer.json), a factor e^0.5 either way.
        Self {
            median: 1.5,
            sd_ln: 0.5,
        }
    }
}

/// Up-down staircases over the levels' indices.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct StaircaseSpec {
    pub rule: StairRule,
    /// Staircases per condition, randomly interleaved with all others.
    pub interleaved: u32,
    /// Trials per staircase.
    pub trials: u32,
    /// Step towards the harder levels (more samples) in level indices; the step towards the
    /// easier ones follows from the rule.
    pub step: f64,
}

impl Default for StaircaseSpec {
    fn default() -> Self {
        Self {
            rule: StairRule::OneUpTwoDown,
            interleaved: 2,
            trials: 24,
            step: 1.0,
        }
    }
}

impl StaircaseSpec {
    fn validate(&self) -> Result<()> {
        if !(1..=16).contains(&self.interleaved) {
            bail!(
                "field `procedure.staircase.interleaved` is {}; expected 1 to 16 staircases per \
                 condition",
                self.interleaved
            );
        }
        if !(self.step.is_finite() && (0.05..=8.0).contains(&self.step)) {
            bail!(
                "field `procedure.staircase.step` is {}; expected 0.05 to 8 level indices",
                renderer::limits::shortest(self.step)
            );
        }
        if let StairRule::Weighted { target } = self.rule
            && !(target.is_finite() && 0.5 < target && target < 0.95)
        {
            bail!(
                "field `procedure.staircase.rule.weighted.target` is {}; expected a \
                 proportion correct between 0.5 and 0.95",
                renderer::limits::shortest(target)
            );
        }
        Ok(())
    }
}

/// When a staircase steps. "Up" is towards the easier, noisier levels (fewer samples).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
#[serde(rename_all = "snake_case")]
pub enum StairRule {
    /// Levitt (1971): one wrong answer steps up, two correct in a row step down (p = 0.707).
    OneUpTwoDown,
    /// Levitt (1971): one wrong up, three correct in a row down (p = 0.794).
    OneUpThreeDown,
    /// Kaernbach (1991): every answer steps, down `step` when correct, up
    /// `step` x target / (1 - target) when wrong (converges where p = target).
    Weighted { target: f64 },
}

impl StairRule {
    /// The proportion correct the staircase converges to.
    pub fn target(self) -> f64 {
        match self {
            StairRule::OneUpTwoDown => 0.5f64.sqrt(),
            StairRule::OneUpThreeDown => 0.5f64.powf(1.0 / 3.0),
            StairRule::Weighted { target } => target,
        }
    }
}
