//! Stimulus jobs (format `blurlab-job/1`): the thesis's batch job description (Figure 12 —
//! name, sampling levels, point sets, time filters) plus the scenes it applies to, the
//! reference, the master seed and optional overrides. A job expands into one stimulus per
//! scene x point set x time filter x level, plus one independent reference per scene unless
//! the reference is each condition's highest level ([`expand`]); [`runner`] renders them into
//! `stimuli/<job>/`, optionally split into shards ([`shard`]). The thesis's own seven-line text
//! (Figure 12, `.job`) reads into the same [`JobFile`] ([`line_format`]).

pub mod dry_run;
pub mod expand;
pub mod finalize;
pub mod frame_record;
pub mod line_format;
pub mod lock;
pub mod plan;
pub mod runner;
pub mod scene_source;
pub mod shard;
pub mod slurm;
pub mod source;

pub use dry_run::{DryRun, dry_run_with_sources, human_seconds};
pub use expand::{StimulusSpec, expand};
pub use runner::{Finalize, RunOptions, RunReport, run_with_sources};
pub use scene_source::{dry_run, run};
pub use shard::Shard;

use crate::assets::Assets;
use crate::condition::{PointSetKind, TimeFilter};
use crate::sampling::{FrameSampler, SamplingConfig, SamplingOptions};
use crate::text::SourceMap;
use anyhow::{Result, bail};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The format tag every job file carries.
pub const JOB_FORMAT: &str = "blurlab-job/1";

/// Frames per unit of work when a job does not say (see [`shard`]).
pub const DEFAULT_FRAMES_PER_UNIT: u32 = 8;

/// The job file as written on disk.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct JobFile {
    pub format: String,
    /// The job's name; also the name of its folder under `stimuli/`.
    pub name: String,
    /// Scene files, relative to the job file. A scene's name is its file stem.
    pub scenes: Vec<String>,
    /// Sampling levels (samples per pixel) of the test stimuli.
    pub levels: Vec<u32>,
    /// Point sets to compare, e.g. `hammersley`, `stratified`, `poisson`.
    pub point_sets: Vec<PointSetKind>,
    /// Time filters, e.g. `truncated_box`.
    pub time_filters: Vec<TimeFilter>,
    /// What each stimulus is measured against: the highest level of its own point set and time
    /// filter (`"highest_level"`, the thesis's ground truth), or an independent high-density
    /// render per scene (`{"spp": N, ...}`).
    pub reference: ReferenceSpec,
    /// Master seed; a stimulus's seed is `hash(seed, name_id(stimulus id))`.
    pub seed: u64,
    /// Replace these scene settings for every stimulus.
    #[serde(default, skip_serializing_if = "Overrides::is_empty")]
    pub overrides: Overrides,
    /// Frames per unit of work for `--shard` (default 8). Does not change any output.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frames_per_unit: Option<u32>,
}

/// The ground truth each stimulus is measured against.
#[derive(Clone, Debug, PartialEq)]
pub enum ReferenceSpec {
    /// The highest level of the same scene, point set and time filter (JSON
    /// `"highest_level"`): the thesis's "highest sampling density (512 samples per pixel)",
    /// so the highest level's trial shows two identical pairs. Nothing extra is rendered.
    HighestLevel,
    /// One render per scene at its own density (JSON `{"spp": N, "point_set"?, "time_filter"?}`).
    Independent(IndependentReference),
}

/// JSON spelling of [`ReferenceSpec::HighestLevel`].
pub const HIGHEST_LEVEL: &str = "highest_level";

impl Serialize for ReferenceSpec {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        match self {
            ReferenceSpec::HighestLevel => s.serialize_str(HIGHEST_LEVEL),
            ReferenceSpec::Independent(r) => r.serialize(s),
        }
    }
}

impl<'de> Deserialize<'de> for ReferenceSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        use serde::de::Error;
        match serde_json::Value::deserialize(d)? {
            serde_json::Value::String(s) if s == HIGHEST_LEVEL => Ok(ReferenceSpec::HighestLevel),
            // Through the path tracker, so that a bad name inside says where (the outer
            // reader's path stops at `reference`).
            v @ serde_json::Value::Object(_) => serde_path_to_error::deserialize(v)
                .map(ReferenceSpec::Independent)
                .map_err(|e| match e.path().to_string().as_str() {
                    "." | "" => D::Error::custom(e.into_inner()),
                    at => D::Error::custom(format!("in `{at}`: {}", e.into_inner())),
                }),
            other => Err(D::Error::custom(format!(
                "found {other}; expected \"{HIGHEST_LEVEL}\" or an independent reference \
                 {{\"spp\": N, \"point_set\": ..., \"time_filter\": ...}}"
            ))),
        }
    }
}

