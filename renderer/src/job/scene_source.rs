//! Loading a job's scenes as frame sources, with the job's overrides applied.
//!
//! A scene file names its format. `blurlab-synthetic/1` is the analytic test pattern of
//! [`SyntheticSource`] (fields `width`, `height`, `frames`, `fps`, `speed`, and an optional
//! `sampling` block like a real scene's `settings.sampling`): the whole job
//! pipeline — CLI, resume after a kill, shards, Slurm script — can be exercised end to end in
//! milliseconds with it. `blurlab-scene/1` is a real scene ([`crate::scene`]), rendered by
//! [`SceneSource`]; a file ending in `.scene` is a real scene in the thesis's block text.

use super::source::{FrameSetup, FrameSource, SyntheticSource};
use super::{Job, Overrides, runner};
use crate::assets::Assets;
use crate::film::RenderedFrame;
use crate::sampling::SamplingConfig;
use crate::scene::{SCENE_FORMAT, Scene};
use anyhow::{Context, Result, bail};
use serde::Deserialize;
use std::path::Path;
use std::sync::Arc;

/// Format tag of a synthetic test scene.
pub const SYNTHETIC_FORMAT: &str = "blurlab-synthetic/1";

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SyntheticFile {
    #[allow(dead_code)]
    format: String,
    width: u32,
    height: u32,
    frames: u32,
    #[serde(default = "default_fps")]
    fps: f64,
    #[serde(default = "default_speed")]
    speed: f32,
    #[serde(default)]
    sampling: SamplingConfig,
}

fn default_fps() -> f64 {
    30.0
}
fn default_speed() -> f32 {
    3.0
}

#[derive(Deserialize)]
struct FormatOnly {
    #[serde(default)]
    format: Option<String>,
}

/// A job's scenes as frame sources, and what loading them had to repair.
pub struct Loaded {
    /// One frame source per scene of the job, in order.
    pub sources: Vec<Box<dyn FrameSource>>,
    /// Problems that did not stop loading (repaired environment texels), one line each, for
    /// the command line to show.
    pub warnings: Vec<String>,
}

/// One frame source per scene of the job, in order, reading the job's assets.
pub fn load_sources(job: &Job) -> Result<Loaded> {
    let mut warnings = Vec::new();
    let sources = job
        .scenes
        .iter()
        .map(|s| load_source(&s.path, &job.overrides, &job.assets, &mut warnings))
        .collect::<Result<_>>()?;
    Ok(Loaded { sources, warnings })
}

/// The frame source of one scene file, with the files `assets` names read from the user's
/// copies; the scene's warnings are added to `warnings`.
pub fn load_source(
    path: &Path,
    overrides: &Overrides,
    assets: &Assets,
    warnings: &mut Vec<String>,
) -> Result<Box<dyn FrameSource>> {
    let text = crate::utf8::read(path, "scene file")?;
    if crate::scene::block_format::is_block_scene(path) {
        let scene = Scene::from_text_with(&text, path, assets)?;
        return scene_source(scene, overrides, warnings);
    }
    let head: FormatOnly = crate::json::from_str(&text, path, "JSON scene file")?;
    match head.format.as_deref() {
        Some(SYNTHETIC_FORMAT) => synthetic(&text, path, overrides),
        Some(SCENE_FORMAT) => {
            let scene = Scene::from_text_with(&text, path, assets)?;
            scene_source(scene, overrides, warnings)
        }
        other => bail!(
            "{}: field `format` is {other:?}; expected {SCENE_FORMAT:?} (or \
             {SYNTHETIC_FORMAT:?} for the analytic test pattern)",
            path.display()
        ),
    }
}

fn scene_source(
    scene: Scene,
    overrides: &Overrides,
    warnings: &mut Vec<String>,
) -> Result<Box<dyn FrameSource>> {
    warnings.extend(scene.warnings.iter().cloned());
    Ok(Box::new(SceneSource::new(Arc::new(scene), overrides)?))
}

/// A real scene as a job's frame source, with the job's overrides: size, number of frames, and
/// the scene frame shown as the stimulus's frame 0.
#[derive(Clone, Debug)]
pub struct SceneSource {
    /// The scene at this source's size (sized once here, not per frame: a scene holds its
    /// meshes and environment map).
    scene: Arc<Scene>,
    frames: u32,
    first_frame: u32,
}

impl SceneSource {
    /// Apply `o` to `scene`; stimuli must lie within the scene's animation.
    pub fn new(scene: Arc<Scene>, o: &Overrides) -> Result<Self> {
        let s = &scene.settings;
        let first_frame = o.first_frame.unwrap_or(0);
        let frames = o.frames.unwrap_or(s.frames.saturating_sub(first_frame));
        if frames == 0 || first_frame as u64 + frames as u64 > s.frames as u64 {
            bail!(
                "{}: the job's overrides ask for {frames} frames from scene frame {first_frame}, \
                 but the scene's animation has {} frames (settings.frames); expected \
                 first_frame + frames <= {}",
                scene.path.display(),
                s.frames,
                s.frames
            );
        }
        if o.width == Some(0) || o.height == Some(0) {
            bail!("the job's overrides `width` and `height` must be at least 1");
        }
        let (width, height) = (o.width.unwrap_or(s.width), o.height.unwrap_or(s.height));
        Ok(Self {
            scene: at_size(&scene, width, height),
            frames,
            first_frame,
        })
    }

