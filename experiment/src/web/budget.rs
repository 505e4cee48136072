//! What a session costs a browser before a study starts (issue 48 item 4): distinct videos,
//! bytes on the wire, download time, the browser's decoded memory; warnings above the
//! experimenter's budget, and a refusal for a design no browser can hold. `blurlab serve`
//! prints it at every start, `blurlab serve --check` prints it and stops.

use super::study::Study;
use crate::design::{Design, Layout};
use crate::trials::Trial;
use std::collections::BTreeSet;

/// Above this a browser cannot hold a trial (decoded lookahead plus the trial's encoded videos):
/// a laptop's browser evicts or crashes near 3 GB.
pub const NO_BROWSER_BYTES: u64 = 3 << 30;

/// The experimenter's budget: warnings above it, not refusals.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Bytes one session may move.
    pub session_bytes: u64,
    /// Browser memory a trial may take (decoded frames plus its encoded videos).
    pub memory_bytes: u64,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            session_bytes: 3_000_000_000,
            memory_bytes: 1_200_000_000,
        }
    }
}

/// One session's costs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Budget {
    /// Trials a session presents (practice and main).
    pub trials: usize,
    /// Distinct videos a session shows (an adaptive design: at most, every video it can show).
    pub distinct_videos: usize,
    /// Whether the trial list is known in advance (constant stimuli): the figures are exact.
    pub exact: bool,
    /// Bytes on the wire: each distinct video once.
    pub session_bytes: u64,
    /// The same session with PNG frames fetched anew for every trial (before issue 48).
    pub session_png_bytes: u64,
    /// The largest trial's distinct videos, encoded.
    pub trial_encoded_bytes: u64,
    /// Decoded frames the browser holds while a trial plays.
    pub decoded_bytes: u64,
    pub width: u32,
    pub height: u32,
    pub frames: u32,
    pub lookahead_frames: u32,
    pub cache_bytes: u64,
    pub limits: Limits,
}

/// The subject whose session the budget plays through (every subject's costs the same).
const SUBJECT: &str = "w001";

/// One subject's trials in the order shown: the practice, then the main trials as the
/// procedure gives them, catch trials included (all of them for a procedure that knows its
/// order, constant stimuli; for an adaptive one only those no answer can change).
fn session_trials(design: &Design) -> Vec<Trial> {
    let practice = crate::trials::practice_trials(design, design.subject_seed(SUBJECT));
    let main = crate::procedure::start(design, SUBJECT);
    let rest = main.ahead(main.planned() as usize);
    practice
        .into_iter()
        .chain(main.current().cloned())
        .chain(rest)
        .collect()
}

impl Budget {
    pub fn of(study: &Study, limits: Limits) -> Self {
        let v = &study.video;
        let pack = |id: &str| study.video_of(id).map(|s| s.pack.clone());
        let exact = study.design.file.procedure.is_constant();
        let trials = session_trials(&study.design);
        let n_trials = if exact {
            trials.len()
        } else {
            study.design.main_trial_count() as usize + study.design.file.practice.trials as usize
        };
        let distinct: BTreeSet<&str> = if exact {
            trials.iter().flat_map(|t| t.stimuli()).collect()
        } else {
            study.videos().map(|(id, _)| id).collect()
        };
        let session_bytes = distinct
            .iter()
            .filter_map(|id| pack(id))
            .map(|p| p.bytes)
            .sum();
        let png = |id: &str| pack(id).map_or(0, |p| p.png_bytes);
        let trial_png = |t: &Trial| 3 * png(&t.reference_stimulus) + png(&t.test_stimulus);
        let session_png_bytes = if exact {
            trials.iter().map(trial_png).sum()
        } else {
            // Every video as likely: a mean trial per trial.
            let all: Vec<u64> = study.videos().map(|(_, s)| s.pack.png_bytes).collect();
            let mean = all.iter().sum::<u64>() / all.len().max(1) as u64;
            n_trials as u64 * 4 * mean
        };
        let largest = |refs: bool| {
            study
                .videos()
                .filter(|(id, _)| distinct.contains(id))
                .filter(|(id, _)| is_reference(study, id) == refs)
                .map(|(_, s)| s.pack.bytes)
                .max()
                .unwrap_or(0)
        };
        let at_once = match study.design.file.layout {
            Layout::Sequential => 2,
            Layout::Grid => 4,
        };
        let frame = v.width as u64 * v.height as u64 * 4;
        let held = (study.client.lookahead_frames as u64 + 1).min(v.frames as u64 * 2);
        Self {
            trials: n_trials,
            distinct_videos: distinct.len(),
            exact,
            session_bytes,
            session_png_bytes,
            trial_encoded_bytes: largest(true) + largest(false),
            decoded_bytes: at_once * held * frame,
            width: v.width,
            height: v.height,
            frames: v.frames,
            lookahead_frames: study.client.lookahead_frames,
            cache_bytes: study.client.cache_bytes,
            limits,
        }
    }

