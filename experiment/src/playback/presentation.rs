//! One trial's presentation as a clock-driven sequence of steps, with no GUI types: the app asks
//! [`Presentation::tick`] what to draw at each repaint, tests drive it with made-up times.
//!
//! ```text
//! sequential: fixation -> pair 1 (loops x video) -> gap -> pair 2 (loops x video) -> respond
//! grid:       fixation -> both pairs at once (loops x video)                      -> respond
//! ```
//!
//! A step starts at the first repaint that shows it (so a pair's first drawn frame is always its
//! frame 0, and both videos of a pair, drawn in the same repaint, start on the same display
//! frame). The video frame shown is floor((t - onset) fps): frames follow the clock, never the
//! repaint count, so a late repaint skips frames instead of slowing the video. Every skipped
//! frame is counted as dropped, so `frames shown + dropped = frames x loops` for each pair.

use crate::design::{Design, Layout};
use crate::log::Timing;

/// Which pair a playback step shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pairs {
    /// Pair 1 or 2 alone (sequential layout).
    One(u8),
    /// Both (grid layout).
    Both,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Step {
    Fixation(f64),
    Play(Pairs),
    Gap(f64),
    Respond,
}

/// What to draw now.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    Fixation,
    /// Pair(s) at video frame `frame`.
    Play {
        pairs: Pairs,
        frame: u32,
    },
    /// The screen between the pairs.
    Gap,
    /// Ask for the answer.
    Respond,
}

/// The presentation of one trial.
#[derive(Clone, Debug)]
pub struct Presentation {
    steps: Vec<Step>,
    current: usize,
    step_start: Option<f64>,
    frames: u32,
    fps: f64,
    loops: u32,
    /// Last video frame index (counting loops) shown in the current playback step.
    last_index: Option<u64>,
    onsets_ms: Vec<f64>,
    frame_times_ms: Vec<f64>,
    dropped: u32,
}

impl Presentation {
    /// A presentation of videos with `frames` frames made at `fps` (the manifest's rate) under
    /// the design's playback, which plays them at its own rate when it gives one.
    pub fn new(design: &Design, frames: u32, fps: f64) -> Self {
        let p = &design.file.playback;
        let fixation = Step::Fixation(p.fixation_ms as f64 / 1000.0);
        let steps = match design.file.layout {
            Layout::Sequential => vec![
                fixation,
                Step::Play(Pairs::One(1)),
                Step::Gap(p.gap_ms as f64 / 1000.0),
                Step::Play(Pairs::One(2)),
                Step::Respond,
            ],
            Layout::Grid => vec![fixation, Step::Play(Pairs::Both), Step::Respond],
        };
        Self {
            steps,
            current: 0,
            step_start: None,
            frames: frames.max(1),
            fps: p.rate(fps),
            loops: p.loops,
            last_index: None,
            onsets_ms: Vec::new(),
            frame_times_ms: Vec::new(),
            dropped: 0,
        }
    }

    fn total_frames(&self) -> u64 {
        self.frames as u64 * self.loops as u64
    }

    /// Video frames the whole trial shows: each playback step shows its frames x loops (both
    /// pairs at once in a grid, one pair after the other in sequence). No more can be drawn,
    /// dropped or late.
    pub fn frames_shown(&self) -> u64 {
        let plays = self
            .steps
            .iter()
            .filter(|s| matches!(s, Step::Play(_)))
            .count();
        self.total_frames() * plays as u64
    }

    /// What to show at `now` (seconds on the session's clock), recording onsets, frame times
    /// and drops.
    pub fn tick(&mut self, now: f64) -> View {
        self.tick_ready(now, [u32::MAX; 2])
    }