/// A reference rendered once per scene.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct IndependentReference {
    /// Samples per pixel; should be well above the highest level.
    pub spp: u32,
    /// Point set of the reference (default: the job's first).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point_set: Option<PointSetKind>,
    /// Time filter of the reference (default: the job's first). Stimuli with another filter are
    /// measured against it too, so their error then includes the filters' difference.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time_filter: Option<TimeFilter>,
}

/// Scene settings a job may replace.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Overrides {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width: Option<u32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<u32>,
    /// Number of frames (from `first_frame` on).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frames: Option<u32>,
    /// The scene frame that becomes the stimulus's frame 0 (default 0): a short stimulus can
    /// show the middle of a long animation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub first_frame: Option<u32>,
    /// Also keep 32-bit float EXR frames of every stimulus (references always keep theirs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exr: Option<bool>,
    /// Sampling settings for every stimulus and the reference (spatial filter and sigma,
    /// density split, point set and shift scopes), laid over each scene's `settings.sampling`.
    #[serde(default, skip_serializing_if = "SamplingOptions::is_empty")]
    pub sampling: SamplingOptions,
}

impl Overrides {
    fn is_empty(&self) -> bool {
        *self == Self::default()
    }
}

/// One scene of a job.
#[derive(Clone, Debug, PartialEq)]
pub struct JobScene {
    /// The scene file's stem, used in stimulus ids.
    pub name: String,
    /// Resolved path of the scene file.
    pub path: PathBuf,
}

/// A job's reference, checked.
#[derive(Clone, Debug, PartialEq)]
pub enum Reference {
    /// Each condition's highest level ([`ReferenceSpec::HighestLevel`]).
    HighestLevel,
    /// One render per scene with this sampling (defaults filled in).
    Independent(SamplingConfig),
}

/// A loaded, validated job.
#[derive(Clone, Debug, PartialEq)]
pub struct Job {
    /// Where the job was loaded from (for messages).
    pub path: PathBuf,
    pub name: String,
    pub scenes: Vec<JobScene>,
    pub levels: Vec<u32>,
    pub point_sets: Vec<PointSetKind>,
    pub time_filters: Vec<TimeFilter>,
    pub reference: Reference,
    pub seed: u64,
    pub overrides: Overrides,
    pub frames_per_unit: u32,
    /// The user's copies of files the scenes name (`--asset`; none in a job file): recorded in
    /// each stimulus's stamp and the manifest.
    pub assets: Assets,
}

impl JobFile {
    /// Read a job file, JSON or (by the extension `.job`) the thesis's seven-line text, with
    /// the lines of a text job (for messages).
    pub fn read(path: &Path) -> Result<(Self, Option<SourceMap>)> {
        let text = crate::utf8::read(path, "job file")?;
        if line_format::is_line_job(path) {
            let (file, map) = line_format::read(&text, path)?;
            return Ok((file, Some(map)));
        }
        Ok((crate::json::from_str(&text, path, "job file")?, None))
    }
}

impl Job {
    /// Read and validate a job file (JSON, or the thesis's text by the extension `.job`).
    /// Errors name the file, the field (or line and key) and what was expected.
    pub fn load(path: &Path) -> Result<Self> {
        Self::load_with_scenes(path, &[])
    }

    /// [`Job::load`], with the job's scenes replaced by `scenes` unless it is empty (the
    /// `--scene` option; paths relative to the working folder).
    pub fn load_with_scenes(path: &Path, scenes: &[PathBuf]) -> Result<Self> {
        for s in scenes {
            // Checked here, not with the job's own scenes: a missing --scene file used to be
            // blamed on a line of the job.
            if !s.is_file() {
                let what = if s.is_dir() {
                    "is a folder"
                } else {
                    "does not exist"
                };
                bail!(
                    "--scene {}: {what}; expected a scene file (JSON or .scene)",
                    s.display()
                );
            }
        }
        let (mut file, mut map) = JobFile::read(path)?;
        if !scenes.is_empty() {
            file.scenes = scenes
                .iter()
                .map(|s| {
                    let abs = std::path::absolute(s).unwrap_or_else(|_| s.clone());
                    abs.to_string_lossy().into_owned()
                })
                .collect();
            if let Some(m) = &mut map {
                m.add("scenes", None, "the option --scene");
            }
        }
        Self::from_file_mapped(file, path, map.as_ref())
    }

    /// Validate a parsed job file; scene paths resolve against `path`'s folder.
    pub fn from_file(f: JobFile, path: &Path) -> Result<Self> {
        Self::from_file_mapped(f, path, None)
    }

