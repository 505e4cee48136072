//! `blurlab render` end to end: `render job` on synthetic scenes (a kill mid-run and a rerun
//! give the same stimulus set as one uninterrupted run; so do the generated Slurm array
//! script's body run locally for every array index, and shards fanned out with xargs), `render
//! scene` and `render job` on the thesis's Figures 12 and 13, and the flags' limits.

#[path = "../renderer/tests/support/mod.rs"]
mod figure13;

use renderer::manifest::Manifest;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const BLURLAB: &str = env!("CARGO_BIN_EXE_blurlab");

/// Run `blurlab render ARGS`, require success, return its standard output.
fn render(args: &[&str]) -> String {
    let out = Command::new(BLURLAB)
        .arg("render")
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "render {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Run `blurlab render ARGS`, require a usage error, return its standard error.
fn render_err(args: &[&str]) -> String {
    let out = Command::new(BLURLAB)
        .arg("render")
        .args(args)
        .output()
        .unwrap();
    assert!(!out.status.success(), "render {args:?} succeeded");
    assert_eq!(
        out.status.code(),
        Some(2),
        "render {args:?}: not a usage error"
    );
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A path as a command-line argument.
fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A file of the renderer's thesis fixtures (Figures 12 and 13 as printed).
fn read(name: &str) -> String {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("renderer/tests/fixtures/thesis");
    std::fs::read_to_string(dir.join(name)).unwrap()
}

/// A folder holding Figure 13's scene (as `name`) and small stand-ins at the paths it names.
fn figure13_folder(name: &str) -> tempfile::TempDir {
    figure13::figure13_folder(&read("figure13.scene"), name)
}

fn scene(w: u32, h: u32, frames: u32, speed: f32) -> String {
    format!(
        r#"{{"format": "blurlab-synthetic/1", "width": {w}, "height": {h}, "frames": {frames}, "speed": {speed}}}"#
    )
}

/// A folder with two synthetic scenes and a job over them.
fn setup(size: u32, frames: u32, reference_spp: u32) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("a.json"), scene(size, size, frames, 2.0)).unwrap();
    std::fs::write(d.join("b.json"), scene(size, size / 2, frames, 5.0)).unwrap();
    let job = format!(
        r#"{{"format": "blurlab-job/1", "name": "cli", "scenes": ["a.json", "b.json"],
            "levels": [1, 8], "point_sets": ["random"], "time_filters": ["box"],
            "reference": {{"spp": {reference_spp}}}, "seed": 5, "frames_per_unit": 2}}"#
    );
    let path = d.join("job.json");
    std::fs::write(&path, job).unwrap();
    (dir, path)
}

/// PNG and EXR bytes by relative path.
fn frames(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        if e.path().is_dir() {
            for f in std::fs::read_dir(e.path()).unwrap().flatten() {
                let p = f.path();
                if p.extension().is_some_and(|x| x == "png" || x == "exr") {
                    out.insert(
                        p.strip_prefix(dir).unwrap().into(),
                        std::fs::read(&p).unwrap(),
                    );
                }
            }
        }
    }
    out
}

fn manifest(dir: &Path) -> Manifest {
    let mut m = Manifest::load(dir).unwrap();
    for st in &mut m.stimuli {
        st.render_seconds = 0.0;
    }
    m
}

fn assert_same_set(a: &Path, b: &Path) {
    let fa = frames(a);
    assert!(!fa.is_empty());
    assert_eq!(fa, frames(b), "{} vs {}", a.display(), b.display());
    assert_eq!(manifest(a), manifest(b));
}

