//! Tasks with m alternatives (guess rate 1/m): simulated 3- and 4-alternative data recover
//! their known thresholds within the sampling error derived from the Fisher information; a
//! counts table (the path for data collected elsewhere) takes its guess rate from a design's
//! task; degenerate m-alternative data are reported as the two-alternative cases are.

use analysis::analyze::AnalyzeOptions;
use analysis::bootstrap::{BootstrapSettings, Bound, bootstrap};
use analysis::data::{Curve, Dataset};
use analysis::jnd::{Threshold, empirical_threshold, model_threshold};
use analysis::psychometric::{FitSettings, Model, fit};
use analysis::report::analyze;
use analysis::sigmoid::Sigmoid;
use analysis::simulate::simulate_curve;
use experiment::Design;
use std::path::Path;

const LEVELS: [u32; 8] = [1, 8, 27, 64, 125, 216, 343, 512];

fn truth(m: u32) -> Model {
    Model {
        sigmoid: Sigmoid::Logistic,
        alpha: 40f64.ln(),
        beta: 1.5,
        lapse: 0.0,
        guess: 1.0 / m as f64,
    }
}

/// Standard deviation of the maximum-likelihood alpha with `n` trials per level: the (alpha,
/// alpha) element of the inverse Fisher information of the binomial counts,
/// I = sum_i n / (p (1 - p)) grad p grad p^T, grad p = (1 - g) S (1 - S) (beta, alpha - x).
fn alpha_sd(m: &Model, n: f64) -> f64 {
    let (mut aa, mut ab, mut bb) = (0.0, 0.0, 0.0);
    for &l in &LEVELS {
        let x = (l as f64).ln();
        let s = 1.0 / (1.0 + (-(m.beta * (m.alpha - x))).exp());
        let p = m.guess + (1.0 - m.guess) * s;
        let k = (1.0 - m.guess) * s * (1.0 - s);
        let (da, db) = (k * m.beta, k * (m.alpha - x));
        let w = n / (p * (1.0 - p));
        aa += w * da * da;
        ab += w * da * db;
        bb += w * db * db;
    }
    (bb / (aa * bb - ab * ab)).sqrt()
}

#[test]
fn three_and_four_alternative_data_recover_their_thresholds() {
    // 40 trials per level (10 subjects x 4 repeats, pooled). With the target halfway from the
    // guess rate to 1, the logistic's threshold is alpha itself. Each estimate must lie within
    // 4 standard deviations of the truth (a false alarm in 10 data sets: < 1e-3).
    let n = 40;
    for m in [3, 4] {
        let t = truth(m);
        let target = 0.5 * (1.0 + t.guess);
        let sd = alpha_sd(&t, n as f64);
        for seed in 0..5 {
            let c = simulate_curve(&t, &LEVELS, n, seed, &[m as u64]);
            let f = fit(
                &c,
                &FitSettings {
                    guess: t.guess,
                    ..FitSettings::default()
                },
            );
            let Threshold::Value { spp } = model_threshold(&f, target) else {
                panic!("m = {m}, seed {seed}: {:?}", f.shape);
            };
            assert!(
                (spp.ln() - t.alpha).abs() < 4.0 * sd,
                "m = {m}, seed {seed}: {spp} spp vs 40 (sd {sd} in ln spp)"
            );
            assert!(f.fitted.iter().all(|&p| p >= t.guess && p <= 1.0));
        }
    }
}

