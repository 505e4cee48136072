//! Before the first trial: every stimulus the design needs is in the manifest with the expected
//! factors, every frame file exists with the manifest's size, the frame count matches, the
//! videos' content hash matches (the renderer's definition, [`ContentHash`]), and each test
//! video can stand beside its reference (same size, frame count and rate). Every problem is
//! listed, not only the first; no session starts while any remains.

use crate::design::Design;
use crate::trials::conditions;
use anyhow::Result;
use rayon::prelude::*;
use renderer::condition::{PointSetKind, TimeFilter};
use renderer::manifest::{ContentHash, Manifest, Stimulus};
use renderer::progress::Progress;
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

/// What a design expects of one stimulus.
#[derive(Clone, Debug, PartialEq)]
pub struct Needed {
    pub id: String,
    pub scene: String,
    /// `None` for references (their sampling is the job's business).
    pub test: Option<(PointSetKind, TimeFilter, u32)>,
    /// The manifest's reference flag must be set (the default scene references).
    pub must_be_reference: bool,
    /// The reference it is shown beside (tests only).
    pub reference_id: Option<String>,
}

/// One thing wrong with the stimuli.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Problem {
    /// The stimulus id, or the manifest path for manifest-level problems.
    pub subject: String,
    pub message: String,
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.subject, self.message)
    }
}

/// How thorough to be.
#[derive(Clone, Copy, Debug)]
pub struct PreflightOptions {
    /// Read every frame and compare the content hash (the slow part: all frame bytes).
    pub check_hashes: bool,
}

/// What preflight found.
#[derive(Debug)]
pub struct PreflightReport {
    pub manifest_path: PathBuf,
    pub manifest: Option<Manifest>,
    pub problems: Vec<Problem>,
    pub stimuli_checked: usize,
    pub frames_checked: u64,
    pub bytes_hashed: u64,
}

impl PreflightReport {
    /// The manifest if nothing is wrong, else an error listing every problem.
    pub fn into_result(self) -> Result<Manifest> {
        match self.manifest {
            Some(m) if self.problems.is_empty() => Ok(m),
            _ => {
                let list: Vec<String> = self.problems.iter().map(|p| format!("  - {p}")).collect();
                anyhow::bail!(
                    "preflight found {} problem(s) with the stimuli of {}; no session was \
                     started:\n{}",
                    self.problems.len(),
                    self.manifest_path.display(),
                    list.join("\n")
                )
            }
        }
    }
}

/// Every stimulus the design shows (practice levels are among the design's levels). A
/// condition's highest level that is its own reference (`highest_level`) is checked as a test
/// stimulus.
pub fn needed_stimuli(design: &Design) -> Vec<Needed> {
    let mut out: BTreeMap<String, Needed> = BTreeMap::new();
    let scene_reference = matches!(
        design.file.reference,
        crate::design::ReferenceChoice::SceneReference
    );
    for c in conditions(design) {
        let reference_id = design.reference_id(&c);
        out.entry(reference_id.clone()).or_insert(Needed {
            id: reference_id.clone(),
            scene: c.scene.clone(),
            test: None,
            must_be_reference: scene_reference,
            reference_id: None,
        });
        for &level in &design.file.levels {
            let id = renderer::ids::stimulus_id(&c.scene, c.point_set, c.time_filter, level);
            out.insert(
                id.clone(),
                Needed {
                    id,
                    scene: c.scene.clone(),
                    test: Some((c.point_set, c.time_filter, level)),
                    must_be_reference: false,
                    reference_id: Some(reference_id.clone()),
                },
            );
        }
    }
    out.into_values().collect()
}

