//! `--preset thesis` on a 12-subject simulated study with two subjects excluded (10 analysed,
//! as the thesis's df imply): every row of Tables 1 and 2 checked against t, df and p computed
//! here from the simulated trials, independently of the analysis crate (own counting, own
//! t statistic, p from statrs' Student t); and the tables' layout against the thesis's
//! (Chapter V: column and row order, captions, degrees of freedom 29 and 19).

mod common;

use analysis::analyze::AnalyzeOptions;
use analysis::data::{Dataset, Observation};
use analysis::report::{Preset, Report, analyze};
use analysis::simulate::StudySpec;
use statrs::distribution::{ContinuousCDF, StudentsT};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

const EXCLUDED: [&str; 2] = ["s03", "s07"];

/// The thesis's tables as printed: the Test column of every row, in order.
const TABLE_1: [&str; 4] = [
    "Plane Scene vs. Spheres Scene, 27 spp",
    "Plane Scene vs. Spheres Scene, 64 spp",
    "Plane Scene vs. Spheres Scene, 125 spp",
    "Plane Scene vs. Spheres Scene, 216 spp",
];
const TABLE_2: [&str; 9] = [
    "Hammersley vs. Stratified Monte Carlo, 27 spp",
    "Hammersley vs. Stratified Monte Carlo, 64 spp",
    "Hammersley vs. Stratified Monte Carlo, 125 spp",
    "Hammersley vs. Poisson, 27 spp",
    "Hammersley vs. Poisson, 64 spp",
    "Hammersley vs. Poisson, 125 spp",
    "Stratified Monte Carlo vs. Poisson, 27 spp",
    "Stratified Monte Carlo vs. Poisson, 64 spp",
    "Stratified Monte Carlo vs. Poisson, 125 spp",
];

/// The study's options, as `blurlab analyze --preset thesis --exclude "s03=fell asleep,s07"
/// --out OUT SESSIONS` gives them.
fn args(sessions: &Path, out: &Path) -> AnalyzeOptions {
    AnalyzeOptions {
        preset: Some(Preset::Thesis),
        exclude: vec!["s03=fell asleep".into(), "s07".into()],
        ..AnalyzeOptions::new(vec![sessions.to_path_buf()], out.to_path_buf())
    }
}

/// The paired t-test over cells, computed here: (t, df, two-sided p).
fn paired(a: &[f64], b: &[f64]) -> (f64, f64, f64) {
    let d: Vec<f64> = a.iter().zip(b).map(|(x, y)| x - y).collect();
    let n = d.len() as f64;
    let mean = d.iter().sum::<f64>() / n;
    let var = d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let t = mean / (var / n).sqrt();
    let df = n - 1.0;
    let p = 2.0 * StudentsT::new(0.0, 1.0, df).unwrap().sf(t.abs());
    (t, df, p)
}

/// Proportion correct per (subject, scene, point set, level), from the simulated trials.
fn cell_proportions(obs: &[Observation]) -> BTreeMap<(String, String, String, u32), f64> {
    let mut counts: BTreeMap<(String, String, String, u32), (u32, u32)> = BTreeMap::new();
    for o in obs {
        let key = (
            o.subject.clone(),
            o.scene.clone(),
            o.point_set.clone(),
            o.level,
        );
        let e = counts.entry(key).or_default();
        e.0 += o.correct as u32;
        e.1 += 1;
    }
    counts
        .into_iter()
        .map(|(k, (c, n))| (k, c as f64 / n as f64))
        .collect()
}

/// The expected rows: (test text, t, df, p), pairs over subject x other-factor cells.
fn expected(spec: &StudySpec) -> Vec<(String, f64, f64, f64)> {
    let obs: Vec<Observation> = spec
        .observations()
        .into_iter()
        .filter(|o| !EXCLUDED.contains(&o.subject.as_str()))
        .collect();
    let p = cell_proportions(&obs);
    let subjects: Vec<String> = (0..spec.subjects)
        .map(|s| spec.subject_name(s))
        .filter(|s| !EXCLUDED.contains(&s.as_str()))
        .collect();
    let mut rows = Vec::new();
    for level in [27, 64, 125, 216] {
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for s in &subjects {
            for ps in ["hammersley", "stratified", "poisson"] {
                a.push(p[&(s.clone(), "plane".into(), ps.into(), level)]);
                b.push(p[&(s.clone(), "spheres".into(), ps.into(), level)]);
            }
        }
        let (t, df, pv) = paired(&a, &b);
        rows.push((TABLE_1[rows.len()].to_string(), t, df, pv));
    }
    let pairs = [
        ("hammersley", "stratified"),
        ("hammersley", "poisson"),
        ("stratified", "poisson"),
    ];
    for (i, (x, y)) in pairs.iter().enumerate() {
        for (j, level) in [27, 64, 125].into_iter().enumerate() {
            let (mut a, mut b) = (Vec::new(), Vec::new());
            for s in &subjects {
                for scene in ["plane", "spheres"] {
                    a.push(p[&(s.clone(), scene.into(), x.to_string(), level)]);
                    b.push(p[&(s.clone(), scene.into(), y.to_string(), level)]);
                }
            }
            let (t, df, pv) = paired(&a, &b);
            rows.push((TABLE_2[3 * i + j].to_string(), t, df, pv));
        }
    }
    rows
}