    /// [`Self::tick`] while only the first `ready[p - 1]` frames of both videos of pair p are
    /// loaded (streaming playback): a frame not loaded when due is never drawn. The last drawn
    /// frame stays up instead, and the frames skipped meanwhile count as dropped, as after a late
    /// repaint; a pair whose frame 0 is not loaded does not start (the fixation or gap goes on).
    pub fn tick_ready(&mut self, now: f64, ready: [u32; 2]) -> View {
        loop {
            let step = self.steps[self.current];
            let first = self.step_start.is_none();
            let start = *self.step_start.get_or_insert(now);
            let elapsed = now - start;
            match step {
                Step::Fixation(d) | Step::Gap(d) if elapsed >= d => self.next_step(),
                Step::Fixation(_) => return View::Fixation,
                Step::Gap(_) => return View::Gap,
                Step::Respond => return View::Respond,
                Step::Play(pairs) => {
                    if first {
                        self.onsets_ms.push(now * 1000.0);
                        self.last_index = None;
                    }
                    let index = (elapsed * self.fps).floor() as u64;
                    if index >= self.total_frames() {
                        // Frames due before the end but never drawn were dropped too.
                        let shown_to = self.last_index.map_or(0, |l| l + 1);
                        self.dropped += (self.total_frames() - shown_to) as u32;
                        self.next_step();
                        continue;
                    }
                    let frame = (index % self.frames as u64) as u32;
                    let ready = match pairs {
                        Pairs::One(p) => ready[usize::from(p.clamp(1, 2)) - 1],
                        Pairs::Both => ready[0].min(ready[1]),
                    };
                    if frame >= ready {
                        return self.hold(pairs);
                    }
                    if self.last_index != Some(index) {
                        let expected = self.last_index.map_or(0, |l| l + 1);
                        self.dropped += (index - expected) as u32;
                        self.frame_times_ms.push(now * 1000.0);
                        self.last_index = Some(index);
                    }
                    return View::Play { pairs, frame };
                }
            }
        }
    }

    /// The view while the frame due is not loaded: the last one drawn, or, before the first,
    /// the step before playback (which then starts later).
    fn hold(&mut self, pairs: Pairs) -> View {
        match self.last_index {
            Some(l) => View::Play {
                pairs,
                frame: (l % self.frames as u64) as u32,
            },
            None => {
                self.step_start = None;
                self.onsets_ms.pop();
                if self.current > 0 && matches!(self.steps[self.current - 1], Step::Gap(_)) {
                    View::Gap
                } else {
                    View::Fixation
                }
            }
        }
    }

    fn next_step(&mut self) {
        self.current = (self.current + 1).min(self.steps.len() - 1);
        self.step_start = None;
    }

    /// Seconds from `now` until what is shown next changes (a frame boundary or the end of a
    /// timed step); `None` while waiting for the answer.
    pub fn next_change(&self, now: f64) -> Option<f64> {
        let start = self.step_start.unwrap_or(now);
        match self.steps[self.current] {
            Step::Fixation(d) | Step::Gap(d) => Some((start + d - now).max(0.0)),
            Step::Play(_) => {
                let next = self.last_index.map_or(0, |l| l + 1) as f64;
                Some((start + next / self.fps - now).max(0.0))
            }
            Step::Respond => None,
        }
    }

    /// Whether the videos are playing (repaint every display refresh).
    pub fn playing(&self) -> bool {
        matches!(self.steps[self.current], Step::Play(_))
    }

    /// Whether the presentation is over and the answer is due.
    pub fn responding(&self) -> bool {
        matches!(self.steps[self.current], Step::Respond)
    }

    /// Milliseconds from the first repaint of the response step to `now`.
    pub fn response_time_ms(&self, now: f64) -> f64 {
        match (self.responding(), self.step_start) {
            (true, Some(s)) => (now - s).max(0.0) * 1000.0,
            _ => 0.0,
        }
    }

    /// After a pause of `paused` seconds: a presentation cut short is shown again from the
    /// start (what was seen of it is discarded); while responding, the pause is left out of
    /// the response time.
    pub fn after_pause(&mut self, paused: f64) {
        if self.responding() {
            if let Some(s) = self.step_start.as_mut() {
                *s += paused;
            }
        } else {
            self.current = 0;
            self.step_start = None;
            self.last_index = None;
            self.onsets_ms.clear();
            self.frame_times_ms.clear();
            self.dropped = 0;
        }
    }

