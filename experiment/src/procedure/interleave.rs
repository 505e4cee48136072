//! Adaptive tracks interleaved over a design's conditions: each condition runs one or more
//! tracks (a QUEST+, a staircase), and the main trials take the tracks in an order shuffled
//! from the subject's seed, as the thesis interleaves its conditions. A schedule of slots,
//! `trials` per track, is fixed in advance; a track that stops early gives up its remaining
//! slots. Which pair holds the difference and the test video's side cycle through the four
//! combinations per track (balanced to within one, from a start drawn per track), so only the
//! level depends on the answers.

use super::seam::{Procedure, TrackEstimate};
use crate::design::Design;
use crate::trials::{COMBOS, Condition, Trial, conditions, make_trial};
use rand::seq::SliceRandom;
use renderer::hash::{HashRng, hash};

/// Hash streams (the constant-stimuli plan uses 1 to 3).
const STREAM_SCHEDULE: u64 = 10;
const STREAM_COMBO: u64 = 11;

/// One adaptive track over the levels, sorted ascending (index 0: fewest samples, the easiest).
pub trait Track: std::fmt::Debug + Send {
    /// Index of the level to present next.
    fn level(&self) -> usize;
    /// The answer at level index `level`.
    fn update(&mut self, level: usize, correct: bool);
    /// The track has met its own stopping rule (the trial count is the schedule's).
    fn stopped(&self) -> bool {
        false
    }
    /// (threshold spp, 95% interval, slope, target p) from the answers so far.
    fn estimate(&self, levels: &[u32]) -> (f64, Option<(f64, f64)>, Option<f64>, f64);
}

#[derive(Clone, Debug)]
struct Slot<T> {
    condition: Condition,
    number: u32,
    combo_start: usize,
    done: u32,
    track: T,
}

/// The tracks of one subject's session.
#[derive(Clone, Debug)]
pub struct Interleaved<T> {
    levels: Vec<u32>,
    per_track: u32,
    tracks: Vec<Slot<T>>,
    /// Slot k of the session belongs to track `schedule[k]`.
    schedule: Vec<usize>,
    /// The slot being presented (== schedule.len() when finished).
    pos: usize,
    done: u32,
    current: Option<Trial>,
    /// Trials are made from it like planned ones (stimulus ids, reference).
    design: Design,
}

impl<T: Track> Interleaved<T> {
    /// `per_condition` tracks for every condition of `design`, made by `make(condition, k)`.
    pub fn new(
        design: &Design,
        seed: u64,
        per_condition: u32,
        per_track: u32,
        mut make: impl FnMut(usize) -> T,
    ) -> Self {
        let mut levels = design.file.levels.clone();
        levels.sort_unstable();
        let mut tracks = Vec::new();
        for condition in conditions(design) {
            for number in 0..per_condition {
                let id = tracks.len() as u64;
                tracks.push(Slot {
                    condition: condition.clone(),
                    number,
                    combo_start: (hash(seed, &[STREAM_COMBO, id]) % 4) as usize,
                    done: 0,
                    track: make(number as usize),
                });
            }
        }
        let mut schedule: Vec<usize> = (0..tracks.len())
            .flat_map(|t| std::iter::repeat_n(t, per_track as usize))
            .collect();
        schedule.shuffle(&mut HashRng::new(seed, &[STREAM_SCHEDULE]));
        let mut s = Self {
            levels,
            per_track,
            tracks,
            schedule,
            pos: 0,
            done: 0,
            current: None,
            design: design.clone(),
        };
        s.settle();
        s
    }

    fn finished(&self, t: usize) -> bool {
        let slot = &self.tracks[t];
        slot.done >= self.per_track || slot.track.stopped()
    }

    /// Skip the slots of finished tracks and make the trial of the slot reached.
    fn settle(&mut self) {
        while self.pos < self.schedule.len() && self.finished(self.schedule[self.pos]) {
            self.pos += 1;
        }
        self.current =
            (self.pos < self.schedule.len()).then(|| self.trial(self.schedule[self.pos]));
    }

    fn trial(&self, t: usize) -> Trial {
        let slot = &self.tracks[t];
        let level = self.levels[slot.track.level()];
        let combo = COMBOS[(slot.combo_start + slot.done as usize) % 4];
        let mut trial = make_trial(&self.design, &slot.condition, level, combo);
        trial.index = self.done;
        trial
    }

    /// The tracks' states, for tests and reports.
    pub fn tracks(&self) -> impl Iterator<Item = &T> {
        self.tracks.iter().map(|s| &s.track)
    }
}

impl<T: Track> Procedure for Interleaved<T> {
    fn current(&self) -> Option<&Trial> {
        self.current.as_ref()
    }

    fn answer(&mut self, correct: bool) {
        let Some(trial) = self.current.take() else {
            return;
        };
        let t = self.schedule[self.pos];
        let level = self.levels.partition_point(|&l| l < trial.level);
        let slot = &mut self.tracks[t];
        slot.track.update(level, correct);
        slot.done += 1;
        self.done += 1;
        self.pos += 1;
        self.settle();
    }