    /// Browser memory while a trial plays: decoded frames and the trial's encoded videos.
    pub fn trial_memory(&self) -> u64 {
        self.decoded_bytes + self.trial_encoded_bytes
    }

    /// Why no browser can run this design, and what to change; `None` if one can.
    pub fn refusal(&self) -> Option<String> {
        let need = self.trial_memory();
        if need > NO_BROWSER_BYTES {
            let scale = NO_BROWSER_BYTES as f64 / need as f64;
            return Some(format!(
                "a trial needs {} of browser memory ({} decoded, {} encoded videos), more than \
                 a browser can hold ({}); render fewer frames (`overrides.frames` <= {}) or a \
                 smaller size (<= {}x{}), or lower --lookahead-frames",
                gb(need),
                gb(self.decoded_bytes),
                gb(self.trial_encoded_bytes),
                gb(NO_BROWSER_BYTES),
                (self.frames as f64 * scale).floor(),
                (self.width as f64 * scale.sqrt()).floor(),
                (self.height as f64 * scale.sqrt()).floor(),
            ));
        }
        if self.trial_encoded_bytes > self.cache_bytes {
            return Some(format!(
                "a trial's videos take {} encoded, more than the browser's cache of {} \
                 (--cache-mb); raise it, or render fewer frames or a smaller size",
                gb(self.trial_encoded_bytes),
                gb(self.cache_bytes)
            ));
        }
        None
    }

    /// Warnings above the experimenter's budget.
    pub fn warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        if self.session_bytes > self.limits.session_bytes {
            out.push(format!(
                "a session moves {}, above the budget of {} (--budget-gb): fewer distinct videos \
                 (levels, point sets, scenes), fewer frames or a smaller size cut it; repeats \
                 cost nothing once a video is fetched",
                gb(self.session_bytes),
                gb(self.limits.session_bytes)
            ));
        }
        if self.trial_memory() > self.limits.memory_bytes {
            out.push(format!(
                "a trial takes {} of browser memory, above the budget of {} \
                 (--memory-budget-gb): lower --lookahead-frames, or render fewer frames or a \
                 smaller size",
                gb(self.trial_memory()),
                gb(self.limits.memory_bytes)
            ));
        }
        if self.session_bytes > self.cache_bytes {
            out.push(format!(
                "a session's videos ({}) exceed the browser's cache ({}, --cache-mb): videos \
                 shown again after being evicted are fetched again",
                gb(self.session_bytes),
                gb(self.cache_bytes)
            ));
        }
        out
    }

    /// The figures as lines of text.
    pub fn lines(&self) -> Vec<String> {
        let secs = |mbit: f64| self.session_bytes as f64 * 8.0 / (mbit * 1e6);
        let at_most = if self.exact { "" } else { "at most " };
        vec![
            format!(
                "videos:          {}x{}, {} frames; {} trials a session",
                self.width, self.height, self.frames, self.trials
            ),
            format!(
                "distinct videos: {at_most}{} a session",
                self.distinct_videos
            ),
            format!(
                "bytes a session: {at_most}{} (lossless WebP, each video once; as PNG frames \
                 fetched for every trial: {})",
                gb(self.session_bytes),
                gb(self.session_png_bytes)
            ),
            format!(
                "download:        {} at 25 Mbit/s, {} at 100 Mbit/s",
                minutes(secs(25.0)),
                minutes(secs(100.0))
            ),
            format!(
                "browser memory:  {} a trial: {} decoded ({} frames ahead), {} encoded videos",
                gb(self.trial_memory()),
                gb(self.decoded_bytes),
                self.lookahead_frames,
                gb(self.trial_encoded_bytes)
            ),
        ]
    }
}

