//! The `analyze` command on real log files: a thesis-size simulated study end to end, and the
//! refusals (mixed designs, corrupt lines, unknown formats, empty input).

mod common;

use analysis::analyze::{AnalyzeOptions, run_report};
use analysis::psychometric::LapseMode;
use analysis::sigmoid::Sigmoid;
use analysis::simulate::StudySpec;
use analysis::ttest::TestKind;
use std::path::{Path, PathBuf};

/// What the `analyze` command runs (without its summary on stderr).
fn run(a: AnalyzeOptions) -> anyhow::Result<()> {
    run_report(&a).map(drop)
}

fn args(inputs: Vec<PathBuf>, out: &Path) -> AnalyzeOptions {
    AnalyzeOptions {
        bootstrap: 1000,
        seed: 5,
        ..AnalyzeOptions::new(inputs, out.to_path_buf())
    }
}

#[test]
fn library_defaults_are_the_command_line_defaults() {
    let a = AnalyzeOptions::new(vec!["a".into(), "b".into()], "out".into());
    assert_eq!(a.inputs, vec![PathBuf::from("a"), PathBuf::from("b")]);
    assert_eq!(a.out, PathBuf::from("out"));
    assert_eq!(
        (a.target, a.bootstrap, a.seed, a.alpha),
        (0.75, 2000, 1, 0.05)
    );
    assert_eq!(
        (a.sigmoid, a.lapse, a.test),
        (Sigmoid::Logistic, LapseMode::Fixed, TestKind::Paired)
    );
    assert_eq!((a.levels, a.scene_levels), (vec![27, 64, 125], vec![216]));
    // A path that looks like an option is still an input; no input is an error of the run,
    // not a panic.
    let odd = AnalyzeOptions::new(vec!["--out".into()], "o".into());
    assert_eq!(odd.inputs, vec![PathBuf::from("--out")]);
    let none = AnalyzeOptions::new(vec![], "o".into());
    assert!(run(none).unwrap_err().to_string().contains("no input"));
}

#[test]
fn thesis_size_study_produces_every_report_file_without_nan() {
    let dir = tempfile::tempdir().unwrap();
    let sessions = dir.path().join("sessions");
    let out = dir.path().join("report");
    StudySpec::thesis()
        .write_logs(&sessions, "design-1")
        .unwrap();
    let report = run_report(&args(vec![sessions], &out)).unwrap();
    // The short summary a caller (the umbrella `demo`) prints: scenes then point sets.
    let summary = report.summary();
    let labels: Vec<&str> = summary.rows.iter().map(|r| r.label.as_str()).collect();
    assert_eq!(
        labels,
        ["plane", "spheres", "hammersley", "poisson", "stratified"]
    );
    assert_eq!(summary.tests, 13);
    let text = summary.to_string();
    assert!(
        text.contains("plane") && text.contains("t-tests:"),
        "{text}"
    );

    common::assert_report_is_finite(&out);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(json["format"], "blurlab-report/1");
    // 6 conditions + 2 scenes + 3 point sets pooled, each with 12 subjects.
    assert_eq!(json["jnd"].as_array().unwrap().len(), 11 * 13);
    // Tables 1 and 2: 1 scene pair x 4 levels, 3 point-set pairs x 3 levels.
    let tests = json["ttests"].as_array().unwrap();
    assert_eq!(tests.len(), 4 + 9);
    // Every paired test pairs the 12 subjects, df = 11.
    assert!(tests.iter().all(|t| t["df"] == 11.0), "{tests:?}");

    // The plane scene's pooled JND: the simulation's threshold is 40 spp per point set with
    // subject offsets of +-30% (uniform in ln spp), so the pooled threshold is near 40; the
    // interval must hold it and be a finite range inside the tested levels.
    let plane = json["jnd"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["grouping"] == "scene" && r["label"] == "plane" && r["subject"] == "pooled")
        .unwrap();
    let lo = plane["ci_lower_spp"].as_f64().unwrap();
    let hi = plane["ci_upper_spp"].as_f64().unwrap();
    let jnd = plane["threshold_spp"].as_f64().unwrap();
    assert!(lo < jnd && jnd < hi && 8.0 < lo && hi < 216.0, "{plane}");
    // The spheres scene (100 spp) is harder to tell from the reference than the plane (40 spp):
    // the simulated per-subject difference in proportion correct is 0.12-0.17 at 27, 64 and
    // 125 spp with a subject-level SD of about 0.19 (12 trials per subject and level), so each
    // t has an expected value near -3: the sign must come out negative at all three levels
    // (each wrong with probability ~0.1%), and at least one must reach p < 0.05.
    let scene_rows: Vec<_> = tests
        .iter()
        .filter(|t| t["family"] == "scene" && [27, 64, 125].contains(&t["level"].as_u64().unwrap()))
        .collect();
    assert!(
        scene_rows.iter().all(|t| t["t"].as_f64().unwrap() < 0.0),
        "{scene_rows:?}"
    );
    assert!(
        scene_rows.iter().any(|t| t["significant"] == true),
        "{scene_rows:?}"
    );

    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(md.contains("Between scenes (thesis Table 1)"));
    for fig in [
        "scene_plane",
        "point_set_hammersley",
        "scene_overlaid",
        "point_set_overlaid",
    ] {
        let svg = std::fs::read_to_string(out.join(format!("figures/{fig}.svg"))).unwrap();
        assert!(svg.contains("<svg"), "{fig}");
        let png = std::fs::read(out.join(format!("figures/{fig}.png"))).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n", "{fig}");
        assert!(md.contains(&format!("figures/{fig}.svg")));
    }
    // No temporary files left behind.
    for e in std::fs::read_dir(out.join("figures")).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!name.starts_with('.'), "{name}");
    }
}

