//! The job runner on a cheap analytic scene (`SyntheticSource`, sampled through the real
//! sampler): manifest contents, resume after an interruption, shards whose union equals the
//! single-machine run byte for byte, and refusal to mix frames of a changed job.

use renderer::job::source::{FrameSource, SyntheticSource};
use renderer::job::{Finalize, Job, RunOptions, Shard, run_with_sources};
use renderer::manifest::Manifest;
use renderer::progress::NoProgress;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

#[path = "support/progress.rs"]
mod recorder;
use recorder::Recorder;

const JOB: &str = r#"{
  "format": "blurlab-job/1",
  "name": "tiny",
  "scenes": ["alpha.json", "beta.json"],
  "levels": [1, 4, 16],
  "point_sets": ["random"],
  "time_filters": ["box"],
  "reference": {"spp": 256},
  "seed": 11,
  "frames_per_unit": 2
}"#;

struct Fixture {
    dir: tempfile::TempDir,
    job: Job,
}

fn fixture(job_text: &str) -> Fixture {
    let dir = tempfile::tempdir().unwrap();
    for s in ["alpha", "beta"] {
        std::fs::write(
            dir.path().join(format!("{s}.json")),
            format!("{{\"s\": \"{s}\"}}"),
        )
        .unwrap();
    }
    let path = dir.path().join("tiny.json");
    std::fs::write(&path, job_text).unwrap();
    let job = Job::load(&path).unwrap();
    Fixture { dir, job }
}

fn sources() -> Vec<Box<dyn FrameSource>> {
    vec![
        Box::new(SyntheticSource::new(12, 8, 5)),
        Box::new(SyntheticSource {
            speed: 7.0,
            ..SyntheticSource::new(10, 6, 3)
        }),
    ]
}

/// Every file under `dir` except frame records (they hold wall-clock seconds) and the manifest.
fn frame_files(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "png" || x == "exr") {
                out.insert(
                    p.strip_prefix(dir).unwrap().to_path_buf(),
                    std::fs::read(&p).unwrap(),
                );
            }
        }
    }
    out
}

/// The manifest without render seconds (the one measured, non-reproducible field).
fn without_seconds(mut m: Manifest) -> Manifest {
    for s in &mut m.stimuli {
        s.render_seconds = 0.0;
    }
    m
}

#[test]
fn a_run_writes_every_stimulus_and_a_manifest_that_round_trips() {
    let f = fixture(JOB);
    let out = f.dir.path().join("stimuli");
    let report = run_with_sources(&f.job, &sources(), &RunOptions::new(&out), &NoProgress).unwrap();
    let m = report.manifest.expect("complete run is finalized");
    assert_eq!(m.stimuli.len(), 2 * (1 + 3));
    assert_eq!(report.frames_rendered, 4 * 5 + 4 * 3);
    assert_eq!(Manifest::load(&report.job_dir).unwrap(), m);

    let s = m.get("alpha-random-box-0004").unwrap();
    assert_eq!((s.width, s.height, s.frames, s.spp), (12, 8, 5, 4));
    assert_eq!(s.frame_paths[4], "alpha-random-box-0004/frame_0004.png");
    assert!(s.exr_paths.is_empty());
    let r = m.reference("beta").unwrap();
    assert_eq!(r.exr_paths.len(), 3);
    assert!(r.error.is_none());

    // The content hash is SHA-256 over the PNG files' bytes in order.
    use sha2::Digest;
    let mut h = sha2::Sha256::new();
    for p in &s.frame_paths {
        h.update(std::fs::read(report.job_dir.join(p)).unwrap());
    }
    let hex: String = h.finalize().iter().map(|b| format!("{b:02x}")).collect();
    assert_eq!(s.content_hash, hex);

    // Error falls with sampling density: independent random samples have variance ~ 1/spp,
    // so 16x the samples should give about 4x lower RMSE; demand at least 2x.
    for scene in ["alpha", "beta"] {
        let e = |spp: u32| {
            m.get(&format!("{scene}-random-box-{spp:04}"))
                .unwrap()
                .error
                .clone()
                .unwrap()
        };
        assert!(
            e(1).rmse > 2.0 * e(16).rmse,
            "{scene}: {:?} vs {:?}",
            e(1),
            e(16)
        );
        assert!(e(1).psnr < e(16).psnr);
        assert!(e(1).flip > e(16).flip);
        assert!(e(16).rmse > 0.0);
    }
}