fn is_reference(study: &Study, id: &str) -> bool {
    crate::preflight::needed_stimuli(&study.design)
        .iter()
        .any(|n| n.id == id && n.test.is_none())
}

/// Bytes in GB (decimal) or MB below 1 GB.
pub fn gb(bytes: u64) -> String {
    if bytes >= 1_000_000_000 {
        format!("{:.2} GB", bytes as f64 / 1e9)
    } else {
        format!("{:.1} MB", bytes as f64 / 1e6)
    }
}

fn minutes(secs: f64) -> String {
    if secs >= 90.0 {
        format!("{:.0} min", secs / 60.0)
    } else {
        format!("{secs:.0} s")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A thesis-sized session: 768x768, 210 frames, 48 videos of 40 MB, lookahead 24.
    fn thesis_like() -> Budget {
        let frame = 768 * 768 * 4;
        Budget {
            trials: 196,
            distinct_videos: 48,
            exact: true,
            session_bytes: 48 * 40_000_000,
            session_png_bytes: 45_000_000_000,
            trial_encoded_bytes: 80_000_000,
            decoded_bytes: 2 * 25 * frame,
            width: 768,
            height: 768,
            frames: 210,
            lookahead_frames: 24,
            cache_bytes: 4_000_000_000,
            limits: Limits::default(),
        }
    }

    #[test]
    fn a_thesis_sized_session_passes_without_warnings() {
        let b = thesis_like();
        assert_eq!(b.refusal(), None);
        assert!(b.warnings().is_empty(), "{:?}", b.warnings());
        assert!(
            b.lines().iter().any(|l| l.contains("1.92 GB")),
            "{:?}",
            b.lines()
        );
    }

    #[test]
    fn over_budget_warns_and_a_trial_no_browser_holds_is_refused_with_what_fits() {
        let mut b = thesis_like();
        b.session_bytes = 5_000_000_000;
        b.limits.memory_bytes = 100_000_000;
        let w = b.warnings();
        assert_eq!(w.len(), 3, "{w:?}");
        assert!(w[0].contains("--budget-gb") && w[1].contains("--lookahead-frames"));
        assert!(w[2].contains("fetched again"));
        // Encoded videos of 2 GB a trial: over 3 GiB with the decoded frames.
        b.trial_encoded_bytes = 3_300_000_000;
        let why = b.refusal().expect("refused");
        assert!(
            why.contains("`overrides.frames` <= ") && why.contains("smaller size"),
            "{why}"
        );
        let frames: f64 = why
            .split("`overrides.frames` <= ")
            .nth(1)
            .and_then(|s| s.split(')').next())
            .and_then(|s| s.parse().ok())
            .expect("a frame count");
        assert!(frames < 210.0 && frames > 150.0, "{why}");
        // A cache smaller than a trial is refused too.
        let mut b = thesis_like();
        b.cache_bytes = 50_000_000;
        assert!(b.refusal().unwrap().contains("--cache-mb"));
    }
}
