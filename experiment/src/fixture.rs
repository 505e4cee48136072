//! Test support: a small real study on disk in milliseconds — synthetic scenes
//! (`blurlab-synthetic/1`), a job rendered by the real job runner into a manifest with PNG
//! frames, and a design file pointing at it. Used by this crate's tests, the GUI tests and the
//! preload measurement. Not part of the library's API: compiled for the crate's unit tests and
//! with the `test-support` feature (which the crate's dev-dependency on itself turns on for its
//! integration tests; other crates can turn it on the same way).

use anyhow::{Context, Result};
use renderer::job::{Job, RunOptions};
use serde_json::json;
use std::path::{Path, PathBuf};

/// What to build.
#[derive(Clone, Debug)]
pub struct StudySpec {
    /// Job and design name.
    pub name: String,
    pub scenes: Vec<String>,
    pub point_sets: Vec<String>,
    pub time_filters: Vec<String>,
    pub levels: Vec<u32>,
    pub reference_spp: u32,
    pub width: u32,
    pub height: u32,
    pub frames: u32,
    pub fps: f64,
    /// Design fields set over the generated ones (`repeats`, `playback`, `practice`, ...).
    pub design: serde_json::Value,
}

impl StudySpec {
    /// Two scenes, two point sets, one time filter, levels 1 and 4; 24x16 px, 6 frames.
    pub fn tiny() -> Self {
        Self {
            name: "tiny".into(),
            scenes: vec!["alpha".into(), "beta".into()],
            point_sets: vec!["random".into(), "stratified".into()],
            time_filters: vec!["box".into()],
            levels: vec![1, 8],
            reference_spp: 27,
            width: 24,
            height: 16,
            frames: 6,
            fps: 30.0,
            design: json!({"repeats": 2, "practice": {"trials": 2}, "break_every": 4}),
        }
    }
}

/// Files of a built study.
#[derive(Clone, Debug)]
pub struct Study {
    pub root: PathBuf,
    pub design_path: PathBuf,
    /// The job's stimulus folder (holding `manifest.json`).
    pub stimuli_dir: PathBuf,
}

/// Render the spec's stimuli under `root/stimuli/<name>/` and write `root/design.json`.
pub fn write_study(root: &Path, spec: &StudySpec) -> Result<Study> {
    write_study_with_reference(root, spec, json!({"spp": spec.reference_spp}))
}

/// [`write_study`] with the job's `reference` given (e.g. `"highest_level"`; the spec's
/// `reference_spp` is then unused, and the design's `reference` comes from `spec.design`).
pub fn write_study_with_reference(
    root: &Path,
    spec: &StudySpec,
    reference: serde_json::Value,
) -> Result<Study> {
    let scenes_dir = root.join("scenes");
    std::fs::create_dir_all(&scenes_dir)?;
    for (i, scene) in spec.scenes.iter().enumerate() {
        let text = json!({
            "format": "blurlab-synthetic/1",
            "width": spec.width, "height": spec.height, "frames": spec.frames,
            "fps": spec.fps, "speed": 3.0 + 2.0 * i as f64,
        });
        std::fs::write(scenes_dir.join(format!("{scene}.json")), text.to_string())?;
    }
    let job_path = root.join("job.json");
    let job = json!({
        "format": "blurlab-job/1",
        "name": spec.name,
        "scenes": spec.scenes.iter().map(|s| format!("scenes/{s}.json")).collect::<Vec<_>>(),
        "levels": spec.levels,
        "point_sets": spec.point_sets,
        "time_filters": spec.time_filters,
        "reference": reference,
        "seed": 5,
    });
    std::fs::write(&job_path, job.to_string())?;
    let job = Job::load(&job_path)?;
    let opts = RunOptions::new(root.join("stimuli"));
    let report = renderer::job::run(&job, &opts, &renderer::progress::NoProgress)
        .context("rendering the fixture's stimuli")?;
    let mut design = json!({
        "format": "blurlab-design/1",
        "name": spec.name,
        "manifest": format!("stimuli/{}/manifest.json", spec.name),
        "factors": {"scenes": spec.scenes, "point_sets": spec.point_sets,
                    "time_filters": spec.time_filters},
        "levels": spec.levels,
        "seed": {"master": 3},
    });
    if let Some(extra) = spec.design.as_object() {
        for (k, v) in extra {
            design[k] = v.clone();
        }
    }
    let design_path = root.join("design.json");
    std::fs::write(&design_path, serde_json::to_string_pretty(&design)?)?;
    Ok(Study {
        root: root.to_path_buf(),
        design_path,
        stimuli_dir: report.job_dir,
    })
}