    /// [`Job::from_file`], with errors located by `map` (the lines of a text job).
    pub fn from_file_mapped(f: JobFile, path: &Path, map: Option<&SourceMap>) -> Result<Self> {
        let at = |field: &str, what: String| -> anyhow::Error {
            SourceMap::error(map, path, field, what)
        };
        if f.format != JOB_FORMAT {
            return Err(at(
                "format",
                format!("is {:?}; this version reads {JOB_FORMAT:?}", f.format),
            ));
        }
        check_name(&f.name).map_err(|e| at("name", e))?;
        if f.scenes.is_empty() {
            return Err(at(
                "scenes",
                "is empty; expected at least one scene file".into(),
            ));
        }
        let dir = path.parent().unwrap_or(Path::new(""));
        let mut scenes: Vec<JobScene> = Vec::new();
        for (i, s) in f.scenes.iter().enumerate() {
            let p = dir.join(s);
            if !p.is_file() {
                return Err(at(
                    &format!("scenes[{i}]"),
                    format!("names {s:?}, but {} is not a file", p.display()),
                ));
            }
            let name = p
                .file_stem()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            check_name(&name).map_err(|e| at(&format!("scenes[{i}]"), format!("{s:?}: {e}")))?;
            if scenes.iter().any(|o| o.name == name) {
                return Err(at(
                    &format!("scenes[{i}]"),
                    format!("repeats the scene name {name:?}; scene file stems must differ"),
                ));
            }
            scenes.push(JobScene { name, path: p });
        }
        let most = crate::limits::MAX_SPP;
        check_list("levels", &f.levels, |&l| {
            (l == 0 || l > most)
                .then(|| format!("is {l}; expected samples per pixel from 1 to {most}"))
        })
        .map_err(|(field, e)| at(&field, e))?;
        // The names were checked when the file was read; here each list is checked on its
        // own, so that a repeated time filter is reported as such (and not as a failure of the
        // first point set's stimuli).
        check_list("point_sets", &f.point_sets, |_| None).map_err(|(fl, e)| at(&fl, e))?;
        check_list("time_filters", &f.time_filters, |_| None).map_err(|(fl, e)| at(&fl, e))?;
        let reference = match &f.reference {
            ReferenceSpec::HighestLevel => Reference::HighestLevel,
            ReferenceSpec::Independent(r) => {
                let reference = stimulus_sampling(
                    r.point_set.unwrap_or(f.point_sets[0]),
                    r.spp,
                    r.time_filter.unwrap_or(f.time_filters[0]),
                    &f.overrides.sampling,
                );
                if let Some(max) = f.levels.iter().max().filter(|&&m| reference.spp <= m) {
                    return Err(at(
                        "reference.spp",
                        format!(
                            "is {}; expected more than the highest level ({max})",
                            reference.spp
                        ),
                    ));
                }
                // The sampler is the authority on constraints such as cube counts for
                // stratified sampling.
                check_sampling(&reference).map_err(|e| at("reference", e))?;
                Reference::Independent(reference)
            }
        };
        for (i, &ps) in f.point_sets.iter().enumerate() {
            for &tf in &f.time_filters {
                for &spp in &f.levels {
                    let cfg = stimulus_sampling(ps, spp, tf, &f.overrides.sampling);
                    check_sampling(&cfg).map_err(|e| {
                        at(
                            &format!("point_sets[{i}]"),
                            format!("with time filter \"{tf}\" at {spp} spp: {e}"),
                        )
                    })?;
                }
            }
        }
        let o = &f.overrides;
        for (field, v) in [("overrides.width", o.width), ("overrides.height", o.height)] {
            if let Some(v) = v {
                crate::limits::check_side(v).map_err(|e| at(field, e))?;
            }
        }
        for (field, v) in [("overrides.frames", o.frames)] {
            if v == Some(0) {
                return Err(at(field, "is 0; expected at least 1".into()));
            }
        }
        if f.frames_per_unit == Some(0) {
            return Err(at("frames_per_unit", "is 0; expected at least 1".into()));
        }
        Ok(Self {
            path: path.to_path_buf(),
            name: f.name,
            scenes,
            levels: f.levels,
            point_sets: f.point_sets,
            time_filters: f.time_filters,
            reference,
            seed: f.seed,
            overrides: f.overrides,
            frames_per_unit: f.frames_per_unit.unwrap_or(DEFAULT_FRAMES_PER_UNIT),
            assets: Assets::default(),
        })
    }