/// Check the design's stimuli; `progress` counts the frames checked.
pub fn preflight(
    design: &Design,
    opts: PreflightOptions,
    progress: &dyn Progress,
) -> PreflightReport {
    let manifest_path = renderer::manifest::manifest_file(&design.manifest_path);
    let mut report = PreflightReport {
        manifest_path: manifest_path.clone(),
        manifest: None,
        problems: Vec::new(),
        stimuli_checked: 0,
        frames_checked: 0,
        bytes_hashed: 0,
    };
    let manifest = match Manifest::load(&manifest_path) {
        Ok(m) => m,
        Err(e) => {
            report.problems.push(Problem {
                subject: manifest_path.display().to_string(),
                message: format!(
                    "{e:#} (render the stimuli first: `blurlab render job <job file>`)"
                ),
            });
            return report;
        }
    };
    let folder = manifest_path
        .parent()
        .unwrap_or(Path::new(""))
        .to_path_buf();
    let needed = needed_stimuli(design);
    let total_frames: u64 = needed
        .iter()
        .filter_map(|n| manifest.get(&n.id))
        .map(|s| s.frame_paths.len() as u64)
        .sum();
    progress.start(total_frames);
    let results: Vec<(Vec<Problem>, u64, u64)> = needed
        .par_iter()
        .map(|n| check_stimulus(&manifest, &folder, n, opts, progress))
        .collect();
    progress.finish();
    for (problems, frames, bytes) in results {
        report.problems.extend(problems);
        report.frames_checked += frames;
        report.bytes_hashed += bytes;
    }
    report.stimuli_checked = needed.len();
    report.manifest = Some(manifest);
    report
}

/// Problems of one stimulus, frames checked and bytes hashed.
fn check_stimulus(
    manifest: &Manifest,
    folder: &Path,
    n: &Needed,
    opts: PreflightOptions,
    progress: &dyn Progress,
) -> (Vec<Problem>, u64, u64) {
    let mut problems = Vec::new();
    let mut say = |message: String| {
        problems.push(Problem {
            subject: n.id.clone(),
            message,
        })
    };
    let Some(s) = manifest.get(&n.id) else {
        say(
            "not in the manifest (was the job rendered with these scenes, point sets, time \
             filters and levels?)"
                .into(),
        );
        return (problems, 0, 0);
    };
    for m in factor_mismatches(s, n) {
        say(m);
    }
    if let Some(r) = n.reference_id.as_deref().and_then(|r| manifest.get(r)) {
        for m in pair_mismatches(s, r) {
            say(m);
        }
    }
    let (frame_problems, frames, bytes) = stimulus_problems(s, folder, opts, progress);
    for m in frame_problems {
        say(m);
    }
    (problems, frames, bytes)
}

/// What is wrong with one manifest entry whatever the design: its frame count against its
/// frame list, its rate, and its frames (missing, of another size, or, with `check_hashes`,
/// not the content hash the manifest records), with the frames checked and bytes hashed.
/// `folder` holds the manifest. `blurlab predict` checks its stimuli with it too.
pub fn stimulus_problems(
    s: &Stimulus,
    folder: &Path,
    opts: PreflightOptions,
    progress: &dyn Progress,
) -> (Vec<String>, u64, u64) {
    let mut problems = Vec::new();
    if s.frames == 0 || s.frame_paths.len() != s.frames as usize {
        problems.push(format!(
            "the manifest says {} frames but lists {} frame files",
            s.frames,
            s.frame_paths.len()
        ));
    }
    if !(s.fps.is_finite() && s.fps > 0.0) {
        problems.push(format!(
            "field `fps` is {}; expected a positive rate",
            s.fps
        ));
    }
    let (frame_problems, frames, bytes) = check_frames(s, folder, opts, progress);
    problems.extend(frame_problems);
    (problems, frames, bytes)
}

fn factor_mismatches(s: &Stimulus, n: &Needed) -> Vec<String> {
    let mut out = Vec::new();
    let mut field = |name: &str, found: String, expected: String| {
        if found != expected {
            out.push(format!(
                "manifest field `{name}` is {found}; the design expects {expected}"
            ));
        }
    };
    field("scene", format!("{:?}", s.scene), format!("{:?}", n.scene));
    if let Some((ps, tf, level)) = &n.test {
        field("point_set", format!("{:?}", s.point_set), format!("{ps:?}"));
        field(
            "time_filter",
            format!("{:?}", s.time_filter),
            format!("{tf:?}"),
        );
        field("spp", s.spp.to_string(), level.to_string());
        field("reference", s.reference.to_string(), "false".into());
    } else if n.must_be_reference {
        field("reference", s.reference.to_string(), "true".into());
    }
    out
}

