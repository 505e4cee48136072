//! Up-down staircases over the level indices (sorted ascending: up is towards fewer samples,
//! the easier, noisier videos): Levitt's (1971) transformed 1-up/2-down and 1-up/3-down, and
//! Kaernbach's (1991) weighted up-down. The position is kept in level indices as a real number
//! (weighted steps are fractions of an index) and the nearest level is presented.
//!
//! Choices (docs/experiment.md): staircase k of n in a condition starts at index
//! (levels - 1) (k + 1) / (n + 1), so interleaved staircases start spread over the range; the
//! estimate is the geometric mean of the levels at the reversals after the first two (all of
//! them when there are at most two; the presented level when there are none).

use super::interleave::{Interleaved, Track};
use crate::design::Design;
use crate::design::procedure::{StairRule, StaircaseSpec};

/// One subject's staircases, `interleaved` per condition.
pub fn procedure(design: &Design, seed: u64, spec: &StaircaseSpec) -> Interleaved<Staircase> {
    let levels = design.file.levels.len();
    let n = spec.interleaved;
    Interleaved::new(design, seed, n, spec.trials, |k| {
        let start = (levels - 1) as f64 * (k + 1) as f64 / (n + 1) as f64;
        Staircase::new(spec.rule, spec.step, levels, start)
    })
}

/// One staircase.
#[derive(Clone, Debug)]
pub struct Staircase {
    rule: StairRule,
    step: f64,
    top: f64,
    position: f64,
    /// Correct answers in a row since the last step.
    run: u32,
    /// The last step's direction (+1 harder, -1 easier, 0 none yet).
    last: i8,
    /// Level indices where the direction reversed.
    reversals: Vec<usize>,
}

impl Staircase {
    pub fn new(rule: StairRule, step: f64, levels: usize, start: f64) -> Self {
        Self {
            rule,
            step,
            top: (levels - 1) as f64,
            position: start,
            run: 0,
            last: 0,
            reversals: Vec::new(),
        }
    }

    /// The step an answer causes, in level indices (+ harder, - easier).
    fn step_for(&mut self, correct: bool) -> f64 {
        let down_after = match self.rule {
            StairRule::OneUpTwoDown => 2,
            StairRule::OneUpThreeDown => 3,
            StairRule::Weighted { target } => {
                return if correct {
                    self.step
                } else {
                    -self.step * target / (1.0 - target)
                };
            }
        };
        if !correct {
            self.run = 0;
            return -self.step;
        }
        self.run += 1;
        if self.run < down_after {
            return 0.0;
        }
        self.run = 0;
        self.step
    }

    pub fn reversals(&self) -> &[usize] {
        &self.reversals
    }
}

impl Track for Staircase {
    fn level(&self) -> usize {
        self.position.round() as usize
    }

    fn update(&mut self, level: usize, correct: bool) {
        let step = self.step_for(correct);
        if step == 0.0 {
            return;
        }
        let direction = if step > 0.0 { 1 } else { -1 };
        if self.last != 0 && direction != self.last {
            self.reversals.push(level);
        }
        self.last = direction;
        self.position = (self.position + step).clamp(0.0, self.top);
    }

    fn estimate(&self, levels: &[u32]) -> (f64, Option<(f64, f64)>, Option<f64>, f64) {
        let used = match self.reversals.len() {
            0 => &[][..],
            1 | 2 => &self.reversals[..],
            _ => &self.reversals[2..],
        };
        let ln = |i: &usize| (levels[*i] as f64).ln();
        let threshold = if used.is_empty() {
            ln(&self.level()).exp()
        } else {
            (used.iter().map(ln).sum::<f64>() / used.len() as f64).exp()
        };
        (threshold, None, None, self.rule.target())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use renderer::hash::{hash, unit_f64};

    fn run(s: &mut Staircase, answers: &[bool]) -> Vec<usize> {
        answers
            .iter()
            .map(|&a| {
                let l = s.level();
                s.update(l, a);
                s.level()
            })
            .collect()
    }

    #[test]
    fn one_up_two_down_steps_after_two_correct_and_one_wrong() {
        let mut s = Staircase::new(StairRule::OneUpTwoDown, 1.0, 8, 3.0);
        let path = run(&mut s, &[true, true, true, false, true, true, true, true]);
        assert_eq!(path, [3, 4, 4, 3, 3, 4, 4, 5]);
        // Down at 3->4, up at 4 (reversal at level 4), down at 3 (reversal at level 3).
        assert_eq!(s.reversals(), [4, 3]);
        let mut s = Staircase::new(StairRule::OneUpThreeDown, 1.0, 8, 0.0);
        assert_eq!(run(&mut s, &[false, true, true, true]), [0, 0, 0, 1]);
        // Clamped at the ends.
        let mut s = Staircase::new(StairRule::OneUpTwoDown, 2.0, 4, 3.0);
        assert_eq!(run(&mut s, &[true, true, false, false]), [3, 3, 1, 0]);
    }

    #[test]
    fn weighted_steps_are_in_the_ratio_of_the_target() {
        let mut s = Staircase::new(StairRule::Weighted { target: 0.75 }, 0.5, 20, 10.0);
        run(&mut s, &[true]);
        assert_eq!(s.position, 10.5);
        run(&mut s, &[false]);
        assert_eq!(s.position, 9.0);
    }

    /// Each rule's staircase settles where the observer's proportion correct is the rule's
    /// target (Levitt 1971; Kaernbach 1991): the mean position of the second half is the index
    /// where p = target, within a tolerance of twice its standard error over independent runs.
    #[test]
    fn staircases_converge_where_p_is_their_target() {
        let n = 200;
        // p(index) falls from 1 to 1/2 over a fine grid of 200 levels.
        let p = |x: f64| 0.5 + 0.5 / (1.0 + ((x - 100.0) / 15.0).exp());
        let at = |target: f64| 100.0 + 15.0 * (0.5 / (target - 0.5) - 1.0).ln();
        for rule in [
            StairRule::OneUpTwoDown,
            StairRule::OneUpThreeDown,
            StairRule::Weighted { target: 0.75 },
        ] {
            let means: Vec<f64> = (0..20)
                .map(|run| {
                    let mut s = Staircase::new(rule, 2.0, n, at(rule.target()));
                    let mut sum = 0.0;
                    for i in 0..4000u64 {
                        let l = s.level();
                        if i >= 2000 {
                            sum += l as f64;
                        }
                        s.update(l, unit_f64(hash(run, &[i])) < p(l as f64));
                    }
                    sum / 2000.0
                })
                .collect();
            let m = means.iter().sum::<f64>() / 20.0;
            let sd = (means.iter().map(|x| (x - m).powi(2)).sum::<f64>() / 19.0).sqrt();
            let want = at(rule.target());
            // One step of slack: the up-down rules' own bias is of the order of their step.
            let tolerance = 2.0 + 3.0 * sd / 20f64.sqrt();
            assert!(
                (m - want).abs() < tolerance,
                "{rule:?}: {m} vs {want} (sd {sd})"
            );
        }
    }
}
