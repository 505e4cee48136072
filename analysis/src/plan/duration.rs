//! How long a session takes, from the design's timing: per trial the fixation, each pair's
//! video played `loops` times (sequential layout: pair 1, the gap, pair 2; grid: both pairs at
//! once, as `experiment::presentation` steps them), and the answer; practice trials count,
//! and each break adds its rest. The answer time and the rest are assumptions (the design does
//! not hold them): the command's `--response-seconds` and `--break-seconds`.

use experiment::Design;
use experiment::design::Layout;
use renderer::manifest::Manifest;
use serde::Serialize;

/// A session's expected length.
#[derive(Clone, Debug, Serialize)]
pub struct SessionDuration {
    /// One video's play time (frames / fps), seconds.
    pub video_seconds: f64,
    pub trial_seconds: f64,
    /// Main plus practice trials.
    pub trials: u32,
    pub breaks: u32,
    pub session_seconds: f64,
}

/// The longest video of the design's manifest, if the manifest can be read.
pub fn manifest_video_seconds(design: &Design) -> Option<f64> {
    let m = Manifest::load(&design.manifest_path).ok()?;
    m.stimuli
        .iter()
        .map(|s| s.frames as f64 / s.fps)
        .max_by(f64::total_cmp)
}

/// The session's length with videos of `video_seconds`.
pub fn session(
    design: &Design,
    video_seconds: f64,
    response_seconds: f64,
    break_seconds: f64,
) -> SessionDuration {
    let f = &design.file;
    let play = f.playback.loops as f64 * video_seconds;
    let fixation = f.playback.fixation_ms as f64 / 1000.0;
    let trial_seconds = match f.layout {
        Layout::Sequential => fixation + 2.0 * play + f.playback.gap_ms as f64 / 1000.0,
        Layout::Grid => fixation + play,
    } + response_seconds;
    let main = design.main_trial_count();
    let breaks = main
        .saturating_sub(1)
        .checked_div(f.break_every)
        .unwrap_or(0);
    let trials = main + f.practice.trials;
    SessionDuration {
        video_seconds,
        trial_seconds,
        trials,
        breaks,
        session_seconds: trials as f64 * trial_seconds + breaks as f64 * break_seconds,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn the_thesis_session_adds_up() {
        let d = Design::load(
            &Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/designs/thesis.json"),
        )
        .unwrap();
        // 7 s videos, one loop, fixation 0.5 s, gap 1 s, answer 2 s: 17.5 s per trial; 192 main
        // + 4 practice trials; a break after every 48 main trials (3 breaks) of 60 s.
        let s = session(&d, 7.0, 2.0, 60.0);
        assert_eq!((s.trials, s.breaks), (196, 3));
        assert!((s.trial_seconds - 17.5).abs() < 1e-12);
        assert!((s.session_seconds - (196.0 * 17.5 + 180.0)).abs() < 1e-9);
    }
}