    /// What the log keeps of this presentation, answered at `now`.
    pub fn timing(&self, now: f64, pauses: u32, preload_ms: f64) -> Timing {
        Timing {
            rt_ms: self.response_time_ms(now),
            onsets_ms: self.onsets_ms.clone(),
            frame_times_ms: self.frame_times_ms.clone(),
            dropped_frames: self.dropped,
            pauses,
            preload_ms,
            late_frames: None,
            refresh_interval_ms: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::tests::small;

    /// Tick at a steady interval until the answer is due; return the views, the presentation
    /// and the time of the tick that reached the response step.
    fn run(d: &Design, frames: u32, fps: f64, dt: f64) -> (Vec<View>, Presentation, f64) {
        let mut p = Presentation::new(d, frames, fps);
        let mut views = Vec::new();
        let mut t = 10.0;
        loop {
            views.push(p.tick(t));
            if p.responding() {
                return (views, p, t);
            }
            t += dt;
            assert!(t < 100.0, "never reached the response step");
        }
    }

    fn frames_of(views: &[View], pair: u8) -> Vec<u32> {
        views
            .iter()
            .filter_map(|v| match v {
                View::Play {
                    pairs: Pairs::One(p),
                    frame,
                } if *p == pair => Some(*frame),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn at_twice_the_video_rate_every_frame_shows_twice_and_none_drops() {
        // 60 Hz repaints, 30 fps video: frame k is due at k/30 s, repaints every 1/60 s.
        // Use a binary-exact interval near 1/60 s (2^-6) so floor() sees no rounding.
        let d = small();
        let dt = 1.0 / 64.0;
        let (views, p, _) = run(&d, 6, 32.0, dt);
        for pair in [1, 2] {
            let f = frames_of(&views, pair);
            assert_eq!(f, vec![0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5]);
        }
        let t = p.timing(0.0, 0, 0.0);
        assert_eq!(t.dropped_frames, 0);
        assert_eq!(t.frame_times_ms.len(), 12);
        assert_eq!(p.frames_shown(), 12);
        assert_eq!(t.onsets_ms.len(), 2);
        // Fixation 0.5 s, pair 6/32 s, gap 1 s: pair 2 starts >= 1.6875 s after pair 1 start.
        assert!(t.onsets_ms[1] - t.onsets_ms[0] >= 1000.0 * (6.0 / 32.0 + 1.0));
    }

    #[test]
    fn late_repaints_skip_frames_and_count_them_including_at_the_end() {
        let d = small();
        // Repaint every 3 video frames: 10 frames show 0, 3, 6, 9; 6 dropped per pair.
        let (views, p, _) = run(&d, 10, 32.0, 3.0 / 32.0);
        assert_eq!(frames_of(&views, 1), vec![0, 3, 6, 9]);
        assert_eq!(p.timing(0.0, 0, 0.0).dropped_frames, 2 * 6);
        // 4 frames every 3: shows 0 and 3, frames 1 and 2 dropped in each pair.
        let (views, p, _) = run(&d, 4, 32.0, 3.0 / 32.0);
        assert_eq!(frames_of(&views, 2), vec![0, 3]);
        assert_eq!(p.timing(0.0, 0, 0.0).dropped_frames, 4);
    }

    #[test]
    fn loops_wrap_the_frame_index_and_grid_shows_both_pairs_once() {
        let mut v: serde_json::Value = serde_json::from_str(crate::design::tests::SMALL).unwrap();
        v["layout"] = "grid".into();
        v["playback"] = serde_json::json!({"loops": 2});
        let d = Design::parse(std::path::Path::new("d.json"), &v.to_string()).unwrap();
        let (views, p, _) = run(&d, 3, 32.0, 1.0 / 32.0);
        let both: Vec<u32> = views
            .iter()
            .filter_map(|v| match v {
                View::Play {
                    pairs: Pairs::Both,
                    frame,
                } => Some(*frame),
                _ => None,
            })
            .collect();
        assert_eq!(both, vec![0, 1, 2, 0, 1, 2]);
        assert_eq!(p.frames_shown(), 6);
        assert_eq!(p.timing(0.0, 0, 0.0).onsets_ms.len(), 1);
        assert!(!views.contains(&View::Gap));
    }

    #[test]
    fn the_design_s_rate_replaces_the_manifest_s_and_loops_repeat_at_it() {
        // 15 fps (the thesis's session length) for 30-fps videos, two loops: at 64 Hz repaints
        // (binary-exact, so floor() sees no rounding) the frame shown at t is floor(t * 15).
        let mut v: serde_json::Value = serde_json::from_str(crate::design::tests::SMALL).unwrap();
        v["layout"] = "grid".into();
        v["playback"] = serde_json::json!({"fps": 15.0, "loops": 2});
        let d = Design::parse(std::path::Path::new("d.json"), &v.to_string()).unwrap();
        let dt = 1.0 / 64.0;
        let (views, p, _) = run(&d, 4, 30.0, dt);
        let shown: Vec<u32> = views
            .iter()
            .filter_map(|v| match v {
                View::Play { frame, .. } => Some(*frame),
                _ => None,
            })
            .collect();
        // 8 frames (4 x 2 loops) of 1/15 s: 8 / 15 s = 34.13 repaints.
        let expected: Vec<u32> = (0..35)
            .map(|i| ((i as f64 * dt * 15.0).floor() as u32) % 4)
            .collect();
        assert_eq!(shown, expected);
        assert_eq!(p.timing(0.0, 0, 0.0).dropped_frames, 0);
        // Without the field the manifest's rate plays.
        let (views, _, _) = run(&small(), 4, 30.0, dt);
        assert_eq!(
            frames_of(&views, 1).len(),
            (4.0_f64 * 64.0 / 30.0).ceil() as usize
        );
    }

    #[test]
    fn pause_restarts_a_presentation_but_not_the_answer_clock() {
        let d = small();
        let mut p = Presentation::new(&d, 4, 32.0);
        p.tick(0.0);
        p.tick(0.6); // into pair 1
        assert!(p.playing());
        p.after_pause(5.0);
        assert_eq!(p.tick(7.0), View::Fixation);
        assert!(p.timing(7.0, 1, 0.0).onsets_ms.is_empty());
        let (_, mut done, t_respond) = run(&d, 4, 32.0, 1.0 / 32.0);
        done.after_pause(2.0);
        assert_eq!(done.response_time_ms(t_respond + 3.0), 1000.0);
    }

    /// Streaming: pair 1's frames load at half the video's rate; no frame is shown before it is
    /// loaded, every due frame is either shown or counted as dropped, and pair 1 waits for
    /// frame 0 (pair 2's videos are all in).
    #[test]
    fn a_frame_not_yet_loaded_is_never_shown_and_counts_as_dropped() {
        let d = small();
        let (frames, fps, dt) = (8, 32.0, 1.0 / 64.0);
        let mut p = Presentation::new(&d, frames, fps);
        let t0 = 10.0;
        let loaded = |t: f64| (((t - t0 - 0.55) * fps / 2.0).max(0.0) as u32).min(frames);
        let (mut t, mut shown) = (t0, Vec::new());
        while !p.responding() {
            let ready = loaded(t);
            match p.tick_ready(t, [ready, u32::MAX]) {
                View::Play { pairs, frame } => {
                    if pairs == Pairs::One(1) {
                        assert!(frame < ready, "frame {frame} shown with {ready} loaded");
                    }
                    shown.push(frame);
                }
                View::Fixation => assert!(t < t0 + 0.62, "fixation at {t}"),
                _ => {}
            }
            t += dt;
            assert!(t < t0 + 100.0);
        }
        let timing = p.timing(t, 0, 0.0);
        // Pair 1 began only once frame 0 was loaded (0.5 s fixation; loaded at 0.6125 s).
        assert!(timing.onsets_ms[0] >= (t0 + 0.6125) * 1000.0 - 1e-6);
        let distinct = timing.frame_times_ms.len() as u32;
        assert_eq!(distinct + timing.dropped_frames, 2 * frames);
        assert!(timing.dropped_frames > 0);
        assert!(shown.windows(2).all(|w| w[0] <= w[1] || w[1] == 0));
    }

    #[test]
    fn next_change_points_at_the_next_frame_boundary() {
        let d = small();
        let mut p = Presentation::new(&d, 4, 32.0);
        p.tick(0.0);
        assert_eq!(p.next_change(0.25), Some(0.25));
        p.tick(0.5); // pair 1 starts at 0.5, frame 0
        assert_eq!(p.next_change(0.5), Some(1.0 / 32.0));
    }
}