    /// A stimulus's sampling: the job's point set, spp, time filter and whatever options the
    /// job set, over the scene's own `settings.sampling` ([`SamplingConfig::over`]).
    pub fn sampling(&self, job: &SamplingConfig) -> SamplingConfig {
        job.over(&self.scene.settings.sampling)
    }
}

impl FrameSource for SceneSource {
    fn setup(&self) -> FrameSetup {
        FrameSetup {
            width: self.scene.settings.width,
            height: self.scene.settings.height,
            frames: self.frames,
            fps: self.scene.settings.fps,
        }
    }

    fn render(&self, sampling: &SamplingConfig, seed: u64, frame: u32) -> Result<RenderedFrame> {
        let scene = &self.scene;
        let (film, _) = crate::render::render_frame(
            scene,
            &self.sampling(sampling),
            seed,
            self.first_frame + frame,
            &crate::progress::NoProgress,
        )?;
        Ok(film.develop(scene.settings.exposure))
    }

    fn resized(&self, width: u32, height: u32) -> Result<Box<dyn FrameSource>> {
        Ok(Box::new(Self {
            scene: at_size(&self.scene, width, height),
            ..self.clone()
        }))
    }
}

/// `scene` at `width` x `height`: itself when it has that size, else a copy with that size.
fn at_size(scene: &Arc<Scene>, width: u32, height: u32) -> Arc<Scene> {
    let s = &scene.settings;
    if (s.width, s.height) == (width, height) {
        return Arc::clone(scene);
    }
    let mut sized = (**scene).clone();
    sized.settings.width = width;
    sized.settings.height = height;
    Arc::new(sized)
}

fn synthetic(text: &str, path: &Path, o: &Overrides) -> Result<Box<dyn FrameSource>> {
    let f: SyntheticFile = serde_json::from_str(text)
        .with_context(|| format!("{}: not a valid synthetic scene", path.display()))?;
    if f.width == 0 || f.height == 0 || f.frames == 0 {
        bail!(
            "{}: fields `width`, `height` and `frames` must be at least 1",
            path.display()
        );
    }
    let mut s = SyntheticSource::new(
        o.width.unwrap_or(f.width),
        o.height.unwrap_or(f.height),
        o.frames.unwrap_or(f.frames),
    );
    s.setup.fps = f.fps;
    s.speed = f.speed;
    s.first_frame = o.first_frame.unwrap_or(0);
    s.sampling = f.sampling;
    Ok(Box::new(s))
}

/// Render (this shard of) a job; see [`runner::run_with_sources`]. The report carries the
/// scenes' loading warnings.
pub fn run(
    job: &Job,
    opts: &runner::RunOptions,
    progress: &dyn crate::progress::Progress,
) -> Result<runner::RunReport> {
    let loaded = load_sources(job)?;
    let mut report = runner::run_with_sources(job, &loaded.sources, opts, progress)?;
    report.warnings = loaded.warnings;
    Ok(report)
}

/// Count a job's work and estimate its time; see [`super::dry_run_with_sources`]. The second
/// value holds the scenes' loading warnings.
pub fn dry_run(job: &Job, shard: super::Shard) -> Result<(super::DryRun, Vec<String>)> {
    let loaded = load_sources(job)?;
    let dry = super::dry_run_with_sources(job, &loaded.sources, shard)?;
    Ok((dry, loaded.warnings))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::SamplingConfig;

    #[test]
    fn a_synthetic_scene_s_sampling_block_lies_under_the_stimulus() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.json");
        std::fs::write(
            &path,
            r#"{"format": "blurlab-synthetic/1", "width": 4, "height": 3, "frames": 1,
                "sampling": {"point_set": "sobol", "density": {"temporal": 3}}}"#,
        )
        .unwrap();
        let src = load_source(
            &path,
            &Overrides::default(),
            &Assets::default(),
            &mut vec![],
        )
        .unwrap();
        let job = |spp| SamplingConfig {
            point_set: crate::condition::PointSetKind::Hammersley,
            spp,
            ..Default::default()
        };
        // The scene's density split applies: 9 = 3 x 3 works, 8 does not divide by 3.
        assert!(src.render(&job(9), 1, 0).is_ok());
        let e = format!("{:#}", src.render(&job(8), 1, 0).unwrap_err());
        assert!(e.contains("`density`"), "{e}");
        // Unless the stimulus says otherwise.
        let joint = SamplingConfig {
            density: Some(crate::sampling::Density::Joint),
            ..job(8)
        };
        assert!(src.render(&joint, 1, 0).is_ok());
    }
}
