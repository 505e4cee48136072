//! Prediction and calibration end to end: sessions simulated from a prediction with a known
//! sensitivity constant, through the experiment's session machine and logs, and the
//! calibration's maximum-likelihood fit recovering that constant.

// The thesis study's design; the rest of the shared support serves the recovery tests.
#[allow(dead_code)]
mod support;

use analysis::data::Dataset;
use analysis::predict::calibrate::{calibrate, cells};
use analysis::predict::stimuli::{Prediction, StimulusPrediction};
use experiment::display::DisplaySpec;
use experiment::predicted::{PredictedRow, PredictedTable, two_pair_p_correct};
use experiment::simulate::simulate;
use std::path::Path;
use support::thesis_study::{LEVELS, POINT_SETS, SCENES, TIME_FILTER, write_design};

/// Q of a thesis-design cell: noise amplitude falling as spp^-1/2, scenes and point sets apart.
fn q(scene: usize, point_set: usize, spp: u32) -> f64 {
    (6.0 + 4.0 * scene as f64) * (1.0 + 0.15 * point_set as f64) / (spp as f64).sqrt()
}

fn row(scene: usize, ps: usize, spp: u32, k: f64) -> PredictedRow {
    let q = q(scene, ps, spp);
    let p = two_pair_p_correct(k * q);
    PredictedRow {
        scene: SCENES[scene].0.into(),
        point_set: POINT_SETS[ps].parse().unwrap(),
        time_filter: TIME_FILTER.parse().unwrap(),
        spp,
        test_stimulus: renderer::job::expand::stimulus_id(
            SCENES[scene].0,
            POINT_SETS[ps].parse().unwrap(),
            TIME_FILTER.parse().unwrap(),
            spp,
        ),
        reference_stimulus: format!("{}-reference", SCENES[scene].0),
        q,
        k,
        d_prime: k * q,
        p_correct: p,
        p_frame_min: p,
        p_frame_median: p,
        p_frame_max: p,
        frames: 1,
    }
}

fn rows(k: f64) -> Vec<PredictedRow> {
    let mut out = Vec::new();
    for s in 0..SCENES.len() {
        for p in 0..POINT_SETS.len() {
            for &spp in &LEVELS {
                out.push(row(s, p, spp, k));
            }
        }
    }
    out
}

#[test]
fn calibration_recovers_the_constant_the_sessions_were_simulated_with() {
    let dir = tempfile::tempdir().unwrap();
    let design = write_design(dir.path(), 77);
    // Subjects answer from the prediction with k = 0.6, all alike (no spread), no lapse.
    let k_true = 0.6;
    let csv = dir.path().join("predicted.csv");
    std::fs::write(
        &csv,
        PredictedTable::from_rows(rows(k_true)).to_csv().unwrap(),
    )
    .unwrap();
    let observer_file = dir.path().join("observer.json");
    std::fs::write(
        &observer_file,
        r#"{"format": "blurlab-observer/1", "name": "known-k", "predicted": "predicted.csv",
            "subject_spread": 0.0, "seed": 5}"#,
    )
    .unwrap();
    let observer = experiment::Observer::load(&observer_file).unwrap();
    let sessions = dir.path().join("sessions");
    simulate(&design, &observer, 12, &sessions).unwrap();
    let ds = Dataset::read(&[sessions]).unwrap();
    // The model's Q (k = 1) as `predict` would hand it to the calibration.
    let prediction = Prediction {
        job: "known-k".into(),
        manifest_path: dir.path().join("manifest.json"),
        display: DisplaySpec::default(),
        pixels_per_degree: 39.5,
        k: 1.0,
        decision: analysis::predict::stage_choice::StageChoice::for_layout(None),
        stimuli: rows(1.0)
            .into_iter()
            .map(|row| StimulusPrediction {
                q_frames: vec![row.q],
                row,
                seconds: 0.0,
            })
            .collect(),
        conditions: Vec::new(),
        wall_seconds: 0.0,
    };
    let c = calibrate(cells(&prediction, &ds).unwrap());
    let [lo, hi] = c.k_interval.unwrap();
    eprintln!("k = {} ({lo} to {hi}), truth {k_true}", c.k);
    // 2304 trials: the curvature interval is about +-6%; it must hold the truth, and the fit
    // must be within 15% (more than 4 of the interval's standard errors).
    assert!(lo <= k_true && k_true <= hi, "{} [{lo}, {hi}]", c.k);
    assert!((c.k / k_true - 1.0).abs() < 0.15);
    assert_eq!(c.held_out.len(), 6);
    for h in &c.held_out {
        assert!(
            h.log_likelihood_per_trial > h.guess_log_likelihood_per_trial,
            "{h:?}"
        );
    }
    assert!(Path::new(&csv).is_file());
}