    fn after_current(&self) -> Option<Trial> {
        let now = *self.schedule.get(self.pos)?;
        let next = (self.pos + 1..self.schedule.len())
            .map(|k| self.schedule[k])
            .find(|&t| t == now || !self.finished(t))?;
        // The current track's next trial depends on this answer (level, or whether it stops).
        (next != now).then(|| {
            let mut trial = self.trial(next);
            trial.index = self.done + 1;
            trial
        })
    }

    fn planned(&self) -> u32 {
        self.schedule.len() as u32
    }

    fn done(&self) -> u32 {
        self.done
    }

    fn estimates(&self) -> Vec<TrackEstimate> {
        self.tracks
            .iter()
            .map(|s| {
                let (threshold, interval, slope, target) = s.track.estimate(&self.levels);
                TrackEstimate {
                    condition: s.condition.clone(),
                    track: s.number,
                    trials: s.done,
                    threshold,
                    interval,
                    slope,
                    target,
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::procedure::QuestPlusSpec;
    use crate::log::Side;
    use crate::procedure::quest_plus;
    use crate::procedure::tests::adaptive;
    use std::collections::BTreeMap;

    fn answers(n: usize, seed: u64) -> impl Iterator<Item = bool> {
        (0..n).map(move |i| !hash(seed, &[i as u64]).is_multiple_of(3))
    }

    #[test]
    fn every_track_gets_its_trials_with_pairs_and_sides_balanced() {
        let d = adaptive(
            r#"{"staircase": {"interleaved": 2, "trials": 7}}"#,
            &[1, 8, 27],
        );
        let mut p = super::super::start(&d, "s01");
        assert_eq!(p.planned(), 4 * 2 * 7);
        let mut by_condition: BTreeMap<String, Vec<Trial>> = BTreeMap::new();
        for (i, correct) in answers(56, 3).enumerate() {
            let t = p.current().unwrap().clone();
            assert_eq!(t.index, i as u32);
            assert!(d.file.levels.contains(&t.level));
            by_condition
                .entry(t.condition.to_string())
                .or_default()
                .push(t);
            p.answer(correct);
        }
        assert!(p.current().is_none());
        assert_eq!(p.done(), 56);
        assert_eq!(by_condition.len(), 4);
        for ts in by_condition.values() {
            assert_eq!(ts.len(), 14);
            // Two tracks of 7: each pair and each side 7 times, give or take one per track.
            let pair1 = ts.iter().filter(|t| t.diff_pair == 1).count() as i64;
            let left = ts.iter().filter(|t| t.test_side == Side::Left).count() as i64;
            assert!(
                (pair1 - 7).abs() <= 2 && (left - 7).abs() <= 2,
                "{pair1} {left}"
            );
        }
        // A pure function of the design and the subject.
        let d2 = adaptive(
            r#"{"staircase": {"interleaved": 2, "trials": 7}}"#,
            &[1, 8, 27],
        );
        let p2 = super::super::start(&d2, "s01");
        assert_eq!(p2.current(), super::super::start(&d, "s01").current());
    }

    #[test]
    fn the_trial_after_the_current_one_is_given_only_when_no_answer_changes_it() {
        let d = adaptive(r#"{"quest_plus": {"trials": 6}}"#, &[1, 4, 8, 27]);
        let spec = QuestPlusSpec {
            trials: 6,
            ..QuestPlusSpec::default()
        };
        let mut p = quest_plus::procedure(&d, d.subject_seed("s01"), &spec);
        let mut given = 0;
        for correct in answers(24, 5) {
            if let Some(next) = p.after_current() {
                given += 1;
                for a in [true, false] {
                    let mut q = p.clone();
                    q.answer(a);
                    assert_eq!(q.current(), Some(&next));
                }
            }
            p.answer(correct);
        }
        assert!(p.current().is_none());
        // Four conditions: most next trials belong to another track.
        assert!(given >= 12, "{given}");
    }

    #[test]
    fn a_track_that_stops_early_gives_up_its_slots() {
        // A width the posterior reaches after two answers, not after the first (a rule met
        // after one answer whatever it is would stop every track there: refused, spec.rs).
        let d = adaptive(
            r#"{"quest_plus": {"trials": 5, "stop_width": 4.9}}"#,
            &[1, 8, 27],
        );
        let mut p = super::super::start(&d, "s02");
        assert_eq!(p.planned(), 20);
        let mut n = 0;
        while p.current().is_some() {
            p.answer(n % 2 == 0);
            n += 1;
        }
        assert_eq!(n, 8, "4 tracks of 2 trials");
    }

    #[test]
    fn a_stop_rule_met_after_the_first_trial_is_refused() {
        let mut v: serde_json::Value = serde_json::from_str(crate::design::tests::SMALL).unwrap();
        v["procedure"] = serde_json::json!({"quest_plus": {"trials": 5, "stop_width": 100}});
        v["levels"] = serde_json::json!([1, 8, 27]);
        let e = crate::Design::parse(std::path::Path::new("d.json"), &v.to_string())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("stop_width` is 100, but the 95% interval")
                && e.contains("every track would stop after one trial"),
            "{e}"
        );
    }
}
