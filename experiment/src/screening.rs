//! Who to exclude (issue 49): for every subject of session logs, the facts an online study
//! pre-registers exclusions on (display facts, the share of dropped or late frames, catch-trial
//! accuracy, responses too fast to have watched the videos, an unfinished session), and which
//! of the criteria (the design's `exclusion`, or `analyze`'s flags) each subject fails. Used by
//! `analyze` (the report and `exclusions.csv`) and by `blurlab serve`'s admin page (the flags
//! as they arise).

use crate::design::online::Exclusion;
use crate::log::{BrowserDisplay, SessionLog};
use std::collections::BTreeMap;

/// Default share of fast responses above which a subject is excluded (with `min_rt_ms`).
pub const DEFAULT_MAX_FAST_SHARE: f64 = 0.2;

/// What one subject's logs show.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SubjectFacts {
    pub subject: String,
    /// Main trials answered (catch trials included) and planned.
    pub main_done: usize,
    pub planned: usize,
    pub catch_trials: usize,
    pub catch_correct: usize,
    /// Frames that should have been shown (drawn + dropped), and of them dropped or late.
    pub frames: u64,
    pub bad_frames: u64,
    /// Every main trial's response time, ms.
    pub rts: Vec<f64>,
    /// The browser's display facts of every run (header and resumes).
    pub displays: Vec<BrowserDisplay>,
    /// The refresh interval of every run, ms.
    pub refresh_ms: Vec<f64>,
}

impl SubjectFacts {
    pub fn catch_accuracy(&self) -> Option<f64> {
        (self.catch_trials > 0).then(|| self.catch_correct as f64 / self.catch_trials as f64)
    }

    pub fn bad_frame_share(&self) -> Option<f64> {
        (self.frames > 0).then(|| self.bad_frames as f64 / self.frames as f64)
    }

    pub fn fast_share(&self, min_rt_ms: f64) -> Option<f64> {
        let fast = self.rts.iter().filter(|&&rt| rt < min_rt_ms).count();
        (!self.rts.is_empty()).then(|| fast as f64 / self.rts.len() as f64)
    }

    pub fn finished(&self) -> bool {
        self.main_done >= self.planned
    }
}

/// Every subject's facts, in subject order.
pub fn facts(logs: &[SessionLog]) -> Vec<SubjectFacts> {
    let mut by: BTreeMap<String, SubjectFacts> = BTreeMap::new();
    for log in logs {
        let h = &log.header;
        let f = by.entry(h.subject.clone()).or_insert_with(|| SubjectFacts {
            subject: h.subject.clone(),
            ..SubjectFacts::default()
        });
        f.planned += h.trials_planned as usize;
        let runs = std::iter::once(&h.display).chain(log.resumes.iter().map(|r| &r.display));
        for d in runs.flatten() {
            f.refresh_ms.push(d.refresh_interval_ms);
            f.displays.extend(d.browser.clone());
        }
        for t in log.main_trials() {
            f.main_done += 1;
            f.rts.push(t.timing.rt_ms);
            if t.catch {
                f.catch_trials += 1;
                f.catch_correct += t.correct as usize;
            }
            let drawn = t.timing.frame_times_ms.len() as u64;
            f.frames += drawn + u64::from(t.timing.dropped_frames);
            f.bad_frames +=
                u64::from(t.timing.dropped_frames) + u64::from(t.timing.late_frames.unwrap_or(0));
        }
    }
    by.into_values().collect()
}

/// The criteria `f` fails, each as a reason naming the fact, its value and the limit.
pub fn reasons(f: &SubjectFacts, c: &Exclusion) -> Vec<String> {
    let mut out = Vec::new();
    if c.require_finished && !f.finished() {
        out.push(format!(
            "unfinished: {} of {} main trials",
            f.main_done, f.planned
        ));
    }
    if let (Some(min), Some(acc)) = (c.min_catch_accuracy, f.catch_accuracy())
        && acc < min
    {
        out.push(format!(
            "catch trials {} of {} correct ({:.0}%), below {:.0}%",
            f.catch_correct,
            f.catch_trials,
            100.0 * acc,
            100.0 * min
        ));
    }
    if let (Some(max), Some(share)) = (c.max_bad_frames, f.bad_frame_share())
        && share > max
    {
        out.push(format!(
            "{:.1}% of frames dropped or late, above {:.1}%",
            100.0 * share,
            100.0 * max
        ));
    }
    if let Some(min_rt) = c.min_rt_ms
        && let Some(share) = f.fast_share(min_rt)
    {
        let max = c.max_fast_share.unwrap_or(DEFAULT_MAX_FAST_SHARE);
        if share > max {
            out.push(format!(
                "{:.0}% of responses faster than {min_rt} ms, above {:.0}%",
                100.0 * share,
                100.0 * max
            ));
        }
    }
    for (d, refresh) in f.displays.iter().zip(&f.refresh_ms) {
        if let Some(v) = c
            .display
            .violation(d.pixels_per_degree, d.viewing_distance_mm, *refresh)
        {
            out.push(format!("display: {v}"));
            break;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn subject() -> SubjectFacts {
        SubjectFacts {
            subject: "a".into(),
            main_done: 10,
            planned: 10,
            catch_trials: 4,
            catch_correct: 4,
            frames: 1000,
            bad_frames: 10,
            rts: vec![600.0; 10],
            ..SubjectFacts::default()
        }
    }

    fn all() -> Exclusion {
        Exclusion {
            min_catch_accuracy: Some(0.75),
            max_bad_frames: Some(0.05),
            min_rt_ms: Some(150.0),
            max_fast_share: Some(0.2),
            require_finished: true,
            ..Exclusion::default()
        }
    }

    #[test]
    fn a_good_subject_passes_and_each_failure_is_named() {
        assert!(reasons(&subject(), &all()).is_empty());
        let mut s = subject();
        s.catch_correct = 2;
        assert!(reasons(&s, &all())[0].contains("catch trials 2 of 4"));
        let mut s = subject();
        s.bad_frames = 60;
        assert!(reasons(&s, &all())[0].contains("6.0% of frames"));
        let mut s = subject();
        s.rts[..3].fill(40.0);
        assert!(reasons(&s, &all())[0].contains("30% of responses faster than 150"));
        // At the limit (2 of 10 = 20%) is not above it.
        s.rts[2] = 600.0;
        assert!(reasons(&s, &all()).is_empty());
        let mut s = subject();
        s.main_done = 7;
        assert!(reasons(&s, &all())[0].contains("unfinished: 7 of 10"));
        // No criteria: nobody is excluded, whatever the facts.
        s.catch_correct = 0;
        assert!(reasons(&s, &Exclusion::default()).is_empty());
    }

    #[test]
    fn facts_that_were_not_measured_exclude_no_one() {
        let s = SubjectFacts {
            rts: vec![],
            frames: 0,
            catch_trials: 0,
            ..subject()
        };
        assert_eq!(s.catch_accuracy(), None);
        assert_eq!(s.bad_frame_share(), None);
        assert!(reasons(&s, &all()).is_empty());
    }
}