/// A test video must match its reference in everything the eye compares side by side.
fn pair_mismatches(s: &Stimulus, r: &Stimulus) -> Vec<String> {
    let mut out = Vec::new();
    if (s.width, s.height) != (r.width, r.height) {
        out.push(format!(
            "is {}x{} but its reference {} is {}x{}; a pair must be the same size",
            s.width, s.height, r.id, r.width, r.height
        ));
    }
    if s.frames != r.frames || s.fps != r.fps {
        out.push(format!(
            "has {} frames at {} fps but its reference {} has {} at {} fps",
            s.frames, s.fps, r.id, r.frames, r.fps
        ));
    }
    out
}

/// Report at most this many frames per kind of problem, then a count.
const LIST_LIMIT: usize = 3;

fn check_frames(
    s: &Stimulus,
    folder: &Path,
    opts: PreflightOptions,
    progress: &dyn Progress,
) -> (Vec<String>, u64, u64) {
    let mut missing = Vec::new();
    let mut wrong_size = Vec::new();
    let mut hasher = ContentHash::new();
    let mut bytes_hashed = 0u64;
    for (f, rel) in s.frame_paths.iter().enumerate() {
        progress.advance(1);
        let path = folder.join(rel);
        let dims = if opts.check_hashes {
            match std::fs::read(&path) {
                Ok(bytes) => {
                    hasher.add_frame(&bytes);
                    bytes_hashed += bytes.len() as u64;
                    png_dimensions(std::io::Cursor::new(bytes))
                }
                Err(_) => {
                    missing.push(format!("frame {f} ({})", path.display()));
                    continue;
                }
            }
        } else {
            match std::fs::File::open(&path) {
                Ok(file) => png_dimensions(std::io::BufReader::new(file)),
                Err(_) => {
                    missing.push(format!("frame {f} ({})", path.display()));
                    continue;
                }
            }
        };
        match dims {
            Some(d) if d == (s.width, s.height) => {}
            Some((w, h)) => wrong_size.push(format!("frame {f} ({}) is {w}x{h}", path.display())),
            None => wrong_size.push(format!("frame {f} ({}) is not a PNG image", path.display())),
        }
    }
    let mut out = Vec::new();
    if !missing.is_empty() {
        out.push(listed("missing", &missing));
    }
    if !wrong_size.is_empty() {
        out.push(format!(
            "{}; the manifest says {}x{}",
            listed("wrong size", &wrong_size),
            s.width,
            s.height
        ));
    }
    if opts.check_hashes && missing.is_empty() {
        let found = hasher.finish();
        if found != s.content_hash {
            out.push(format!(
                "content hash of the frames is {found}, but the manifest says {} (frames changed \
                 or corrupted since rendering; render the job again)",
                s.content_hash
            ));
        }
    }
    (out, s.frame_paths.len() as u64, bytes_hashed)
}

fn listed(what: &str, items: &[String]) -> String {
    let shown = items[..items.len().min(LIST_LIMIT)].join(", ");
    if items.len() > LIST_LIMIT {
        format!(
            "{} frame(s) {what}: {shown} and {} more",
            items.len(),
            items.len() - LIST_LIMIT
        )
    } else {
        format!("{} frame(s) {what}: {shown}", items.len())
    }
}

/// Width and height from a PNG's header (nothing else is decoded).
fn png_dimensions<R: std::io::BufRead + std::io::Seek>(reader: R) -> Option<(u32, u32)> {
    image::ImageReader::with_format(reader, image::ImageFormat::Png)
        .into_dimensions()
        .ok()
}
