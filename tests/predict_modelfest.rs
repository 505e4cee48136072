//! The observer against human data: Meese et al. 2007's cross-orientation masking through
//! `blurlab predict validate meese2007` (last test), and ModelFest (analysis/tests/data/modelfest)
//! through the model's pipeline with the committed parameters (pooling::FITTED, shape::FITTED,
//! proportion_correct::DEFAULT_K, the fit of `blurlab predict validate modelfest` on all 43
//! stimuli). A subset keeps CI quick;
//! the full validation's figures are in docs/predict.md.

use analysis::observer::datasets::modelfest::fit::{Fit, Params, d_prime_84, db};
use analysis::observer::datasets::modelfest::{Stimulus, load, response};
use analysis::observer::model::pooling::{FITTED, Grid};
use analysis::observer::model::proportion_correct::DEFAULT_K;
use analysis::observer::model::shape;
use std::path::PathBuf;

fn data() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("analysis/tests/data/modelfest")
}

fn committed() -> Fit {
    Fit {
        params: Params {
            pooling: FITTED,
            shape: shape::FITTED,
        },
        log10_k: DEFAULT_K.log10(),
        rms_log10: f64::NAN,
    }
}

/// The response per unit contrast at the committed parameters.
fn q1(s: &Stimulus) -> f64 {
    response(s, &Grid::one(FITTED), &[shape::FITTED]).unwrap()[0]
}

/// Predicted minus measured log10 sensitivity of each stimulus, at the committed parameters.
fn errors(stimuli: &[&Stimulus]) -> Vec<f64> {
    stimuli
        .iter()
        .map(|s| committed().predict(q1(s)) - s.measured)
        .collect()
}

#[test]
fn the_data_set_loads_whole() {
    let all = load(&data()).unwrap();
    assert_eq!(all.len(), 43);
    assert!(
        all.iter().all(|s| s.observations == 64),
        "16 observers x 4 repeats each"
    );
    assert!(all.iter().all(|s| (s.width, s.height) == (256, 256)));
    // The README's reading of the units: 1.82 for the 1.12 cpd Gabor, 0.57 at 30 cpd.
    assert!((all[0].measured - 1.821).abs() < 1e-3 && (all[9].measured - 0.5675).abs() < 1e-3);
    let err = load(&data().join("stimuli")).unwrap_err();
    assert!(format!("{err:#}").contains("stimuli.json"), "{err:#}");
}

/// One stimulus from each of eight families (low / peak / high frequency Gabors, an elongated
/// Gabor, a subthreshold-summation compound, the smallest and largest Gaussian blob, the
/// noise): their RMS error at the committed parameters, measured when they were committed, may
/// not grow.
#[test]
fn the_validation_error_does_not_grow() {
    let all = load(&data()).unwrap();
    let subset: Vec<&Stimulus> = [1, 6, 10, 15, 22, 26, 29, 35]
        .iter()
        .map(|n| all.iter().find(|s| s.number == *n).unwrap())
        .collect();
    let e = errors(&subset);
    let rms_db = db((e.iter().map(|v| v * v).sum::<f64>() / e.len() as f64).sqrt());
    eprintln!(
        "subset errors (dB): {:?}; RMS {rms_db:.3} dB",
        e.iter().map(|v| db(*v)).collect::<Vec<_>>()
    );
    assert!(
        rms_db <= SUBSET_RMS_DB + 0.05,
        "{rms_db} dB > {SUBSET_RMS_DB}"
    );
    assert!(d_prime_84() > 1.406 && d_prime_84() < 1.407);
}

/// The subset's RMS error (dB) at the committed parameters, as measured by the test above
/// (1.190 dB with the fifth pass's CSF roll-off and frequency scale; 1.58 before).
const SUBSET_RMS_DB: f64 = 1.19;

/// A noise-free border around a real stimulus (the field 1.5 times as wide, at the background
/// luminance) never lowers its predicted visibility: a detector's pooling, not a mean (which
/// gave 1 / 1.5^2 of it).
#[test]
fn a_noise_free_border_never_lowers_a_stimulus_visibility() {
    let all = load(&data()).unwrap();
    for n in [35] {
        let s = all.iter().find(|s| s.number == n).unwrap();
        let mut big = s.clone();
        let side = 3 * s.width / 2;
        big.width = side;
        big.height = side;
        big.contrast = vec![0.0; side * side];
        let off = s.width / 4;
        for y in 0..s.height {
            for x in 0..s.width {
                big.contrast[(y + off) * side + x + off] = s.contrast[y * s.width + x];
            }
        }
        let (q, q_big) = (q1(s), q1(&big));
        // The field's filters are periodic: the noise, which fills its field, wraps around in
        // the small field and not in the big one, which moves Q by about 2e-4 either way.
        assert!(q_big >= q * (1.0 - 1e-3), "{}: {q_big} < {q}", s.name);
    }
}