#[test]
fn a_rerun_after_an_interruption_finishes_only_what_is_missing() {
    let f = fixture(JOB);
    let out = f.dir.path().join("stimuli");
    let first = run_with_sources(&f.job, &sources(), &RunOptions::new(&out), &NoProgress).unwrap();
    let before = frame_files(&first.job_dir);
    let m1 = without_seconds(first.manifest.unwrap());

    // What a kill leaves behind: a frame whose record never got written, a half-written
    // temporary file, and (as if written by a non-atomic tool) a truncated PNG and EXR.
    let d = first.job_dir.join("alpha-random-box-0016");
    std::fs::remove_file(d.join("frame_0003.json")).unwrap();
    std::fs::remove_file(d.join("frame_0003.png")).unwrap();
    std::fs::write(d.join(".frame_0003.png.4242.tmp"), b"\x89PNG half").unwrap();
    let png = std::fs::read(d.join("frame_0001.png")).unwrap();
    std::fs::write(d.join("frame_0001.png"), &png[..png.len() / 2]).unwrap();
    let r = first.job_dir.join("beta-reference");
    let exr = std::fs::read(r.join("frame_0002.exr")).unwrap();
    std::fs::write(r.join("frame_0002.exr"), &exr[..100]).unwrap();
    std::fs::remove_file(first.job_dir.join("manifest.json")).unwrap();

    let progress = Recorder::default();
    let second = run_with_sources(&f.job, &sources(), &RunOptions::new(&out), &progress).unwrap();
    assert_eq!(second.frames_rendered, 3);
    // Progress counts the samples of what is left, frame by frame: two frames of alpha at
    // 12 x 8 x 16 spp and one of beta's reference at 10 x 6 x 256.
    let seen = progress.seen();
    let left = 2 * 12 * 8 * 16 + 10 * 6 * 256;
    assert_eq!(seen.totals, [left]);
    assert_eq!(seen.advances.iter().sum::<u64>(), left);
    assert_eq!(seen.messages.len(), 3);
    assert!(
        seen.messages[0].starts_with("frame 1/3 of shard "),
        "{:?}",
        seen.messages
    );
    assert!(seen.finished);
    assert_eq!(second.frames_skipped, 4 * 5 + 4 * 3 - 3);
    assert_eq!(frame_files(&second.job_dir), before);
    assert_eq!(without_seconds(second.manifest.unwrap()), m1);
    assert!(
        !d.join(".frame_0003.png.4242.tmp").exists(),
        "temporary files are cleaned"
    );

    // Nothing missing: a third run renders nothing.
    let third = run_with_sources(&f.job, &sources(), &RunOptions::new(&out), &NoProgress).unwrap();
    assert_eq!(third.frames_rendered, 0);
}

#[test]
fn the_union_of_shards_equals_the_single_run_byte_for_byte() {
    let f = fixture(JOB);
    let whole = run_with_sources(
        &f.job,
        &sources(),
        &RunOptions::new(f.dir.path().join("whole")),
        &NoProgress,
    )
    .unwrap();
    let expected = frame_files(&whole.job_dir);
    let expected_manifest = without_seconds(whole.manifest.unwrap());

    for n in [2u32, 3] {
        let out = f.dir.path().join(format!("sharded{n}"));
        // Highest shard first, so some test frames are rendered before their reference
        // frames and must be measured when the job is finalized.
        for k in (1..=n).rev() {
            let opts = RunOptions {
                shard: Shard { index: k, count: n },
                finalize: Finalize::Never,
                ..RunOptions::new(&out)
            };
            let rep = run_with_sources(&f.job, &sources(), &opts, &NoProgress).unwrap();
            assert!(rep.manifest.is_none());
            if k > 1 {
                assert!(rep.frames_missing > 0);
            }
        }
        let done = run_with_sources(
            &f.job,
            &sources(),
            &RunOptions {
                finalize: Finalize::Only,
                ..RunOptions::new(&out)
            },
            &NoProgress,
        )
        .unwrap();
        assert_eq!(frame_files(&done.job_dir), expected, "{n} shards");
        assert_eq!(without_seconds(done.manifest.unwrap()), expected_manifest);
    }
}

#[test]
fn finalizing_an_incomplete_job_says_what_is_missing() {
    let f = fixture(JOB);
    let out = f.dir.path().join("s");
    let opts = RunOptions {
        shard: Shard { index: 1, count: 4 },
        ..RunOptions::new(&out)
    };
    let rep = run_with_sources(&f.job, &sources(), &opts, &NoProgress).unwrap();
    assert!(rep.manifest.is_none() && rep.frames_missing > 0);
    let err = run_with_sources(
        &f.job,
        &sources(),
        &RunOptions {
            finalize: Finalize::Only,
            ..RunOptions::new(&out)
        },
        &NoProgress,
    )
    .unwrap_err();
    let msg = format!("{err:#}");
    assert!(
        msg.contains("not rendered yet") && msg.contains("shard"),
        "{msg}"
    );
}

#[test]
fn frames_of_a_changed_job_are_never_mixed_in() {
    let f = fixture(JOB);
    let out = f.dir.path().join("s");
    run_with_sources(&f.job, &sources(), &RunOptions::new(&out), &NoProgress).unwrap();
    let changed = fixture(&JOB.replace("\"seed\": 11", "\"seed\": 12"));
    let err = run_with_sources(
        &changed.job,
        &sources(),
        &RunOptions::new(&out),
        &NoProgress,
    )
    .unwrap_err();
    let msg = format!("{err:#}");
    assert!(
        msg.contains("stimulus.json") && msg.contains("different job"),
        "{msg}"
    );
}

#[test]
fn a_dry_run_counts_the_work_and_estimates_time() {
    let f = fixture(JOB);
    let d = renderer::job::dry_run_with_sources(&f.job, &sources(), Shard { index: 1, count: 2 })
        .unwrap();
    assert_eq!((d.stimuli, d.references), (8, 2));
    assert_eq!(d.frames, 4 * 5 + 4 * 3);
    let per_stim = |w: u64, h: u64, frames: u64| w * h * frames * (256 + 1 + 4 + 16);
    assert_eq!(d.samples, per_stim(12, 8, 5) + per_stim(10, 6, 3));
    assert!(d.shard_samples < d.samples);
    assert!(d.estimated_seconds.is_finite() && d.estimated_seconds > 0.0);
    assert!(d.to_string().contains("estimated time"));
}
