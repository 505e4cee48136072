//! A subject's trial list: every condition x level exactly `repeats` times, shuffled from the
//! subject's seed, plus practice trials.
//!
//! Which pair holds the difference (1 or 2) and the test video's side (left or right) are
//! *balanced*, not drawn independently: the four combinations are dealt out so that within
//! every condition x level, and over the whole list, the counts of pair 1 vs pair 2 and of left
//! vs right differ by at most one. With `repeats` a multiple of 4 each combination occurs
//! equally often in every cell. Every random choice is `hash(seed, [stream, ...])`, so the list
//! is a pure function of the design and the subject's seed.

use crate::design::Design;
use crate::log::{Side, TrialRecord};
use rand::seq::SliceRandom;
use renderer::hash::{HashRng, hash};
use renderer::ids::stimulus_id;

/// One cell of the design (without the level): the renderer's condition.
pub use renderer::condition::Condition;

/// One trial to present.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Trial {
    /// Position in its list (practice and main trials count separately from 0).
    pub index: u32,
    pub practice: bool,
    pub condition: Condition,
    /// The test video's samples per pixel.
    pub level: u32,
    pub test_stimulus: String,
    pub reference_stimulus: String,
    /// The pair (1 or 2) that shows reference and test; the other shows the reference twice.
    pub diff_pair: u8,
    /// The test video's side within its pair.
    pub test_side: Side,
    /// An attention check (`catch_trials`): logged, but left out of fits and of the adaptive
    /// procedures' state.
    pub catch: bool,
}

impl Trial {
    /// The stimulus shown in `pair` (1 or 2) on `side`.
    pub fn video(&self, pair: u8, side: Side) -> &str {
        if pair == self.diff_pair && side == self.test_side {
            &self.test_stimulus
        } else {
            &self.reference_stimulus
        }
    }

    /// The distinct stimuli the trial shows (reference first).
    pub fn stimuli(&self) -> [&str; 2] {
        [&self.reference_stimulus, &self.test_stimulus]
    }

    /// Whether a logged record is this trial (same place in the list, same videos and sides).
    pub fn matches(&self, r: &TrialRecord) -> bool {
        r.index == self.index
            && r.practice == self.practice
            && r.condition() == self.condition
            && r.level == self.level
            && r.test_stimulus == self.test_stimulus
            && r.reference_stimulus == self.reference_stimulus
            && r.diff_pair == self.diff_pair
            && r.test_side == self.test_side
            && r.catch == self.catch
    }
}

/// A subject's whole list.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TrialPlan {
    /// The subject's seed (see [`Design::subject_seed`]).
    pub seed: u64,
    pub practice: Vec<Trial>,
    pub main: Vec<Trial>,
}

/// Hash streams of the plan's random choices.
const STREAM_CELL_ORDER: u64 = 1;
const STREAM_MAIN_ORDER: u64 = 2;
const STREAM_PRACTICE: u64 = 3;

/// (diff pair, test side) in an order where each aligned pair ({0,1}, {2,3}) is a "diagonal"
/// (balanced on both factors) and every prefix of the cycle is balanced to within one.
pub(crate) const COMBOS: [(u8, Side); 4] = [
    (1, Side::Left),
    (2, Side::Right),
    (1, Side::Right),
    (2, Side::Left),
];

/// The design's conditions in file order (scene, then point set, then time filter).
pub fn conditions(design: &Design) -> Vec<Condition> {
    let f = &design.file.factors;
    let mut out = Vec::new();
    for scene in &f.scenes {
        for &point_set in &f.point_sets {
            for &time_filter in &f.time_filters {
                out.push(Condition::new(scene.clone(), point_set, time_filter));
            }
        }
    }
    out
}

/// The trial list of one subject.
pub fn plan(design: &Design, subject: &str) -> TrialPlan {
    let seed = design.subject_seed(subject);
    TrialPlan {
        seed,
        practice: practice_trials(design, seed),
        main: main_trials(design, seed),
    }
}

pub(crate) fn make_trial(
    design: &Design,
    condition: &Condition,
    level: u32,
    combo: (u8, Side),
) -> Trial {
    Trial {
        index: 0,
        practice: false,
        test_stimulus: stimulus_id(
            &condition.scene,
            condition.point_set,
            condition.time_filter,
            level,
        ),
        reference_stimulus: design.reference_id(condition),
        condition: condition.clone(),
        level,
        diff_pair: combo.0,
        test_side: combo.1,
        catch: false,
    }
}