/// `blurlab predict validate meese2007` on a cut of the committed data (the 7 c/deg series,
/// its unmasked threshold and one masked): the report names each stage, shows the measured
/// elevation, the RMS figures and the cross-orientation weight's fit; a file without a no-mask
/// row is refused by name.
#[test]
fn meese2007_validation_reports_every_stage() {
    let dir = tempfile::tempdir().unwrap();
    let full = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("analysis/tests/data/meese2007/thresholds.csv"),
    )
    .unwrap();
    let lines: Vec<&str> = full.lines().collect();
    let cut: Vec<&str> = [0, 8, 11].iter().map(|&i| lines[i]).collect();
    std::fs::write(dir.path().join("thresholds.csv"), cut.join("\n") + "\n").unwrap();
    let out_file = dir.path().join("meese.md");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_blurlab"))
        .args([
            "predict",
            "validate",
            "meese2007",
            "--no-progress",
            "--cross-weights",
            "0,1",
        ])
        .arg("--out")
        .arg(&out_file)
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report = std::fs::read_to_string(&out_file).unwrap();
    assert_eq!(
        report.trim_end(),
        String::from_utf8_lossy(&out.stdout).trim_end()
    );
    // The measured elevation: 1.54% over 2.56% at a 5.51% mask.
    assert!(
        report.contains("| DJH | 7 | 5.51% | 1.54% | 0.60 |"),
        "{report}"
    );
    assert_eq!(report.matches("| DJH | 7 |").count(), 2, "{report}");
    for stage in [
        "difference |",
        "side-by-side (pooled) |",
        "side-by-side (w = ",
    ] {
        assert!(report.contains(stage), "{stage}: {report}");
    }
    assert!(
        report.contains("elevations (1) | thresholds (2)"),
        "{report}"
    );
    assert!(report.contains("Lowest elevation error: "), "{report}");
    // The fit over the two weights asked for, and its leave-one-out.
    assert!(
        report.contains("| 0 ") && report.contains("| 1 "),
        "{report}"
    );
    let last = report.trim_end().lines().last().unwrap();
    assert!(
        last.starts_with("cross-orientation weight w = ") && last.contains("leave-one-out"),
        "{last}"
    );

    std::fs::write(
        dir.path().join("thresholds.csv"),
        format!("{}\n{}\n", lines[0], lines[9]),
    )
    .unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_blurlab"))
        .args(["predict", "validate", "meese2007", "--no-progress"])
        .arg(dir.path())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("thresholds.csv") && err.contains("0 no-mask"),
        "{err}"
    );
}

/// Against a blank field the side-by-side stage reduces to detection: on ModelFest's largest
/// Gaussian blob (stimulus 26, mostly below 1 c/deg) its Q is the difference stage's within
/// 10%. Split by orientation below the lowest band, the blob spread over the frame and lost a
/// third of Q (ratio 0.64).
#[test]
fn side_by_side_detects_the_large_gaussian_as_the_difference_stage_does() {
    use analysis::observer::datasets::modelfest::response_by_frames_in;
    use analysis::observer::model::decision_stage::DecisionStage;
    let stimuli = load(&data()).unwrap();
    let s = stimuli.iter().find(|s| s.number == 26).unwrap();
    let d = response_by_frames_in(s, FITTED, shape::FITTED, &|f| f).unwrap();
    let o = response_by_frames_in(s, FITTED, shape::FITTED, &|f| {
        f.with_stage(DecisionStage::SideBySide, FITTED.space)
    })
    .unwrap();
    assert!((o / d - 1.0).abs() < 0.1, "ratio {}", o / d);
}

/// The side-by-side stage (orientation channels, docs/predict.md) on ModelFest's 43 stimuli at
/// the difference stage's fitted k, pooling and CSF: prints each stimulus's error and the RMS
/// (0.995 dB on 29 Nov 2026, against the difference stage's 0.95 and the standard observer's
/// 1.13). About 3 CPU-minutes.
#[test]
#[ignore = "measurement (3 CPU-minutes): cargo test --test predict_modelfest oriented -- --ignored --nocapture"]
fn oriented_side_by_side_on_modelfest() {
    use analysis::observer::datasets::modelfest::response_by_frames_in;
    use analysis::observer::model::decision_stage::DecisionStage;
    use rayon::prelude::*;
    let stimuli = load(&data()).unwrap();
    let f = committed();
    let rows: Vec<(f64, f64, f64)> = stimuli
        .par_iter()
        .map(|s| {
            let d = response_by_frames_in(s, FITTED, shape::FITTED, &|f| f).unwrap();
            let o = response_by_frames_in(s, FITTED, shape::FITTED, &|f| {
                f.with_stage(DecisionStage::SideBySide, FITTED.space)
            })
            .unwrap();
            (f.predict(d) - s.measured, f.predict(o) - s.measured, o / d)
        })
        .collect();
    let rms = |k: usize| {
        db((rows.iter().map(|r| [r.0, r.1][k].powi(2)).sum::<f64>() / rows.len() as f64).sqrt())
    };
    for (s, r) in stimuli.iter().zip(&rows) {
        println!(
            "{} {} diff {:.2} dB oriented {:.2} dB ratio {:.3}",
            s.number,
            s.name,
            db(r.0),
            db(r.1),
            r.2
        );
    }
    println!(
        "RMS difference {:.3} dB, oriented side-by-side {:.3} dB",
        rms(0),
        rms(1)
    );
    // One channel reads exactly the difference stage's Q; several mix through beta_c at the
    // local amplitudes rather than at each pixel, which moved Q by 0.85-1.03 on 29 Nov (the
    // Gaussians most). Outside 0.8-1.1 something else changed.
    for (s, r) in stimuli.iter().zip(&rows) {
        assert!(
            r.2 > 0.8 && r.2 < 1.1,
            "{} {}: ratio {}",
            s.number,
            s.name,
            r.2
        );
    }
}
