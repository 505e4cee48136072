//! Catch trials (the design's `catch_trials`, issue 49): attention checks interleaved with any
//! procedure's main trials. The main trials fall into blocks of `block - 1` procedure trials
//! plus one catch trial (the last block: what remains plus one), the catch trial's place in its
//! block drawn from the subject's seed (never after the block's last procedure trial). A catch trial shows the design's lowest level, the most
//! visible noise, against the reference, in a condition and pair/side drawn from the seed. Its
//! answer is logged (`catch: true`) and never reaches the wrapped procedure, so an adaptive
//! track's state, and the fits, are those of the session without it.

use super::seam::{Procedure, TrackEstimate};
use crate::design::Design;
use crate::trials::{COMBOS, Trial, conditions, make_trial};
use renderer::hash::hash;

const STREAM_CATCH_PLACE: u64 = 20;
const STREAM_CATCH_TRIAL: u64 = 21;

#[derive(Debug)]
pub struct WithCatch {
    inner: Box<dyn Procedure>,
    /// Positions (main-trial indices) of the catch trials, ascending.
    places: Vec<u32>,
    /// One catch trial per place.
    catches: Vec<Trial>,
    /// Main trials answered (catch trials included).
    done: u32,
    /// The trial presented now, numbered by its place among all main trials.
    current: Option<Trial>,
}

impl WithCatch {
    /// `inner`'s trials with one catch trial in every `block` main trials.
    pub fn new(inner: Box<dyn Procedure>, design: &Design, seed: u64, block: u32) -> Self {
        let per_block = block.max(2) - 1;
        let n = inner.planned();
        let conds = conditions(design);
        let lowest = design.file.levels.iter().copied().min().unwrap_or(1);
        let (mut places, mut catches) = (Vec::new(), Vec::new());
        let (mut start, mut left, mut b) = (0u32, n, 0u64);
        while left > 0 {
            let inner_here = left.min(per_block);
            let len = inner_here + 1;
            // Before the block's last procedure trial, so that a session whose procedure runs
            // to its end presents every catch trial (`planned` is exact).
            let at = start + (hash(seed, &[STREAM_CATCH_PLACE, b]) % inner_here as u64) as u32;
            let h = hash(seed, &[STREAM_CATCH_TRIAL, b]);
            let c = &conds[(h % conds.len() as u64) as usize];
            let mut t = make_trial(design, c, lowest, COMBOS[((h >> 32) % 4) as usize]);
            t.index = at;
            t.catch = true;
            places.push(at);
            catches.push(t);
            start += len;
            left -= inner_here;
            b += 1;
        }
        let mut s = Self {
            inner,
            places,
            catches,
            done: 0,
            current: None,
        };
        s.settle();
        s
    }

    /// The catch trial at main-trial position `at`, if that place holds one.
    fn catch_at(&self, at: u32) -> Option<&Trial> {
        self.places
            .binary_search(&at)
            .ok()
            .map(|k| &self.catches[k])
    }

    /// The trial at position `at` given the wrapped procedure's next trial `next`.
    fn at(&self, at: u32, next: Option<&Trial>) -> Option<Trial> {
        // The session ends with the wrapped procedure (a catch trial after its last is skipped).
        let next = next?;
        Some(match self.catch_at(at) {
            Some(c) => c.clone(),
            None => Trial {
                index: at,
                ..next.clone()
            },
        })
    }

    fn settle(&mut self) {
        self.current = self.at(self.done, self.inner.current());
    }
}

impl Procedure for WithCatch {
    fn current(&self) -> Option<&Trial> {
        self.current.as_ref()
    }

    fn answer(&mut self, correct: bool) {
        let Some(t) = &self.current else {
            return;
        };
        if !t.catch {
            self.inner.answer(correct);
        }
        self.done += 1;
        self.settle();
    }

    fn after_current(&self) -> Option<Trial> {
        self.ahead(1).pop()
    }

    fn ahead(&self, n: usize) -> Vec<Trial> {
        let cur = match &self.current {
            Some(t) => t,
            None => return Vec::new(),
        };
        // The wrapped procedure's trials that no answer can change, from its current one on
        // (the current one is still to come when a catch trial is presented now).
        let mut inner: Vec<Trial> = Vec::new();
        if cur.catch {
            inner.extend(self.inner.current().cloned());
        }
        inner.extend(self.inner.ahead(n + 1));
        let mut inner = inner.into_iter();
        let mut out = Vec::new();
        let mut at = self.done + 1;
        while out.len() < n {
            let next = if self.catch_at(at).is_some() {
                // A catch trial comes only while the wrapped procedure has a trial left.
                match inner.as_slice().first() {
                    Some(t) => self.at(at, Some(t)),
                    None => None,
                }
            } else {
                inner.next().and_then(|t| self.at(at, Some(&t)))
            };
            match next {
                Some(t) => out.push(t),
                None => break,
            }
            at += 1;
        }
        out
    }

    fn planned(&self) -> u32 {
        self.inner.planned() + self.places.len() as u32
    }

    fn done(&self) -> u32 {
        self.done
    }

    fn estimates(&self) -> Vec<TrackEstimate> {
        self.inner.estimates()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::tests::small;
    use crate::procedure::constant::ConstantStimuli;
    use crate::trials::main_trials;

    fn wrapped(block: u32) -> (WithCatch, Vec<Trial>) {
        let d = small();
        let main = main_trials(&d, 5);
        let w = WithCatch::new(Box::new(ConstantStimuli::new(main.clone())), &d, 5, block);
        (w, main)
    }

    #[test]
    fn one_catch_trial_per_block_and_the_others_in_order() {
        let (mut w, main) = wrapped(10);
        // 36 main trials in blocks of 9 + 1: 4 catch trials.
        assert_eq!(main.len(), 36);
        assert_eq!(w.planned(), 40);
        let mut seen = Vec::new();
        while let Some(t) = w.current().cloned() {
            assert_eq!(t.index as usize, seen.len());
            // What `ahead` promised is what comes.
            let promised = w.ahead(3);
            seen.push(t);
            w.answer(true);
            for (k, p) in promised.iter().enumerate() {
                if let Some(now) = w.current()
                    && k == 0
                {
                    assert_eq!(p, now);
                }
            }
        }
        assert_eq!(seen.len(), 40);
        for (b, block) in seen.chunks(10).enumerate() {
            assert_eq!(block.iter().filter(|t| t.catch).count(), 1, "block {b}");
        }
        let lowest = *small().file.levels.iter().min().unwrap();
        assert!(seen.iter().filter(|t| t.catch).all(|t| t.level == lowest));
        let plain: Vec<_> = seen.iter().filter(|t| !t.catch).collect();
        assert_eq!(plain.len(), main.len());
        for (a, b) in plain.iter().zip(&main) {
            assert_eq!(
                Trial {
                    index: 0,
                    ..(*a).clone()
                },
                Trial {
                    index: 0,
                    ..b.clone()
                }
            );
        }
    }

    #[test]
    fn catch_answers_do_not_reach_the_procedure() {
        let (mut w, _) = wrapped(4);
        let mut inner_answers = 0;
        while let Some(t) = w.current().cloned() {
            if !t.catch {
                inner_answers += 1;
            }
            w.answer(false);
        }
        assert_eq!(w.inner.done(), inner_answers);
        assert_eq!(inner_answers, 36);
    }
}