    /// Whether every stimulus keeps EXR frames.
    pub fn keep_exr(&self) -> bool {
        self.overrides.exr.unwrap_or(false)
    }

    /// The highest sampling level.
    pub fn highest_level(&self) -> u32 {
        self.levels.iter().copied().max().unwrap_or(1)
    }

    /// A sampling typical of the job's most expensive stimuli: the independent reference's,
    /// else the first condition at the highest level (for time estimates).
    pub fn heaviest_sampling(&self) -> SamplingConfig {
        match &self.reference {
            Reference::Independent(r) => r.clone(),
            Reference::HighestLevel => stimulus_sampling(
                self.point_sets[0],
                self.highest_level(),
                self.time_filters[0],
                &self.overrides.sampling,
            ),
        }
    }
}

/// Names become folder names and parts of ids split on `-`: letters, digits and `_` only.
fn check_name(name: &str) -> std::result::Result<(), String> {
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Err(format!(
            "is {name:?}; expected a non-empty name of ASCII letters, digits and `_`"
        ));
    }
    Ok(())
}

/// A non-empty list without repeats whose items pass `bad` (which explains a failure).
fn check_list<T: PartialEq + std::fmt::Debug>(
    field: &str,
    list: &[T],
    bad: impl Fn(&T) -> Option<String>,
) -> std::result::Result<(), (String, String)> {
    if list.is_empty() {
        return Err((field.into(), "is empty; expected at least one entry".into()));
    }
    for (i, v) in list.iter().enumerate() {
        if let Some(e) = bad(v) {
            return Err((format!("{field}[{i}]"), e));
        }
        if list[..i].contains(v) {
            return Err((format!("{field}[{i}]"), format!("repeats {v:?}")));
        }
    }
    Ok(())
}

/// The sampling of one stimulus as the job sees it: its point set, spp and time filter plus the
/// job's `overrides.sampling`; the scene's own settings fill in the rest when it is rendered
/// ([`SamplingConfig::over`]).
pub fn stimulus_sampling(
    point_set: PointSetKind,
    spp: u32,
    time_filter: TimeFilter,
    options: &SamplingOptions,
) -> SamplingConfig {
    SamplingConfig {
        point_set,
        spp,
        time_filter,
        ..Default::default()
    }
    .with_options(options)
}