#[test]
fn mixed_designs_are_refused_naming_both_files() {
    let dir = tempfile::tempdir().unwrap();
    let spec = StudySpec {
        subjects: 1,
        ..StudySpec::thesis()
    };
    let a = spec.write_logs(&dir.path().join("a"), "hash-a").unwrap();
    let b = spec.write_logs(&dir.path().join("b"), "hash-b").unwrap();
    let err = run(args(
        vec![a[0].clone(), b[0].clone()],
        &dir.path().join("out"),
    ))
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("design_hash") && err.contains("hash-a") && err.contains("hash-b"),
        "{err}"
    );
    assert!(
        err.contains("a/s01.jsonl") && err.contains("b/s01.jsonl"),
        "{err}"
    );
    assert!(!dir.path().join("out/jnd.csv").exists());
}

#[test]
fn corrupt_lines_and_unknown_formats_are_reported_with_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let spec = StudySpec {
        subjects: 1,
        ..StudySpec::thesis()
    };
    let logs = spec.write_logs(dir.path(), "h").unwrap();
    let text = std::fs::read_to_string(&logs[0]).unwrap();
    let mut lines: Vec<&str> = text.lines().collect();
    lines[5] = "{\"kind\":\"trial\",\"index\":oops}";
    std::fs::write(&logs[0], lines.join("\n") + "\n").unwrap();
    let err = run(args(logs.clone(), &dir.path().join("out")))
        .unwrap_err()
        .to_string();
    assert!(err.contains("s01.jsonl:6"), "{err}");

    let unknown = text.replacen("blurlab-session/1", "blurlab-session/9", 1);
    std::fs::write(&logs[0], unknown).unwrap();
    let err = format!(
        "{:#}",
        run(args(logs, &dir.path().join("out"))).unwrap_err()
    );
    assert!(
        err.contains("blurlab-session/9") && err.contains("format"),
        "{err}"
    );
}

#[test]
fn a_log_given_twice_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let spec = StudySpec {
        subjects: 1,
        ..StudySpec::thesis()
    };
    let logs = spec.write_logs(&dir.path().join("sessions"), "h").unwrap();
    let copy = dir.path().join("sessions/s01-copy.jsonl");
    std::fs::copy(&logs[0], &copy).unwrap();
    let err = run(args(
        vec![dir.path().join("sessions")],
        &dir.path().join("out"),
    ))
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("s01-copy.jsonl") && err.contains("s01.jsonl") && err.contains("counted once"),
        "{err}"
    );
}

#[test]
fn one_scene_and_one_point_set_give_an_empty_ttest_table_with_its_header() {
    let dir = tempfile::tempdir().unwrap();
    let spec = StudySpec {
        subjects: 3,
        scenes: vec![("plane".into(), 40.0)],
        point_sets: vec![(renderer::condition::PointSetKind::Sobol, 1.0)],
        ..StudySpec::thesis()
    };
    spec.write_logs(&dir.path().join("s"), "h").unwrap();
    let out = dir.path().join("out");
    run(args(vec![dir.path().join("s")], &out)).unwrap();
    let text = std::fs::read_to_string(out.join("ttests.csv")).unwrap();
    assert_eq!(text.lines().count(), 1, "{text}");
    assert!(text.starts_with("family,a,b,level,test,"), "{text}");
}

#[test]
fn empty_inputs_and_bad_settings_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let err = run(args(
        vec![dir.path().to_path_buf()],
        &dir.path().join("out"),
    ))
    .unwrap_err()
    .to_string();
    assert!(err.contains("no session logs"), "{err}");
    let mut a = args(vec![dir.path().to_path_buf()], &dir.path().join("out"));
    a.target = 0.5;
    assert!(run(a).unwrap_err().to_string().contains("--target"));
    let mut a = args(vec![dir.path().to_path_buf()], &dir.path().join("out"));
    a.bootstrap = 10;
    assert!(run(a).unwrap_err().to_string().contains("--bootstrap"));
}

#[test]
fn a_design_orders_the_pairs_and_must_match_the_logs() {
    let dir = tempfile::tempdir().unwrap();
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let design_path = repo.join("scenes/thesis/design.json");
    let design = experiment::Design::load(&design_path).unwrap();
    let spec = StudySpec {
        subjects: 3,
        ..StudySpec::thesis()
    };
    let sessions = dir.path().join("sessions");
    spec.write_logs(&sessions, &design.hash).unwrap();
    let a = AnalyzeOptions {
        design: Some(design_path.clone()),
        ..args(vec![sessions.clone()], &dir.path().join("out"))
    };
    let ds = analysis::data::Dataset::read(&a.inputs).unwrap();
    let s = a.settings_for(&ds, Some(&design)).unwrap();
    // The design's point-set order (hammersley, stratified, poisson), not the alphabet.
    let pairs: Vec<(String, String)> = analysis::comparisons::compare(&ds, &s.comparisons)
        .into_iter()
        .filter(|c| c.family == analysis::data::Grouping::PointSet && c.level == 27)
        .map(|c| (c.a, c.b))
        .collect();
    let want = [
        ("hammersley", "stratified"),
        ("hammersley", "poisson"),
        ("stratified", "poisson"),
    ];
    assert_eq!(pairs, want.map(|(x, y)| (x.to_string(), y.to_string())));
    assert_eq!(s.fit.guess, 0.5);
    // Logs recorded under another design are refused, naming both hashes.
    let other = dir.path().join("other");
    spec.write_logs(&other, "another-hash").unwrap();
    let e = run_report(&AnalyzeOptions {
        design: Some(design_path),
        ..args(vec![other], &dir.path().join("out2"))
    })
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("--design") && e.contains(&design.hash) && e.contains("another-hash"),
        "{e}"
    );
}