/// The combinations one cell receives: `q` full rounds, then the remainder `m` chosen by the
/// cell's rank `k` in a shuffled order so that remainders also balance over the list.
fn cell_combos(repeats: u32, k: usize) -> Vec<(u8, Side)> {
    let mut out = Vec::with_capacity(repeats as usize);
    for _ in 0..repeats / 4 {
        out.extend_from_slice(&COMBOS);
    }
    match repeats % 4 {
        1 => out.push(COMBOS[k % 4]),
        // A diagonal: one of each pair and one of each side; alternate the two diagonals.
        2 => out.extend_from_slice(&COMBOS[2 * (k % 2)..2 * (k % 2) + 2]),
        // Everything but one combination, the left-out one cycling over cells.
        3 => out.extend((0..4).filter(|&i| i != k % 4).map(|i| COMBOS[i])),
        _ => {}
    }
    out
}

/// The constant-stimuli list of main trials (every condition x level `repeats` times, shuffled
/// and numbered) for a subject's seed: built here only, for the procedure that presents it
/// (`procedure::constant`) and the plan (`plan`).
pub fn main_trials(design: &Design, seed: u64) -> Vec<Trial> {
    let mut cells: Vec<(Condition, u32)> = Vec::new();
    for c in conditions(design) {
        for &level in &design.file.levels {
            cells.push((c.clone(), level));
        }
    }
    let mut ranks: Vec<usize> = (0..cells.len()).collect();
    ranks.shuffle(&mut HashRng::new(seed, &[STREAM_CELL_ORDER]));
    let mut trials = Vec::new();
    for (k, &cell) in ranks.iter().enumerate() {
        let (condition, level) = &cells[cell];
        for combo in cell_combos(design.file.repeats, k) {
            trials.push(make_trial(design, condition, *level, combo));
        }
    }
    trials.shuffle(&mut HashRng::new(seed, &[STREAM_MAIN_ORDER]));
    for (i, t) in trials.iter_mut().enumerate() {
        t.index = i as u32;
    }
    trials
}