#[test]
fn expected_counts_recover_the_parameters_only_with_the_right_guess_rate() {
    // Counts exactly n p(x) (n = 1e8): the MLE is the truth up to the count rounding.
    let n = 100_000_000u32;
    for m in [3, 4] {
        for sigmoid in Sigmoid::ALL {
            let t = Model {
                sigmoid,
                ..truth(m)
            };
            let c = Curve::from_counts(LEVELS.iter().map(|&l| {
                let k = (t.p((l as f64).ln()) * n as f64).round() as u32;
                (l, k, n)
            }));
            let right = fit(
                &c,
                &FitSettings {
                    sigmoid,
                    guess: t.guess,
                    ..FitSettings::default()
                },
            );
            let got = right.model().expect("finite");
            assert!(
                (got.alpha - t.alpha).abs() < 1e-4,
                "{m} {sigmoid:?} {got:?}"
            );
            assert!((got.beta - t.beta).abs() < 1e-4, "{m} {sigmoid:?} {got:?}");
            // The fitter's stated precision (the stress test in `psychometric.rs`): its
            // log-likelihood is within 1e-9 (1 + |ln L|) of the maximum, here ~4e8 in size;
            // the saturated model is the maximum up to the count rounding (~1e-7).
            let bound = 2e-9 * (1.0 + right.log_likelihood.abs());
            assert!(right.deviance < bound, "{m} {sigmoid:?} {}", right.deviance);
            // The two-alternative model cannot go below 0.5, which these data do.
            let wrong = fit(
                &c,
                &FitSettings {
                    sigmoid,
                    ..FitSettings::default()
                },
            );
            assert!(wrong.deviance > 1e6, "{m} {sigmoid:?} {}", wrong.deviance);
        }
    }
}

#[test]
fn degenerate_four_alternative_data_are_out_of_range() {
    let g = FitSettings {
        guess: 0.25,
        ..FitSettings::default()
    };
    // Every level at the guess rate: a step below the range, fitted at 1/4 everywhere.
    let chance = Curve::from_counts(LEVELS.iter().map(|&l| (l, 10, 40)));
    let f = fit(&chance, &g);
    assert_eq!(f.kind(), "step");
    assert!(f.fitted.iter().all(|&p| p == 0.25), "{:?}", f.fitted);
    assert_eq!(
        model_threshold(&f, 0.625),
        Threshold::BelowRange { bound: 1 }
    );
    // The bootstrap draws from the fitted 1/4 and refits with the same guess rate: every
    // replicate is at chance again, so both interval ends lie below the range.
    let b = bootstrap(&f, 1, &boot(100));
    assert_eq!(b.ci_lower, Some(Bound::BelowRange { bound: 1 }));
    assert_eq!(b.ci_upper, Some(Bound::BelowRange { bound: 1 }));
    // For two alternatives the same counts lie below chance: still below range, at 0.5.
    let f2 = fit(&chance, &FitSettings::default());
    assert!(f2.fitted.iter().all(|&p| p == 0.5));
    // All correct: above the range whatever the guess rate.
    let all = Curve::from_counts(LEVELS.iter().map(|&l| (l, 40, 40)));
    let f = fit(&all, &g);
    assert_eq!(
        model_threshold(&f, 0.625),
        Threshold::AboveRange { bound: 512 }
    );
    assert_eq!(
        bootstrap(&f, 1, &boot(100)).ci_lower,
        Some(Bound::AboveRange { bound: 512 })
    );
    // The empirical crossing reads the target only: 4-alternative proportions falling from 1
    // through 0.625 between 27 and 64 spp (0.75 -> 0.5, halfway in ln spp).
    let c = Curve::from_counts([(8, 40, 40), (27, 30, 40), (64, 20, 40), (125, 10, 40)]);
    let Threshold::Value { spp } = empirical_threshold(&c, 0.625) else {
        panic!()
    };
    assert!((spp - (27.0f64 * 64.0).sqrt()).abs() < 1e-9, "{spp}");
}

fn boot(resamples: usize) -> BootstrapSettings {
    BootstrapSettings {
        resamples,
        seed: 3,
        target: 0.625,
        confidence: 0.95,
    }
}

const DESIGN: &str = r#"{
    "format": "blurlab-design/1", "name": "four", "manifest": "none",
    "factors": {"scenes": ["b", "a"], "point_sets": ["sobol"], "time_filters": ["box"]},
    "levels": [1, 8, 27, 64, 125, 216, 343, 512],
    "task": {"alternatives": 4},
    "seed": {"master": 1}
}"#;

/// A counts table of 6 subjects x 2 scenes with 4-alternative observers: scene `a` at 40 spp,
/// scene `b` at 100 spp.
fn write_table(path: &Path) {
    let mut text = String::from("subject,scene,point_set,time_filter,level,correct,trials\n");
    for s in 0..6u64 {
        for (scene, jnd) in [("a", 40f64), ("b", 100.0)] {
            let m = Model {
                alpha: jnd.ln(),
                ..truth(4)
            };
            let c = simulate_curve(&m, &LEVELS, 8, 9, &[s, jnd as u64]);
            for p in &c.points {
                text.push_str(&format!(
                    "s{s},{scene},sobol,box,{},{},{}\n",
                    p.level, p.correct, p.trials
                ));
            }
        }
    }
    std::fs::write(path, text).unwrap();
}

