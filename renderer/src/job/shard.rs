//! Splitting a job for scale-out. The unit of work is one stimulus x one range of frames
//! (`frames_per_unit` consecutive frames). Every frame's pixels depend only on the stimulus's
//! seed and the frame number, so which machine renders a unit never changes its bytes; a shard
//! is just a subset of units. `--shard K/N` (K in 1..=N, so that Slurm's `--array=1-N` maps
//! directly) takes the K-th of N subsets chosen by a greedy longest-first balance of estimated
//! cost; within a shard, reference units go first so that test frames usually find their
//! reference frame already rendered.

use anyhow::{Result, bail};
use std::ops::Range;
use std::str::FromStr;

/// One of N disjoint parts of a job.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// 1-based index.
    pub index: u32,
    pub count: u32,
}

impl Shard {
    /// The whole job as one shard.
    pub const WHOLE: Shard = Shard { index: 1, count: 1 };
}

impl FromStr for Shard {
    type Err = anyhow::Error;
    fn from_str(s: &str) -> Result<Self> {
        let parsed = s.split_once('/').and_then(|(k, n)| {
            Some((k.trim().parse::<u32>().ok()?, n.trim().parse::<u32>().ok()?))
        });
        match parsed {
            Some((index, count)) if count >= 1 && (1..=count).contains(&index) => {
                Ok(Shard { index, count })
            }
            _ => bail!("--shard {s:?}: expected K/N with 1 <= K <= N, e.g. 2/8"),
        }
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// A unit of work: frames `frames` of stimulus `stimulus` (an index into the expansion).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Unit {
    pub stimulus: usize,
    pub frames: Range<u32>,
    pub reference: bool,
    /// Estimated cost (samples to trace).
    pub cost: u64,
}

/// Cut each stimulus's frames into units of `frames_per_unit`. `stimuli` gives per stimulus
/// (frame count, samples per frame, is reference).
pub fn units(stimuli: &[(u32, u64, bool)], frames_per_unit: u32) -> Vec<Unit> {
    let step = frames_per_unit.max(1);
    let mut out = Vec::new();
    for (i, &(frames, samples_per_frame, reference)) in stimuli.iter().enumerate() {
        let mut start = 0;
        while start < frames {
            let end = (start + step).min(frames);
            out.push(Unit {
                stimulus: i,
                frames: start..end,
                reference,
                cost: samples_per_frame.max(1) * (end - start) as u64,
            });
            start = end;
        }
    }
    out
}

/// Indices of the units shard `shard` renders, in the order to render them: references first,
/// then by unit index.
pub fn assign(units: &[Unit], shard: Shard) -> Vec<usize> {
    let n = shard.count.max(1) as usize;
    let mut order: Vec<usize> = (0..units.len()).collect();
    // Longest first, ties by index: a deterministic greedy balance.
    order.sort_by(|&a, &b| units[b].cost.cmp(&units[a].cost).then(a.cmp(&b)));
    let mut load = vec![0u64; n];
    let mut mine = Vec::new();
    for u in order {
        let target = (0..n).min_by_key(|&k| (load[k], k)).unwrap_or(0);
        load[target] += units[u].cost;
        if target == shard.index as usize - 1 {
            mine.push(u);
        }
    }
    mine.sort_by_key(|&u| (!units[u].reference, u));
    mine
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_k_of_n() {
        assert_eq!(
            "2/8".parse::<Shard>().unwrap(),
            Shard { index: 2, count: 8 }
        );
        for bad in ["0/4", "5/4", "1/0", "x/2", "3"] {
            let e = bad.parse::<Shard>().unwrap_err().to_string();
            assert!(e.contains("K/N"), "{bad}: {e}");
        }
    }

    #[test]
    fn units_cover_every_frame_once() {
        let u = units(&[(20, 10, true), (5, 1, false)], 8);
        assert_eq!(u.len(), 4);
        assert_eq!(u[2].frames, 16..20);
        assert_eq!(u[3].frames, 0..5);
        assert_eq!(u[0].cost, 80);
    }

    #[test]
    fn shards_partition_the_units_and_balance_them() {
        let stimuli: Vec<(u32, u64, bool)> = (0..30)
            .map(|i| (24, 1 + (i * 37 % 512) as u64, i % 10 == 0))
            .collect();
        let u = units(&stimuli, 8);
        for n in [1u32, 2, 3, 7] {
            let mut seen = vec![0; u.len()];
            let mut loads = Vec::new();
            for k in 1..=n {
                let mine = assign(&u, Shard { index: k, count: n });
                loads.push(mine.iter().map(|&i| u[i].cost).sum::<u64>());
                for i in mine {
                    seen[i] += 1;
                }
            }
            assert!(
                seen.iter().all(|&c| c == 1),
                "n = {n}: every unit exactly once"
            );
            // Greedy longest-first: no shard exceeds the average by more than the largest unit.
            let avg = loads.iter().sum::<u64>() / n as u64;
            let biggest = u.iter().map(|x| x.cost).max().unwrap();
            assert!(loads.iter().all(|&l| l <= avg + biggest), "{loads:?}");
        }
    }

    #[test]
    fn references_come_first_within_a_shard() {
        let u = units(&[(8, 5, false), (8, 500, true), (8, 5, false)], 4);
        let mine = assign(&u, Shard::WHOLE);
        assert!(u[mine[0]].reference && u[mine[1]].reference);
        assert!(!u[mine[2]].reference);
    }
}