/// The practice trials for a subject's seed.
pub fn practice_trials(design: &Design, seed: u64) -> Vec<Trial> {
    let conds = conditions(design);
    let levels = design.practice_levels();
    let n = design.file.practice.trials as usize;
    let start = hash(seed, &[STREAM_PRACTICE]) as usize;
    let mut trials: Vec<Trial> = (0..n)
        .map(|i| {
            let h = hash(seed, &[STREAM_PRACTICE, i as u64]);
            let c = &conds[(h % conds.len() as u64) as usize];
            let level = levels[((h >> 32) % levels.len() as u64) as usize];
            make_trial(design, c, level, COMBOS[(start + i) % 4])
        })
        .collect();
    trials.shuffle(&mut HashRng::new(seed, &[STREAM_PRACTICE, u64::MAX]));
    for (i, t) in trials.iter_mut().enumerate() {
        t.index = i as u32;
        t.practice = true;
    }
    trials
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::tests::{SMALL, small};
    use proptest::prelude::*;
    use std::collections::BTreeMap;
    use std::path::Path;

    /// |count(a) - count(b)| for the two values of a binary factor.
    fn imbalance<T: PartialEq>(items: impl Iterator<Item = T>, a: T) -> i64 {
        let (mut x, mut y) = (0i64, 0i64);
        for i in items {
            if i == a { x += 1 } else { y += 1 }
        }
        (x - y).abs()
    }

    fn design_with(repeats: u32, levels: usize, point_sets: usize) -> Design {
        let mut v: serde_json::Value = serde_json::from_str(SMALL).unwrap();
        v["repeats"] = repeats.into();
        v["levels"] = serde_json::json!((1..=levels as u32).map(|l| l * l * l).collect::<Vec<_>>());
        v["factors"]["point_sets"] = serde_json::json!(
            renderer::condition::PointSetKind::ALL[..point_sets]
                .iter()
                .map(|p| p.name())
                .collect::<Vec<_>>()
        );
        Design::parse(Path::new("d.json"), &v.to_string()).unwrap()
    }

    fn check_balance(d: &Design, plan: &TrialPlan) {
        let main = &plan.main;
        assert_eq!(main.len() as u32, d.main_trial_count());
        let mut cells: BTreeMap<(Condition, u32), Vec<&Trial>> = BTreeMap::new();
        for (i, t) in main.iter().enumerate() {
            assert_eq!(t.index as usize, i);
            assert!(!t.practice);
            cells
                .entry((t.condition.clone(), t.level))
                .or_default()
                .push(t);
        }
        let n_cells = conditions(d).len() * d.file.levels.len();
        assert_eq!(cells.len(), n_cells);
        for ts in cells.values() {
            assert_eq!(ts.len() as u32, d.file.repeats);
            assert!(imbalance(ts.iter().map(|t| t.diff_pair), 1) <= 1);
            assert!(imbalance(ts.iter().map(|t| t.test_side), Side::Left) <= 1);
            if d.file.repeats.is_multiple_of(4) {
                for combo in COMBOS {
                    let n = ts
                        .iter()
                        .filter(|t| (t.diff_pair, t.test_side) == combo)
                        .count() as u32;
                    assert_eq!(n, d.file.repeats / 4);
                }
            }
        }
        assert!(imbalance(main.iter().map(|t| t.diff_pair), 1) <= 1);
        assert!(imbalance(main.iter().map(|t| t.test_side), Side::Left) <= 1);
    }

    #[test]
    fn thesis_sized_list_is_balanced_everywhere() {
        let d = design_with(4, 8, 3);
        check_balance(&d, &plan(&d, "s01"));
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        #[test]
        fn any_repeats_and_size_balance(repeats in 1u32..10, levels in 1usize..6,
                                        point_sets in 1usize..4, subject in "[a-z0-9]{1,6}") {
            let d = design_with(repeats, levels, point_sets);
            check_balance(&d, &plan(&d, &subject));
        }
    }

    #[test]
    fn same_seed_same_list_other_subject_other_order() {
        let d = small();
        let a = plan(&d, "s01");
        assert_eq!(a, plan(&d, "s01"));
        let b = plan(&d, "s02");
        assert_ne!(a.seed, b.seed);
        assert_ne!(a.main, b.main);
        // Same multiset of cells: only the order and assignment differ.
        let cells = |p: &TrialPlan| {
            let mut v: Vec<_> = p
                .main
                .iter()
                .map(|t| (t.condition.clone(), t.level))
                .collect();
            v.sort();
            v
        };
        assert_eq!(cells(&a), cells(&b));
        // The order is shuffled: not sorted by cell.
        let order: Vec<_> = a
            .main
            .iter()
            .map(|t| (t.condition.clone(), t.level))
            .collect();
        assert_ne!(order, cells(&a));
    }

    #[test]
    fn ids_follow_the_manifest_naming_and_video_picks_the_test_once() {
        let d = small();
        let p = plan(&d, "x");
        let t = &p.main[0];
        assert_eq!(
            t.test_stimulus,
            format!(
                "{}-{}-{}-{:04}",
                t.condition.scene, t.condition.point_set, t.condition.time_filter, t.level
            )
        );
        assert_eq!(
            t.reference_stimulus,
            format!("{}-reference", t.condition.scene)
        );
        let shown: Vec<&str> = [1, 2]
            .iter()
            .flat_map(|&pair| [Side::Left, Side::Right].map(|s| t.video(pair, s)))
            .collect();
        assert_eq!(shown.iter().filter(|s| **s == t.test_stimulus).count(), 1);
    }

    #[test]
    fn practice_uses_practice_levels_and_is_balanced() {
        let d = small();
        let p = plan(&d, "s01");
        assert_eq!(p.practice.len(), 4);
        for (i, t) in p.practice.iter().enumerate() {
            assert!(t.practice);
            assert_eq!(t.index as usize, i);
            assert_eq!(t.level, 1);
        }
        assert_eq!(imbalance(p.practice.iter().map(|t| t.diff_pair), 1), 0);
        assert_eq!(
            imbalance(p.practice.iter().map(|t| t.test_side), Side::Left),
            0
        );
    }
}