fn check_sampling(cfg: &SamplingConfig) -> std::result::Result<(), String> {
    FrameSampler::new(cfg, 0, 0)
        .map(|_| ())
        .map_err(|e| format!("{e:#}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn job_text() -> String {
        r#"{
          "format": "blurlab-job/1",
          "name": "t",
          "scenes": ["a.json", "b.json"],
          "levels": [1, 8, 27],
          "point_sets": ["random", "hammersley"],
          "time_filters": ["box"],
          "reference": {"spp": 64},
          "seed": 7
        }"#
        .to_string()
    }

    fn setup(text: &str) -> (tempfile::TempDir, PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("a.json"), "{}").unwrap();
        std::fs::write(dir.path().join("b.json"), "{}").unwrap();
        let p = dir.path().join("job.json");
        std::fs::write(&p, text).unwrap();
        (dir, p)
    }

    #[test]
    fn loads_and_fills_reference_defaults() {
        let (_d, p) = setup(&job_text());
        let job = Job::load(&p).unwrap();
        assert_eq!(job.scenes[1].name, "b");
        let Reference::Independent(r) = &job.reference else {
            panic!("an independent reference")
        };
        assert_eq!(r.point_set, PointSetKind::Random);
        assert_eq!(r.time_filter, TimeFilter::Box);
        assert_eq!(job.frames_per_unit, DEFAULT_FRAMES_PER_UNIT);
    }

    fn error_of(text: &str) -> String {
        let (_d, p) = setup(text);
        format!("{:#}", Job::load(&p).unwrap_err())
    }

    #[test]
    fn errors_name_file_and_field() {
        let cases = [
            (
                "\"levels\": [1, 8, 27]",
                "\"levels\": [1, 0]",
                "`levels[1]`",
            ),
            ("\"levels\": [1, 8, 27]", "\"levels\": []", "`levels`"),
            ("\"name\": \"t\"", "\"name\": \"a/b\"", "`name`"),
            (
                "\"a.json\", \"b.json\"",
                "\"a.json\", \"c.json\"",
                "`scenes[1]`",
            ),
            (
                "\"a.json\", \"b.json\"",
                "\"a.json\", \"a.json\"",
                "`scenes[1]`",
            ),
            ("{\"spp\": 64}", "{\"spp\": 27}", "`reference.spp`"),
            ("blurlab-job/1", "blurlab-job/2", "`format`"),
            ("\"box\"]", "\"box\", \"box\"]", "`time_filters[1]`"),
        ];
        for (from, to, field) in cases {
            let text = job_text().replacen(from, to, 1);
            assert_ne!(text, job_text(), "{from}");
            let e = error_of(&text);
            assert!(e.contains("job.json") && e.contains(field), "{field}: {e}");
        }
    }

    #[test]
    fn the_reference_is_the_highest_level_or_an_independent_render() {
        let text = job_text().replace("{\"spp\": 64}", "\"highest_level\"");
        let (_d, p) = setup(&text);
        let job = Job::load(&p).unwrap();
        assert_eq!(job.reference, Reference::HighestLevel);
        assert_eq!(job.heaviest_sampling().spp, 27);
        let file: JobFile = serde_json::from_str(&text).unwrap();
        assert!(
            serde_json::to_string(&file)
                .unwrap()
                .contains("\"reference\":\"highest_level\"")
        );
        let e = error_of(&job_text().replace("{\"spp\": 64}", "\"highest\""));
        assert!(
            e.contains("found \"highest\"; expected \"highest_level\" or an independent reference"),
            "{e}"
        );
        let e = error_of(&job_text().replace("{\"spp\": 64}", "{\"sp\": 64}"));
        assert!(e.contains("unknown field `sp`"), "{e}");
    }

    #[test]
    fn unknown_fields_and_missing_fields_are_reported() {
        let e = error_of(&job_text().replace("\"seed\": 7", "\"sed\": 7"));
        assert!(e.contains("job.json") && e.contains("sed"), "{e}");
    }

    #[test]
    fn sampling_overrides_reach_every_stimulus_and_are_checked() {
        use crate::sampling::{Density, Scope, SpatialFilter};
        let text = job_text().replace(
            "\"seed\": 7",
            "\"seed\": 7, \"overrides\": {\"sampling\": {\"spatial_filter\": \"box\", \
             \"shift_scope\": \"frame\"}}",
        );
        let (_d, p) = setup(&text);
        let job = Job::load(&p).unwrap();
        assert_eq!(job.heaviest_sampling().spatial_filter(), SpatialFilter::Box);
        for s in expand(&job) {
            assert_eq!(
                s.sampling.spatial_filter,
                Some(SpatialFilter::Box),
                "{}",
                s.id
            );
            assert_eq!(s.sampling.shift_scope(), Scope::Frame, "{}", s.id);
            assert_eq!(s.sampling.density(), Density::Joint);
        }
        // 8 temporal samples do not divide level 27: the job names the combination.
        let text = job_text().replace(
            "\"seed\": 7",
            "\"seed\": 7, \"overrides\": {\"sampling\": {\"density\": {\"temporal\": 8}}}",
        );
        let e = error_of(&text.replace("[1, 8, 27]", "[8, 27]"));
        assert!(e.contains("`point_sets[0]`") && e.contains("27 spp"), "{e}");
        let e = error_of(&text.replace("\"sampling\": {", "\"sampling\": {\"sigma\": 1, "));
        assert!(e.contains("sigma"), "{e}");
        // The per-pixel randomization is an override like the others; unknown ones are refused
        // with the file and the field.
        let text = job_text().replace(
            "\"seed\": 7",
            "\"seed\": 7, \"overrides\": {\"sampling\": {\"randomization\": \"scramble\"}}",
        );
        let (_d, p) = setup(&text);
        for s in expand(&Job::load(&p).unwrap()) {
            assert_eq!(
                s.sampling.randomization(),
                crate::sampling::Randomization::Scramble
            );
        }
        let e = error_of(&text.replace("\"scramble\"", "\"owen\""));
        assert!(
            e.contains("job.json") && e.contains("randomization") && e.contains("scramble"),
            "{e}"
        );
    }

    #[test]
    fn unknown_names_are_refused_at_load_with_the_field_and_the_known_names() {
        for (from, to, field, names) in [
            (
                "\"hammersley\"",
                "\"no_such_set\"",
                "`point_sets[1]`",
                "random, stratified",
            ),
            (
                "[\"box\"]",
                "[\"tent\"]",
                "`time_filters[0]`",
                "box, truncated_box",
            ),
            (
                "{\"spp\": 64}",
                "{\"spp\": 64, \"point_set\": \"jittered\"}",
                "`reference`: in `point_set`",
                "sobol, halton",
            ),
        ] {
            let e = error_of(&job_text().replace(from, to));
            assert!(
                e.contains("job.json") && e.contains(field) && e.contains(names),
                "{field}: {e}"
            );
        }
    }
}
