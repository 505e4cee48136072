//! Trials with dropped frames (issue 39): a browser or a busy machine can skip frames of a
//! stimulus, and a trial whose noise was not all shown is not the trial the design planned.
//! `analyze --max-dropped-frames N` names the trials over N (and the subjects they come
//! from); with `--exclude-dropped` it also leaves them out, and names every subject whose
//! share of left-out trials is above `--max-dropped-share`, as a candidate for `--exclude`.

use experiment::log::SessionLog;
use std::collections::{BTreeMap, HashSet};

/// What to do with trials over a number of dropped frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DroppedFrames {
    /// Most dropped frames a trial may have.
    pub max: u32,
    /// Leave the trials over `max` out (else only warn).
    pub exclude: bool,
    /// A subject with a larger share of main trials over `max` is named.
    pub max_share: f64,
}

/// The main trials over the limit, as (log, trial) indices, and the warnings that name them.
pub fn over_limit(
    logs: &[SessionLog],
    skip: &HashSet<(usize, usize)>,
    d: &DroppedFrames,
) -> (HashSet<(usize, usize)>, Vec<String>) {
    let mut over = HashSet::new();
    let mut places = Vec::new();
    // subject -> (main trials, trials over the limit)
    let mut per_subject: BTreeMap<&str, (usize, usize)> = BTreeMap::new();
    for (li, log) in logs.iter().enumerate() {
        for (ti, t) in log.trials.iter().enumerate() {
            if t.practice || t.catch || skip.contains(&(li, ti)) {
                continue;
            }
            let counts = per_subject.entry(&log.header.subject).or_default();
            counts.0 += 1;
            if t.timing.dropped_frames > d.max {
                counts.1 += 1;
                over.insert((li, ti));
                places.push(format!(
                    "{}:{} ({} dropped)",
                    log.path.display(),
                    log.trial_lines[ti],
                    t.timing.dropped_frames
                ));
            }
        }
    }
    let mut warnings = Vec::new();
    if over.is_empty() {
        return (over, warnings);
    }
    const SHOWN: usize = 10;
    let more = places.len().saturating_sub(SHOWN);
    places.truncate(SHOWN);
    warnings.push(format!(
        "{} main trials have more than {} dropped frames (--max-dropped-frames){}: {}{}",
        over.len(),
        d.max,
        if d.exclude {
            ", left out (--exclude-dropped)"
        } else {
            "; still analyzed (--exclude-dropped leaves them out)"
        },
        places.join(", "),
        if more > 0 {
            format!(" and {more} more")
        } else {
            String::new()
        }
    ));
    for (subject, (all, bad)) in per_subject {
        let share = bad as f64 / all as f64;
        if share > d.max_share {
            warnings.push(format!(
                "subject {subject:?}: {bad} of {all} main trials ({:.0}%) have more than {} \
                 dropped frames, above --max-dropped-share {}; consider `--exclude {subject}`",
                100.0 * share,
                d.max,
                d.max_share
            ));
        }
    }
    if !d.exclude {
        over.clear();
    }
    (over, warnings)
}