#[test]
fn a_counts_table_takes_its_guess_rate_from_the_design_task() {
    let dir = tempfile::tempdir().unwrap();
    let table = dir.path().join("four.csv");
    write_table(&table);
    let design_path = dir.path().join("four.json");
    std::fs::write(&design_path, DESIGN).unwrap();
    let design = Design::load(&design_path).unwrap();

    let args = AnalyzeOptions {
        design: Some(design_path.clone()),
        ..AnalyzeOptions::new(vec![table.clone()], dir.path().join("out"))
    };
    let ds = Dataset::read(&args.inputs).unwrap();
    assert_eq!((ds.subjects.len(), ds.trials), (6, 6 * 2 * 8 * 8));
    let mut s = args.settings_for(&ds, Some(&design)).unwrap();
    assert_eq!(s.fit.guess, 0.25);
    // The design's factor order: scene b before a, so the pair is b vs a.
    s.bootstrap.resamples = 20;
    let report = analyze(&ds, &s);
    assert_eq!(
        (
            report.comparisons[0].a.as_str(),
            report.comparisons[0].b.as_str()
        ),
        ("b", "a")
    );
    analysis::output::write(&report, &args.out).unwrap();
    let md = std::fs::read_to_string(args.out.join("report.md")).unwrap();
    assert!(md.contains("guess rate g = 0.25"), "{md}");
    // An explicit --guess wins over the design.
    let third = AnalyzeOptions {
        guess: Some(1.0 / 3.0),
        ..args.clone()
    };
    assert_eq!(
        third.settings_for(&ds, Some(&design)).unwrap().fit.guess,
        1.0 / 3.0
    );
    // ... with a warning, since it is not the task's (issue 29); the design's own is silent.
    let w = third.unchecked(&ds, Some(&design));
    assert!(
        w.len() == 1 && w[0].contains("differs from the guess rate 0.25"),
        "{w:?}"
    );
    assert!(args.unchecked(&ds, Some(&design)).is_empty());
    // Without either, a counts table is refused: its task is unknown.
    let bare = AnalyzeOptions::new(vec![table.clone()], dir.path().join("out2"));
    let e = analysis::analyze::run_report(&bare)
        .unwrap_err()
        .to_string();
    assert!(e.contains("--guess") && e.contains("--design"), "{e}");
}

#[test]
fn counts_tables_are_checked_line_by_line() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            "subject,scene,point_set,time_filter,level,correct,trials\ns1,a,p,n,8,5,4\n",
            "t.csv:2",
            "`correct`",
        ),
        (
            "subject,scene,point_set,time_filter,level,correct,trials\ns1,a,p,n,8,1,4\ns1,a,p,n,0,1,4\n",
            "t.csv:3",
            "`level`",
        ),
        (
            "subject,scene,point_set,level,correct,trials\ns1,a,p,8,1,4\n",
            "t.csv:",
            "time_filter",
        ),
        (
            "subject,scene,point_set,time_filter,level,correct,trials\ns1,a,p,n,8,x,4\n",
            "t.csv:2",
            "correct",
        ),
        (
            "subject,scene,point_set,time_filter,level,correct,trials\n",
            "t.csv",
            "no rows with trials",
        ),
    ];
    for (text, at, what) in cases {
        let path = dir.path().join("t.csv");
        std::fs::write(&path, text).unwrap();
        let e = format!(
            "{:#}",
            Dataset::read(std::slice::from_ref(&path)).unwrap_err()
        );
        assert!(e.contains(at) && e.contains(what), "{e}");
    }
    // A counts table and a session log together are refused.
    let log = dir.path().join("s01.jsonl");
    std::fs::write(&log, "").unwrap();
    let e = Dataset::read(&[dir.path().join("t.csv"), log])
        .unwrap_err()
        .to_string();
    assert!(e.contains("one kind of input"), "{e}");
}
