//! The `render job` command end to end on synthetic scenes: a kill mid-run and a rerun give the
//! same stimulus set as one uninterrupted run; so do the generated Slurm array script's body
//! run locally for every array index, and shards fanned out with xargs.

mod support;

use renderer::manifest::Manifest;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use support::{render, s};

const RENDER: &str = env!("CARGO_BIN_EXE_render");

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
    let mut child = Command::new(RENDER)
        .args(["job", s(&job), "--out", s(&out), "--no-progress"])
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
        "seq 1 4 | xargs -P 2 -I{{}} '{RENDER}' job '{}' --out '{}' --shard {{}}/4 \
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