/// The thesis's simulated study through the command's own path (read, exclude, the preset's
/// settings) with fewer bootstrap resamples than the command allows, to keep the test fast
/// (the tables do not use them); the report and its folder.
fn preset_report(dir: &Path) -> (Report, PathBuf) {
    let sessions = dir.join("sessions");
    let out = dir.join("report");
    StudySpec::thesis()
        .write_logs(&sessions, "design-1")
        .unwrap();
    let a = args(&sessions, &out);
    assert_eq!(a.preset, Some(Preset::Thesis));
    let mut ds = Dataset::read(&a.inputs).unwrap();
    ds.exclude(&a.exclusions()).unwrap();
    let mut settings = a.settings_for(&ds, None).unwrap();
    settings.bootstrap.resamples = 20;
    let report = analyze(&ds, &settings);
    analysis::output::write(&report, &out).unwrap();
    (report, out)
}

#[test]
fn thesis_preset_reproduces_tables_1_and_2_with_df_29_and_19() {
    let dir = tempfile::tempdir().unwrap();
    let (report, out) = preset_report(dir.path());
    common::assert_report_is_finite(&out);

    // Every row against the independent computation.
    let want = expected(&StudySpec::thesis());
    let rows = report.thesis_rows();
    assert_eq!(rows.len(), want.len());
    for (r, (test, t, df, p)) in rows.iter().zip(&want) {
        assert_eq!(&r.test, test);
        let (rt, rdf, rp) = (
            r.t_value.unwrap(),
            r.degrees_of_freedom.unwrap(),
            r.p_value.unwrap(),
        );
        assert_eq!(rdf, *df, "{test}");
        // t: the same arithmetic up to summation order, a few ulps of the terms.
        assert!(
            (rt - t).abs() <= 1e-12 * t.abs().max(1.0),
            "{test}: t {rt} vs {t}"
        );
        // p: statrs' incomplete beta is accurate to about 1e-12 relative here; the analysis's
        // own to a few ulps; 1e-9 leaves room for the difference in t.
        assert!(((rp - p) / p).abs() < 1e-9, "{test}: p {rp} vs {p}");
        assert_eq!(
            r.significant,
            if *p < 0.05 { "Yes" } else { "No" },
            "{test}"
        );
    }
    // 10 subjects: 30 cells per scene (3 point sets each), 20 per point set (2 scenes each).
    assert!(rows[..4].iter().all(|r| r.degrees_of_freedom == Some(29.0)));
    assert!(rows[4..].iter().all(|r| r.degrees_of_freedom == Some(19.0)));
    // The thesis's sign: plane - spheres, negative where the spheres' noise is more visible.
    assert!(
        rows[..2].iter().all(|r| r.t_value.unwrap() < 0.0),
        "{rows:?}"
    );

    // The same rows in thesis_tables.csv, and its column order.
    let csv = std::fs::read_to_string(out.join("thesis_tables.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "table,test,p_value,t_value,significant,degrees_of_freedom,a,b,level,n,undefined_reason"
    );
    let mut reader = csv::Reader::from_reader(csv.as_bytes());
    let parsed: Vec<csv::StringRecord> = reader.records().map(|r| r.unwrap()).collect();
    assert_eq!(parsed.len(), 13);
    for (rec, (test, t, df, p)) in parsed.iter().zip(&want) {
        assert_eq!(&rec[1], test.as_str());
        let num = |i: usize| rec[i].parse::<f64>().unwrap();
        assert!(((num(2) - p) / p).abs() < 1e-9 && (num(3) - t).abs() < 1e-9 && num(5) == *df);
    }
}

#[test]
fn thesis_tables_are_laid_out_as_the_thesis_prints_them() {
    let dir = tempfile::tempdir().unwrap();
    let (_, out) = preset_report(dir.path());
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();

    // Each table: its title, the df line, the header, then its rows in the thesis's order.
    for (n, title, df, rows) in [
        (
            1,
            "Results of t-tests for determining statistical significance between scenes",
            29,
            &TABLE_1[..],
        ),
        (
            2,
            "Results of t-tests for determining statistical significance between point sets",
            19,
            &TABLE_2[..],
        ),
    ] {
        let start = md
            .find(&format!("## Table {n}: {title}\n"))
            .unwrap_or_else(|| panic!("Table {n} missing:\n{md}"));
        let lines: Vec<&str> = md[start..].lines().filter(|l| !l.is_empty()).collect();
        assert_eq!(
            lines[1],
            format!("Results of t test (Degrees of Freedom = {df})")
        );
        assert_eq!(
            lines[2],
            "| Test | p value | t value | Significant (p = 0.05) |"
        );
        assert_eq!(lines[3], "|---|---|---|---|");
        for (i, want) in rows.iter().enumerate() {
            let cells: Vec<&str> = lines[4 + i].split('|').map(str::trim).collect();
            assert_eq!(cells[1], *want, "Table {n} row {i}");
            // p with four decimals (or two significant digits below 1e-4), t with four
            // significant digits, Yes / No.
            assert!(
                cells[2].starts_with("0.") || cells[2].contains('e'),
                "{cells:?}"
            );
            let t: f64 = cells[3].parse().unwrap();
            let digits = cells[3].chars().filter(char::is_ascii_digit).count();
            let leading_zero = t.abs() < 1.0;
            assert_eq!(digits, 4 + leading_zero as usize, "{cells:?}");
            assert!(cells[4] == "Yes" || cells[4] == "No", "{cells:?}");
        }
        // The next line ends the table.
        assert!(
            !lines[4 + rows.len()].starts_with("| "),
            "{}",
            lines[4 + rows.len()]
        );
    }
    // Table 1 comes before Table 2, the JND reading beside the fit before both, and the
    // generic t-test tables are not repeated.
    let t1 = md.find("## Table 1:").unwrap();
    let t2 = md.find("## Table 2:").unwrap();
    let jnd = md
        .find("## JNDs: the thesis's reading beside the fit")
        .unwrap();
    assert!(jnd < t1 && t1 < t2);
    assert!(!md.contains("Between scenes (thesis Table 1)"));
    let plane = md
        .lines()
        .find(|l| l.starts_with("| Plane Scene |"))
        .expect("plane's JND row");
    assert!(plane.contains("roughly 40"), "{plane}");
    // The exclusions, with the reason given.
    assert!(md.contains("- s03: fell asleep (192 main trials)"), "{md}");
    assert!(
        md.contains("- s07: no reason given (192 main trials)"),
        "{md}"
    );
    assert!(md.contains("Preset `thesis`"));
}

#[test]
fn exclusions_are_checked() {
    // (That the options the preset fixes cannot be given beside it is the command line's
    // test: the `blurlab` binary's `cli::analyze`.)
    let dir = tempfile::tempdir().unwrap();
    let sessions = dir.path().join("sessions");
    StudySpec {
        subjects: 3,
        ..StudySpec::thesis()
    }
    .write_logs(&sessions, "h")
    .unwrap();
    let mut ds = Dataset::read(&[sessions]).unwrap();
    let e = ds.exclude(&[("s9".into(), None)]).unwrap_err().to_string();
    assert!(e.contains("\"s9\"") && e.contains("s01, s02, s03"), "{e}");
    let all: Vec<(String, Option<String>)> = ["s01", "s02", "s03"]
        .iter()
        .map(|s| (s.to_string(), None))
        .collect();
    assert!(
        ds.exclude(&all)
            .unwrap_err()
            .to_string()
            .contains("no subject")
    );
    // Excluding a subject removes its trials everywhere.
    let before = ds.trials;
    ds.exclude(&[("s02".into(), Some("tired".into()))]).unwrap();
    assert_eq!(ds.subjects, ["s01", "s03"]);
    assert_eq!(ds.trials, before - 192);
    assert!(ds.groups.iter().all(|g| g.per_subject.len() == 2));
    assert_eq!(ds.excluded[0].reason, "tired");
}
