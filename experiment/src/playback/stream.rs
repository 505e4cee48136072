//! When a trial whose videos are still loading may start: the rule behind streaming playback,
//! with no GUI types so it can be tested with made-up rates.
//!
//! Frames load in the order they are first due ([`loading_order`]): a video that pair 1 shows
//! from the fixation's end, one only pair 2 shows (sequential layout) after pair 1 and the gap.
//! A trial may start once, at the loading rate measured so far, every frame not yet loaded will
//! be in before it is due: with `loaded` frames in, the k-th of the order is in
//! `(k + 1 - loaded) / rate` seconds. A margin covers a rate that falls during playback (decoding
//! then shares the CPU with drawing); a frame still late is not drawn: the presentation holds
//! the last drawn frame and counts the late ones as dropped
//! ([`crate::playback::presentation::Presentation::tick_ready`]).

use crate::design::{Design, Layout};
use crate::log::Side;
use crate::trials::Trial;

/// Loading must be this many times faster than needed before a trial starts on a prefix.
pub const MARGIN: f64 = 1.5;

/// Frames that must be in before a rate is trusted (all of them if there are fewer).
pub const MIN_LOADED: usize = 8;

/// One frame to load and when it is first shown, seconds after the trial's start.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Due {
    pub video: usize,
    pub frame: usize,
    pub at_s: f64,
}

/// Seconds from `trial`'s start to the first frame of `stimulus` (videos of `frames` frames made at
/// `fps`, played at the design's rate): the fixation, and for a video only pair 2 shows in the
/// sequential layout, pair 1's playback and the gap as well.
pub fn first_shown_s(design: &Design, trial: &Trial, stimulus: &str, frames: u32, fps: f64) -> f64 {
    let p = &design.file.playback;
    let fixation = p.fixation_ms as f64 / 1000.0;
    let in_pair_1 = [Side::Left, Side::Right]
        .iter()
        .any(|&s| trial.video(1, s) == stimulus);
    if in_pair_1 || design.file.layout == Layout::Grid {
        fixation
    } else {
        fixation + (p.loops * frames) as f64 / p.rate(fps) + p.gap_ms as f64 / 1000.0
    }
}

/// Every frame of videos of `frames[v]` frames at `fps`, first shown `starts[v]` seconds after
/// the start, in the order they are due (the lower video first on a tie).
pub fn loading_order(starts: &[f64], frames: &[usize], fps: f64) -> Vec<Due> {
    let mut order: Vec<Due> = starts
        .iter()
        .zip(frames)
        .enumerate()
        .flat_map(|(video, (&start, &n))| {
            (0..n).map(move |frame| Due {
                video,
                frame,
                at_s: start + frame as f64 / fps,
            })
        })
        .collect();
    order.sort_by(|a, b| a.at_s.total_cmp(&b.at_s).then(a.video.cmp(&b.video)));
    order
}

/// Whether a trial may start now with the first `loaded` frames of `order` in, loading going on
/// at `rate` frames per second.
pub fn can_start(order: &[Due], loaded: usize, rate: f64) -> bool {
    if loaded >= order.len() {
        return true;
    }
    if loaded < MIN_LOADED || rate.is_nan() || rate <= 0.0 {
        return false;
    }
    order[loaded..]
        .iter()
        .enumerate()
        .all(|(i, d)| MARGIN * (i + 1) as f64 / rate <= d.at_s)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The thesis's trial: 210 frames at 30 fps after a 0.5 s fixation; a second video from
    /// `second` s on.
    fn thesis(second: f64) -> Vec<Due> {
        loading_order(&[0.5, second], &[210, 210], 30.0)
    }

    #[test]
    fn frames_load_in_the_order_they_are_due() {
        let both = thesis(0.5);
        assert_eq!(both.len(), 420);
        let first: Vec<(usize, usize)> = both[..4].iter().map(|d| (d.video, d.frame)).collect();
        assert_eq!(first, [(0, 0), (1, 0), (0, 1), (1, 1)]);
        // A video pair 2 shows alone comes after the other's frames due before it.
        let later = thesis(8.5);
        assert!(later[..210].iter().all(|d| d.video == 0));
        assert!(later.windows(2).all(|w| w[0].at_s <= w[1].at_s));
    }

    #[test]
    fn a_loaded_trial_always_starts_and_an_empty_one_never() {
        let order = thesis(0.5);
        assert!(can_start(&order, 420, 0.0));
        assert!(!can_start(&order, 0, 1e9));
        assert!(!can_start(&order, MIN_LOADED - 1, 1e9));
        assert!(!can_start(&order, 100, 0.0));
        assert!(!can_start(&order, 100, f64::NAN));
    }

    #[test]
    fn both_videos_from_pair_1_need_twice_the_rate_of_one() {
        // Both videos due from 0.5 s: 60 frames a second are needed, 90 with the margin, from
        // frame 8 on: the last frame is due at 0.5 + 209 / 30 = 7.467 s and in at 1.5 x 412 /
        // rate s: rate >= 82.8.
        assert!(can_start(&thesis(0.5), MIN_LOADED, 83.0));
        assert!(!can_start(&thesis(0.5), MIN_LOADED, 82.5));
        // Only pair 2 shows the second video (8.5 s on): half the rate does.
        assert!(can_start(&thesis(8.5), MIN_LOADED, 45.0));
    }

    #[test]
    fn slow_loading_waits_until_the_rest_loads_in_time() {
        // One video at 15 frames a second: the last of 210 - r frames is in at
        // 1.5 (210 - r) / 15 s and due at 7.467 s: r >= 135.3, so 136 frames.
        let one = loading_order(&[0.5], &[210], 30.0);
        assert!(!can_start(&one, 135, 15.0));
        assert!(can_start(&one, 136, 15.0));
    }

    /// Whatever the rate, once started no frame is due before it is in if the rate holds.
    #[test]
    fn no_frame_is_due_before_it_is_in_once_started() {
        for second in [0.5, 8.5] {
            let order = thesis(second);
            for rate in [10.0, 20.0, 31.0, 45.0, 60.0, 200.0] {
                let loaded = (0..=order.len())
                    .find(|&l| can_start(&order, l, rate))
                    .unwrap();
                for (k, d) in order.iter().enumerate().skip(loaded) {
                    let in_at = (k + 1 - loaded) as f64 / rate;
                    assert!(in_at <= d.at_s, "rate {rate}: frame {k} late");
                }
            }
        }
    }
}
