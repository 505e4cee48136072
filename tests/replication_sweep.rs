//! The replication sweep is one table, `scenes/replication/sweep.txt`, and
//! `bench/replication_sets.sh` writes its jobs and designs. These tests run the script: every
//! set it writes loads as a job and a design that plays exactly that job's stimuli, the stimuli
//! are the ones the published numbers of `docs/replication.md` were measured on (pinned), and a
//! malformed table is refused by line and column with nothing written.

use renderer::digest::sha256_hex;
use renderer::job::{Job, expand};
use serde_json::Value;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// `bash bench/replication_sets.sh ARGS...` with `SWEEP` set when given.
fn sets(args: &[&str], sweep: Option<&Path>) -> Output {
    let mut c = Command::new("bash");
    c.arg(Path::new(ROOT).join("bench/replication_sets.sh"))
        .args(args);
    if let Some(s) = sweep {
        c.env("SWEEP", s);
    }
    c.output().expect("bash runs")
}

fn lines(o: &Output) -> Vec<String> {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout)
        .lines()
        .map(str::to_string)
        .collect()
}

fn json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Written sets: (name, job file, design file).
fn write_all(out: &Path) -> Vec<(String, PathBuf, PathBuf)> {
    let names = lines(&sets(&[out.to_str().unwrap()], None));
    names
        .into_iter()
        .map(|n| {
            let dir = out.join(&n);
            (n, dir.join("job.json"), dir.join("design.json"))
        })
        .collect()
}

/// What decides a set's stimuli: per stimulus its id, seed and reference; the scene files (from
/// `scenes/`), the size, frames and scopes the job overrides.
fn stimuli_text(name: &str, job: &Job, overrides: &Value) -> String {
    let scenes = Path::new(ROOT).join("scenes").canonicalize().unwrap();
    let mut t = format!("{name} {overrides}");
    for s in &job.scenes {
        let path = s.path.canonicalize().unwrap();
        write!(t, " {}", path.strip_prefix(&scenes).unwrap().display()).unwrap();
    }
    t.push('\n');
    for s in expand(job) {
        writeln!(t, "  {} {} {:?}", s.id, s.seed, s.reference_id).unwrap();
    }
    t
}

/// The sweep's stimuli as of the renders behind `docs/replication.md` (proven equal, id for id
/// and frame for frame, to the hand-written jobs it replaced). A change here re-renders the
/// replication: update the pin only with its numbers.
const PINNED: &str = "82aefc208d5541599c28b3f99eb4f2dbe81ec4e743666fdcefc5408593e41535";

#[test]
fn every_set_is_a_job_and_the_design_that_plays_it() {
    let dir = tempfile::tempdir().unwrap();
    let written = write_all(dir.path());
    assert_eq!(written.len(), 24, "{written:?}");
    let mut all = String::new();
    for (name, job_file, design_file) in &written {
        let job = Job::load(job_file).unwrap_or_else(|e| panic!("{name}: {e:#}"));
        assert_eq!(&job.name, name);
        experiment::Design::load(design_file).unwrap_or_else(|e| panic!("{name}: {e:#}"));
        let (j, d) = (json(job_file), json(design_file));
        assert_eq!(d["name"], j["name"]);
        let stems: Vec<Value> = job
            .scenes
            .iter()
            .map(|s| Value::from(s.name.clone()))
            .collect();
        assert_eq!(d["factors"]["scenes"], Value::from(stems), "{name}");
        assert_eq!(d["factors"]["point_sets"], j["point_sets"], "{name}");
        assert_eq!(d["factors"]["time_filters"], j["time_filters"], "{name}");
        assert_eq!(d["levels"], j["levels"], "{name}");
        let independent = j["reference"].is_object();
        let reference = if independent {
            "scene_reference"
        } else {
            "highest_level"
        };
        assert_eq!(d["reference"], reference, "{name}");
        // The name says the point sets whenever they are not the thesis's three.
        let sets: Vec<&str> = j["point_sets"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(Value::as_str)
            .collect();
        if sets != ["hammersley", "stratified", "poisson"] {
            assert!(
                name.contains(&sets.join("_")),
                "{name} hides its point sets {sets:?}"
            );
        }
        all += &stimuli_text(name, &job, &j["overrides"]);
    }
    let digest = sha256_hex(all.as_bytes());
    assert_eq!(digest, PINNED, "the sweep's stimuli changed:\n{all}");
}

#[test]
fn a_question_selects_its_sets_and_rows_name_them() {
    let dir = tempfile::tempdir().unwrap();
    let hold_out = lines(&sets(&[dir.path().to_str().unwrap(), "hold-out"], None));
    assert_eq!(hold_out.len(), 8, "{hold_out:?}");
    let written: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(written.len(), 8);
    let rows = lines(&sets(&["--rows"], None));
    assert_eq!(rows.len(), 24);
    // f105 was rendered stratified-only under a name that did not say so; the table says it.
    assert!(
        rows.iter()
            .any(|r| r.starts_with("thesis_f105_stratified 105 plane,spheres stratified "))
    );
}

#[test]
fn a_malformed_table_is_refused_by_line_and_column_and_nothing_is_written() {
    let good = "93 plane,spheres stratified thesis frame highest_level distance";
    let cases = [
        (
            "93 plane stratified thesis frames highest_level sky",
            ":2: `shifts` is `frames`",
        ),
        (
            "93 plane stratified thesis frame highest_level pilot",
            ":2: `for` names `pilot`",
        ),
        (
            "93 plane stratified nowhere frame highest_level sky",
            ":2: `scenes_from` nowhere",
        ),
        (
            "93 cube stratified thesis frame highest_level sky",
            ":2: `scenes` is `cube`",
        ),
        (
            "96-91 plane stratified thesis frame highest_level sky",
            ":2: `frames` 96-91",
        ),
        (
            "93 plane stratified thesis frame highest_level",
            ":2: 7 columns expected",
        ),
        (
            "93 plane,spheres stratified thesis frame highest_level sky",
            ":2: the same settings as line 1",
        ),
    ];
    for (bad, want) in cases {
        let dir = tempfile::tempdir().unwrap();
        let table = dir.path().join("sweep.txt");
        std::fs::write(&table, format!("{good}\n{bad}\n")).unwrap();
        let out = dir.path().join("sets");
        let o = sets(&[out.to_str().unwrap()], Some(&table));
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(want), "{bad}: {err}");
        assert!(!out.exists(), "{bad}: a set was written");
    }
}

#[test]
fn the_replication_table_reads_the_sweep() {
    // Nothing rendered: every row prints, each "not rendered" (no blurlab or jq run).
    let dir = tempfile::tempdir().unwrap();
    let o = Command::new("bash")
        .arg(Path::new(ROOT).join("bench/replication_table.sh"))
        .arg(dir.path())
        .output()
        .unwrap();
    let text = lines(&o).join("\n");
    let rows: Vec<&str> = text
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| row"))
        .collect();
    assert_eq!(rows.len(), 21, "{text}");
    for label in [
        "pooled over frames 20/93/105/150/190",
        "real sky, 0.7 m, frame 150",
        "shifts per sequence, 30 fps, 2 loops",
        "reading 'half angle fov'",
    ] {
        assert!(
            rows.iter()
                .any(|r| r.contains(label) && r.contains("not rendered")),
            "{label}:\n{text}"
        );
    }
}