#[test]
fn a_killed_run_resumes_to_the_same_stimulus_set() {
    let (dir, job) = setup(64, 6, 2048);
    let d = dir.path();
    render(&[
        "job",
        s(&job),
        "--out",
        s(&d.join("whole")),
        "--no-progress",
    ]);

    let out = d.join("killed");
    let mut child = Command::new(BLURLAB)
        .args(["render", "job", s(&job), "--out", s(&out), "--no-progress"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    // Kill it as soon as its first frame is on disk (mid-job, probably mid-frame).
    let first = out.join("cli/a-reference/frame_0000.json");
    let start = Instant::now();
    while !first.exists() && start.elapsed() < Duration::from_secs(60) {
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(
        !out.join("cli/manifest.json").exists(),
        "the run was killed before it finished"
    );
    let log = render(&["job", s(&job), "--out", s(&out), "--no-progress"]);
    assert!(log.contains("already done"), "{log}");
    assert_same_set(&d.join("whole/cli"), &out.join("cli"));
}

#[test]
fn the_slurm_script_body_run_for_every_array_index_equals_a_single_run() {
    let (dir, job) = setup(16, 5, 64);
    let d = dir.path();
    render(&[
        "job",
        s(&job),
        "--out",
        s(&d.join("whole")),
        "--no-progress",
    ]);

    let script = d.join("cli.sbatch");
    let out = d.join("slurm");
    let said = render(&[
        "job",
        s(&job),
        "--out",
        s(&out),
        "--emit-slurm",
        s(&script),
        "--shards",
        "3",
        "--cpus-per-task",
        "1",
    ]);
    assert!(said.contains("sbatch"), "{said}");
    let text = std::fs::read_to_string(&script).unwrap();
    assert!(text.contains("#SBATCH --array=1-3"), "{text}");
    // bash -n: the script parses.
    let check = Command::new("bash")
        .arg("-n")
        .arg(&script)
        .status()
        .unwrap();
    assert!(check.success());
    for k in 1..=3 {
        let st = Command::new("bash")
            .arg(&script)
            .env("SLURM_ARRAY_TASK_ID", k.to_string())
            .stdout(Stdio::null())
            .status()
            .unwrap();
        assert!(st.success(), "array task {k}");
        if k < 3 {
            assert!(!out.join("cli/manifest.json").exists());
        }
    }
    // The last task found the job complete and wrote the manifest.
    assert_same_set(&d.join("whole/cli"), &out.join("cli"));
    // Without an array index the script refuses to run.
    let st = Command::new("bash")
        .arg(&script)
        .env_remove("SLURM_ARRAY_TASK_ID")
        .stderr(Stdio::null())
        .status()
        .unwrap();
    assert!(!st.success());
}

#[test]
fn shards_fanned_out_with_xargs_then_finalized_equal_a_single_run() {
    let (dir, job) = setup(16, 5, 64);
    let d = dir.path();
    render(&[
        "job",
        s(&job),
        "--out",
        s(&d.join("whole")),
        "--no-progress",
    ]);
    let out = d.join("xargs");
    let cmd = format!(
        "seq 1 4 | xargs -P 2 -I{{}} '{BLURLAB}' render job '{}' --out '{}' --shard {{}}/4 \
         --no-progress --no-finalize",
        s(&job),
        s(&out)
    );
    let st = Command::new("sh")
        .arg("-c")
        .arg(&cmd)
        .stdout(Stdio::null())
        .status()
        .unwrap();
    assert!(st.success(), "{cmd}");
    assert!(!out.join("cli/manifest.json").exists());
    render(&["job", s(&job), "--out", s(&out), "--finalize"]);
    assert_same_set(&d.join("whole/cli"), &out.join("cli"));
}

#[test]
fn dry_run_report_and_export_work_from_the_command_line() {
    let (dir, job) = setup(16, 3, 64);
    let d = dir.path();
    let dry = render(&["job", s(&job), "--dry-run"]);
    assert!(
        dry.contains("6 stimuli (2 references), 18 frames") && dry.contains("estimated time"),
        "{dry}"
    );
    let out = d.join("st");
    render(&["job", s(&job), "--out", s(&out), "--no-progress"]);
    let set = out.join("cli");
    render(&["report", s(&set)]);
    assert!(set.join("report/convergence.csv").exists());
    assert!(set.join("report/rmse_vs_spp_a.png").exists());
    render(&["export", s(&set), "--id", "a-random-box-0008"]);
    let y4m = std::fs::read(set.join("videos/a-random-box-0008.y4m")).unwrap();
    let header = b"YUV4MPEG2 W16 H16 F30:1 Ip A1:1 C444 XCOLORRANGE=LIMITED\n";
    assert!(y4m.starts_with(header));
    assert_eq!(y4m.len(), header.len() + 3 * (6 + 3 * 16 * 16));
}

/// The same limits wherever a number enters (`renderer::limits`, docs/limits.md): the command
/// line refuses sizes and sample counts out of range, negative numbers included, with a
/// message saying what was expected (before: an abort allocating 120 GB, or clap's `-- -1`
/// hint).
#[test]
fn command_line_sizes_and_counts_are_bounded() {
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/static.json");
    let out = std::env::temp_dir().join("blurlab-limits-never-written");
    let o = out.to_str().unwrap();
    for (flag, value, expected) in [
        ("--width", "100000", "from 1 to 16384"),
        ("--height", "-5", "from 1 to 16384"),
        ("--spp", "-1", "samples per pixel from 1 to 65536"),
        ("--spp", "1000000", "samples per pixel from 1 to 65536"),
        ("--frames", "-1..1", "frame numbers from 0"),
    ] {
        let err = render_err(&["scene", scene, "--out", o, flag, value]);
        assert!(err.contains(expected), "{flag} {value}: {err}");
        assert!(!err.contains("-- -"), "{flag} {value}: clap's hint: {err}");
    }
    assert!(!out.exists());
}

#[test]
fn render_scene_renders_a_scene_file() {
    let dir = figure13_folder("plane.scene");
    let out = dir.path().join("frames");
    let said = render(&[
        "scene",
        s(&dir.path().join("plane.scene")),
        "--out",
        s(&out),
        "--spp",
        "1",
        "--frames",
        "100..102",
        "--width",
        "8",
        "--height",
        "8",
        "--no-progress",
    ]);
    assert!(said.contains("2 frames of 8x8 at 1 spp"), "{said}");
    for f in [100, 101] {
        assert!(out.join(format!("frame_{f:04}.png")).is_file());
    }
}

/// Figure 12's seven lines beside Figure 13's scene (named after the job), with extension
/// lines that shrink it to 6 x 6 pixels and 2 frames: `render job` renders 48 stimuli, no
/// independent reference, and each condition's 512-spp stimulus is its own reference.
#[test]
fn render_job_renders_figure_12_with_the_highest_level_as_ground_truth() {
    let dir = figure13_folder("plane.scene");
    let job = dir.path().join("plane.job");
    let small = "\n# small for the test\nwidth 6\nheight 6\nframes 2\nfirstframe 3\n";
    std::fs::write(&job, read("figure12.job") + small).unwrap();
    let stimuli = dir.path().join("stimuli");
    let said = render(&["job", s(&job), "--out", s(&stimuli), "--no-progress"]);
    assert!(said.contains("(48 stimuli)"), "{said}");
    let job_dir = stimuli.join("Plane_scene");
    assert_eq!(
        std::fs::read_to_string(job_dir.join("job.job")).unwrap(),
        std::fs::read_to_string(&job).unwrap(),
        "the job file is kept as given"
    );
    let m = Manifest::load(&job_dir).unwrap();
    assert_eq!(m.stimuli.len(), 3 * 2 * 8);
    assert!(m.stimuli.iter().all(|s| !s.reference && s.scene == "plane"));
    for s in &m.stimuli {
        let top = format!("plane-{}-{}-0512", s.point_set, s.time_filter);
        assert_eq!(s.reference_id.as_deref(), Some(top.as_str()), "{}", s.id);
        assert_eq!(s.own_reference(), s.spp == 512, "{}", s.id);
        // Zero error by construction is not recorded; everything else is measured.
        assert_eq!(s.error.is_none(), s.spp == 512, "{}", s.id);
        // References keep linear frames to measure the other levels against.
        assert_eq!(
            s.exr_paths.len(),
            if s.spp == 512 { 2 } else { 0 },
            "{}",
            s.id
        );
    }
    let report = render(&[
        "report",
        s(&job_dir),
        "--out",
        s(&dir.path().join("report")),
    ]);
    assert!(report.contains("convergence.csv"), "{report}");
    let csv = std::fs::read_to_string(dir.path().join("report/convergence.csv")).unwrap();
    let own: Vec<&str> = csv.lines().filter(|l| l.ends_with(",true")).collect();
    assert_eq!(own.len(), 6, "one own reference per condition:\n{csv}");
    assert!(own.iter().all(|l| l.contains(",512,")), "{own:?}");
    let slopes = std::fs::read_to_string(dir.path().join("report/convergence_slopes.csv")).unwrap();
    for line in slopes.lines().skip(1) {
        assert_eq!(
            line.split(',').nth(3),
            Some("7"),
            "fitted on the 7 measured levels: {line}"
        );
    }
}
