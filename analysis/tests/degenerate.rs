//! A whole study of degenerate data through the report: every subject perfect in one scene
//! (all correct), exactly at chance in another, non-monotone pooled data in a third, and two
//! point sets with identical data. Nothing may come out as NaN, infinity or an invented number:
//! thresholds are out of range, t-tests undefined with their reason, the misfit flagged.

mod common;

use analysis::data::{Dataset, Observation};
use analysis::jnd::Threshold;
use analysis::report::{Settings, analyze};

const LEVELS: [u32; 8] = [1, 8, 27, 64, 125, 216, 343, 512];

/// Correct answers out of 4 per subject at each level, by scene.
fn correct(scene: &str, level_index: usize, subject: usize) -> u32 {
    match scene {
        "perfect" => 4,
        "chance" => 2,
        // Pooled over subjects: 1.0, 0.5, 1.0, 0.5, ... rising and falling with the level.
        "zigzag" => {
            if level_index.is_multiple_of(2) {
                4
            } else {
                2 + (subject % 2) as u32
            }
        }
        _ => unreachable!(),
    }
}

fn observations() -> Vec<Observation> {
    let mut obs = Vec::new();
    for subject in 0..6 {
        for scene in ["perfect", "chance", "zigzag"] {
            for point_set in ["halton", "sobol"] {
                for (i, &level) in LEVELS.iter().enumerate() {
                    let k = correct(scene, i, subject);
                    for trial in 0..4 {
                        obs.push(Observation {
                            subject: format!("s{subject}"),
                            scene: scene.into(),
                            point_set: point_set.into(),
                            time_filter: "box".into(),
                            level,
                            correct: trial < k,
                        });
                    }
                }
            }
        }
    }
    obs
}

fn settings() -> Settings {
    let mut s = Settings::default();
    // Fewer resamples than the CLI's minimum keep the test fast; the bootstrap p of the
    // misfit below is (1 + 0) / (1 + 200) whatever the count.
    s.bootstrap.resamples = 200;
    s.bootstrap.seed = 3;
    s
}

#[test]
fn degenerate_study_reports_honestly_and_finitely() {
    let ds = Dataset::from_observations(&observations());
    let report = analyze(&ds, &settings());
    let group = |label: &str| report.groups.iter().find(|g| g.key.label == label).unwrap();

    // All correct: a step above the range, its interval too; every subject likewise.
    let perfect = group("perfect");
    assert_eq!(perfect.threshold, Threshold::AboveRange { bound: 512 });
    assert_eq!(perfect.empirical, Threshold::AboveRange { bound: 512 });
    assert_eq!(
        perfect.bootstrap.ci_lower.as_ref().unwrap().kind(),
        "above_range"
    );
    assert!(!perfect.poor_fit);
    assert!(
        perfect
            .subjects
            .iter()
            .all(|s| s.threshold == perfect.threshold)
    );
    // Exactly at chance: below the range.
    let chance = group("chance");
    assert_eq!(chance.threshold, Threshold::BelowRange { bound: 1 });
    assert_eq!(chance.empirical, Threshold::BelowRange { bound: 1 });
    // Non-monotone: fitted, flagged as a poor fit (every replicate of a monotone function
    // fits better than the zigzag: deviance p = 1 / 201).
    let zigzag = group("zigzag");
    assert!(zigzag.poor_fit, "{:?}", zigzag.bootstrap);
    assert!(zigzag.bootstrap.deviance_p < 0.05);

    // Identical point sets, and scene differences constant over subjects (everywhere except
    // the zigzag's odd levels, 64 and 216 spp, where subjects differ): undefined with the
    // reason, outside Holm's family. The others are ordinary finite tests.
    for c in &report.comparisons {
        let varies = (c.a == "zigzag" || c.b == "zigzag") && [64, 216].contains(&c.level);
        match &c.test.result {
            Err(reason) => {
                assert!(!varies && reason.contains("zero variance"), "{c:?}");
                assert_eq!((c.p_holm, c.significant), (None, None));
            }
            Ok(st) => {
                assert!(varies, "{c:?}");
                assert!(st.t.is_finite() && st.p > 0.0 && st.p <= 1.0);
                assert!(c.p_holm.unwrap() >= st.p);
            }
        }
    }
    let perfect_vs_chance = report
        .comparisons
        .iter()
        .find(|c| c.a == "chance" && c.b == "perfect" && c.level == 64)
        .unwrap();
    let reason = perfect_vs_chance.test.result.as_ref().unwrap_err();
    assert!(
        reason.contains("difference is -0.5, so t is infinite"),
        "{reason}"
    );

    // The files: no NaN or infinity anywhere, the flag in the tables, the summary readable.
    let dir = tempfile::tempdir().unwrap();
    analysis::output::write(&report, dir.path()).unwrap();
    common::assert_report_is_finite(dir.path());
    let md = std::fs::read_to_string(dir.path().join("report.md")).unwrap();
    assert!(md.contains("| scene | zigzag |") && md.contains("**poor fit**"));
    let jnd = std::fs::read_to_string(dir.path().join("jnd.csv")).unwrap();
    assert!(
        jnd.lines()
            .any(|l| l.starts_with("scene,zigzag,pooled,") && l.ends_with(",true,384"))
    );
    let summary = report.summary().to_string();
    assert!(
        summary.contains("> 512") && summary.contains("< 1"),
        "{summary}"
    );
    assert!(summary.contains("of 4 significant"), "{summary}");
}
