//! How long a session takes, from the design's timing: per trial the fixation, each pair's video
//! played `loops` times (sequential layout: pair 1, the gap, pair 2; grid: both pairs at once, as
//! `experiment::playback::presentation` steps them), and the answer; practice trials count, and
//! each break adds its rest. The answer time and the rest are assumptions (the design does not hold
//! them): the command's `--response-seconds` and `--break-seconds`.

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

/// The longest video of the design's manifest at the design's playback rate, if the manifest
/// can be read.
pub fn manifest_video_seconds(design: &Design) -> Option<f64> {
    let m = Manifest::load(&design.manifest_path).ok()?;
    m.stimuli
        .iter()
        .map(|s| s.frames as f64 / design.file.playback.rate(s.fps))
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
            &Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/thesis/design.json"),
        )
        .unwrap();
        // 7 s videos, one loop, fixation 0.5 s, gap 1 s, answer 2 s: 17.5 s per trial; 192 main
        // + 4 practice trials; a break after every 48 main trials (3 breaks) of 60 s.
        let s = session(&d, 7.0, 2.0, 60.0);
        assert_eq!((s.trials, s.breaks), (196, 3));
        assert!((s.trial_seconds - 17.5).abs() < 1e-12);
        assert!((s.session_seconds - (196.0 * 17.5 + 180.0)).abs() < 1e-9);
    }

    #[test]
    fn the_design_s_playback_rate_sets_the_videos_length() {
        let dir = tempfile::tempdir().unwrap();
        let mut m = Manifest::new("t");
        m.stimuli.push(renderer::manifest::Stimulus {
            id: "plane-reference".into(),
            scene: "plane".into(),
            point_set: renderer::condition::PointSetKind::Stratified,
            time_filter: renderer::condition::TimeFilter::TruncatedBox,
            spp: 512,
            reference: true,
            reference_id: None,
            seed: 1,
            width: 4,
            height: 4,
            frames: 210,
            fps: 30.0,
            frame_paths: vec![],
            exr_paths: vec![],
            content_hash: String::new(),
            render_seconds: 0.0,
            error: None,
        });
        let path = dir.path().join("manifest.json");
        std::fs::write(&path, serde_json::to_string(&m).unwrap()).unwrap();
        let mut d = Design::load(
            &Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/thesis/design.json"),
        )
        .unwrap();
        d.manifest_path = path;
        // The manifest's rate: 210 frames at 30 fps.
        assert_eq!(manifest_video_seconds(&d), Some(7.0));
        // The design's: 210 frames at 15 fps; with two loops a trial plays each pair twice.
        d.file.playback.fps = Some(15.0);
        d.file.playback.loops = 2;
        assert_eq!(manifest_video_seconds(&d), Some(14.0));
        let s = session(&d, 14.0, 2.0, 60.0);
        assert!((s.trial_seconds - (0.5 + 2.0 * 2.0 * 14.0 + 1.0 + 2.0)).abs() < 1e-12);
    }
}
