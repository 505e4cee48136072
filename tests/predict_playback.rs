//! `blurlab predict` plays each video at the design's rate (`playback.fps`, issue 26): the
//! temporal channels see the frames at that rate, so the same frames give other Q at 15 fps
//! than at the manifest's 30; a design that names the manifest's own rate, or none, gives the
//! same Q bit for bit. The stimuli are the experiment crate's tiny rendered study (6 moving
//! frames).

use analysis::predict::stimuli::{PredictSettings, predict};
use experiment::Design;
use experiment::fixture::{StudySpec, write_study};
use renderer::progress::NoProgress;

/// Q of every test stimulus, in order, with the design's playback given by `playback`.
fn q_with(playback: serde_json::Value) -> Vec<f64> {
    let dir = tempfile::tempdir().unwrap();
    let mut spec = StudySpec::tiny();
    spec.design["playback"] = playback;
    let study = write_study(dir.path(), &spec).unwrap();
    let design = Design::load(&study.design_path).unwrap();
    let settings = PredictSettings {
        display: Default::default(),
        k: 1.0,
        decision: analysis::predict::stage_choice::StageChoice::for_layout(Some(
            design.file.layout,
        )),
    };
    let p = predict(&study.stimuli_dir, Some(&design), &settings, &NoProgress).unwrap();
    p.stimuli.iter().map(|s| s.row.q).collect()
}

#[test]
fn predict_plays_the_videos_at_the_design_s_rate() {
    let manifest_rate = q_with(serde_json::json!({}));
    assert!(manifest_rate.iter().all(|q| q.is_finite() && *q > 0.0));
    assert_eq!(q_with(serde_json::json!({"fps": 30.0})), manifest_rate);
    let slower = q_with(serde_json::json!({"fps": 15.0}));
    assert_eq!(slower.len(), manifest_rate.len());
    let changed = slower
        .iter()
        .zip(&manifest_rate)
        .filter(|(a, b)| (*a / *b - 1.0).abs() > 1e-6)
        .count();
    assert_eq!(
        changed,
        slower.len(),
        "{slower:?} against {manifest_rate:?}"
    );
}
