//! The design file (`scenes/<study>/design.json`, format `blurlab-design/1`): which stimuli a study
//! shows and how. Factors (scenes x point sets x time filters) and test levels pick the test videos
//! by their manifest ids; every field past `seed` has a default (see `docs/experiment.md`).
//! [`Design::load`] (`crate::design_load`) validates everything a session relies on, naming the
//! file and the field of every problem; `procedure` is the `procedure` field.

pub mod keys;
pub mod online;
pub mod procedure;

use procedure::ProcedureSpec;
use renderer::condition::{Condition, PointSetKind, TimeFilter};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// Fastest playback rate a design may ask for: beyond 240 Hz no common display shows every
/// frame, so frame pacing could not hold.
pub const MAX_PLAYBACK_FPS: f64 = 240.0;

/// The format tag every design file carries; readers refuse any other.
pub const DESIGN_FORMAT: &str = "blurlab-design/1";

/// Most main (or practice) trials a design may plan per subject: a trial list is held in
/// memory, and at one trial per 5 s this is a week of sessions.
pub const MAX_TRIALS: u64 = 100_000;

/// Most alternatives of an m-alternative task.
pub const MAX_ALTERNATIVES: u32 = 100;

/// The design file as written on disk.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DesignFile {
    /// Always [`DESIGN_FORMAT`].
    pub format: String,
    /// The study's name: the default results folder is `results/<name>/sessions`.
    pub name: String,
    /// The stimulus manifest (file or folder), relative to the design file.
    pub manifest: String,
    pub factors: Factors,
    /// Samples per pixel of the test videos.
    pub levels: Vec<u32>,
    /// Which video every test video is compared against (per scene, or per condition).
    #[serde(default)]
    pub reference: ReferenceChoice,
    /// Trials per condition x level (the thesis: 4).
    #[serde(default = "default_repeats")]
    pub repeats: u32,
    /// What the subject does on a trial; gives the analysis its guess rate.
    #[serde(default, skip_serializing_if = "Task::is_two_pair")]
    pub task: Task,
    /// How the main trials' levels are chosen (default: constant stimuli, `levels` x `repeats`).
    #[serde(default, skip_serializing_if = "ProcedureSpec::is_constant")]
    pub procedure: ProcedureSpec,
    #[serde(default)]
    pub layout: Layout,
    #[serde(default)]
    pub playback: Playback,
    /// A break screen after every this many main trials (0: no breaks).
    #[serde(default = "default_break_every")]
    pub break_every: u32,
    #[serde(default)]
    pub practice: Practice,
    #[serde(default)]
    pub keys: ResponseKeys,
    pub seed: SeedScheme,
    /// Text of the instructions screen (a default explains the task and the keys).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub instructions: Option<String>,
    /// The display, for predicting visibility (`blurlab predict`); default: the thesis's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub display: Option<crate::display::DisplaySpec>,
    /// Attention checks among the main trials (`procedure::catch`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub catch_trials: Option<online::CatchTrials>,
    /// A study run online: platform, consent, debriefing, screening (`blurlab serve`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub online: Option<online::Online>,
    /// Who `analyze` leaves out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exclusion: Option<online::Exclusion>,
}

/// The crossed factors; a condition is one scene x point set x time filter.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Factors {
    pub scenes: Vec<String>,
    pub point_sets: Vec<PointSetKind>,
    pub time_filters: Vec<TimeFilter>,
}

/// The reference video each test video is shown beside.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(rename_all = "snake_case")]
pub enum ReferenceChoice {
    /// The manifest's independent reference of the scene (id `<scene>-reference`).
    #[default]
    SceneReference,
    /// The highest of `levels` of the same scene, point set and time filter: the thesis's
    /// ground truth ("rendered at the highest sampling density (512 samples per pixel)"), for
    /// stimuli rendered with the job reference `highest_level`. The highest level's trials then
    /// show two identical pairs (chance by construction).
    HighestLevel,
    /// An explicit stimulus id per scene.
    Stimuli(BTreeMap<String, String>),
}

/// The task of a trial.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Task {
    /// The thesis's: two pairs of videos, say which pair differs (guess rate 1/2).
    #[default]
    TwoPair,
    /// m-alternative forced choice (guess rate 1/m), written `{"alternatives": m}`: describes
    /// data collected by another program for `analyze`; sessions present only `two_pair`.
    Alternatives(u32),
}

impl Task {
    /// The proportion correct of a subject who cannot see the difference.
    pub fn guess_rate(self) -> f64 {
        match self {
            Task::TwoPair => 0.5,
            Task::Alternatives(m) => 1.0 / m as f64,
        }
    }

    fn is_two_pair(&self) -> bool {
        *self == Task::TwoPair
    }
}

/// As a design file writes it (`two_pair`, `{"alternatives": 4}`), for messages.
impl std::fmt::Display for Task {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Task::TwoPair => write!(f, "\"two_pair\""),
            Task::Alternatives(m) => write!(f, "{{\"alternatives\": {m}}}"),
        }
    }
}

/// How the four videos of a trial are arranged.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Layout {
    /// The thesis: pair 1, a gap, then pair 2; each pair's two videos side by side.
    #[default]
    Sequential,
    /// All four at once: pair 1 the top row, pair 2 the bottom row.
    Grid,
}

/// Timing and appearance of a presentation.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct Playback {
    /// Playback rate, frames per second; absent: each video's own rate from the manifest (the
    /// renderer's 30 fps). The thesis gives none; its session length fits about 15 fps or
    /// looped videos (docs/replication.md), so the rate is a factor of the design.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fps: Option<f64>,
    /// Times each pair's video plays through.
    pub loops: u32,
    /// Fixation cross before the first pair, milliseconds.
    pub fixation_ms: u32,
    /// Blank screen between the pairs (sequential layout), milliseconds.
    pub gap_ms: u32,
    /// Physical pixels between neighbouring videos.
    pub spacing_px: u32,
    /// Screen colour around the videos, 8-bit sRGB.
    pub background: [u8; 3],
}

impl Default for Playback {
    fn default() -> Self {
        Self {
            fps: None,
            loops: 1,
            fixation_ms: 500,
            gap_ms: 1000,
            spacing_px: 32,
            background: [0, 0, 0],
        }
    }
}

impl Playback {
    /// The rate a video whose manifest says `manifest_fps` plays at: the design's
    /// `playback.fps` when given, else the manifest's.
    pub fn rate(&self, manifest_fps: f64) -> f64 {
        self.fps.unwrap_or(manifest_fps)
    }
}

/// Practice trials before the main trials: logged with `practice: true`, never analyzed.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct Practice {
    pub trials: u32,
    /// Levels practice draws from (default: the lowest test level, the easiest).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub levels: Option<Vec<u32>>,
    /// Tell the subject after each practice answer whether it was right.
    pub feedback: bool,
}

impl Default for Practice {
    fn default() -> Self {
        Self {
            trials: 4,
            levels: None,
            feedback: true,
        }
    }
}

/// Keys that answer "pair 1" and "pair 2" (egui key names: `1`, `ArrowLeft`, `A`, ...).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct ResponseKeys {
    pub pair1: Vec<String>,
    pub pair2: Vec<String>,
}

impl Default for ResponseKeys {
    fn default() -> Self {
        Self {
            pair1: vec!["1".into(), "ArrowLeft".into()],
            pair2: vec!["2".into(), "ArrowRight".into()],
        }
    }
}

/// Where each subject's randomization comes from.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SeedScheme {
    pub master: u64,
    #[serde(default)]
    pub scheme: SeedKind,
}

/// How a subject's seed derives from the master seed.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SeedKind {
    /// `hash(master, [name_id(subject)])`: every subject has their own order.
    #[default]
    PerSubject,
    /// The master seed itself: every subject sees the same order (pilots, demonstrations).
    Shared,
}

fn default_repeats() -> u32 {
    4
}
fn default_break_every() -> u32 {
    48
}

/// A loaded, validated design.
#[derive(Clone, Debug, PartialEq)]
pub struct Design {
    /// Where it was loaded from (for messages).
    pub path: PathBuf,
    pub file: DesignFile,
    /// The manifest path resolved against the design file's folder.
    pub manifest_path: PathBuf,
    /// SHA-256 of the file's canonical JSON (keys sorted, no whitespace), lowercase hex.
    pub hash: String,
}

impl Design {
    pub fn name(&self) -> &str {
        &self.file.name
    }

    /// The practice levels with the default filled in.
    pub fn practice_levels(&self) -> Vec<u32> {
        match &self.file.practice.levels {
            Some(l) => l.clone(),
            None => self.file.levels.iter().min().into_iter().copied().collect(),
        }
    }

    /// The reference stimulus id of a condition (scene, point set, time filter).
    pub fn reference_id(&self, c: &Condition) -> String {
        match &self.file.reference {
            ReferenceChoice::SceneReference => renderer::ids::reference_id(&c.scene),
            ReferenceChoice::HighestLevel => {
                let top = self.file.levels.iter().copied().max().unwrap_or(0);
                renderer::ids::stimulus_id(&c.scene, c.point_set, c.time_filter, top)
            }
            ReferenceChoice::Stimuli(m) => m[&c.scene].clone(),
        }
    }

    /// The seed of one subject's trial list.
    pub fn subject_seed(&self, subject: &str) -> u64 {
        let s = &self.file.seed;
        match s.scheme {
            SeedKind::PerSubject => {
                renderer::hash::hash(s.master, &[renderer::hash::name_id(subject)])
            }
            SeedKind::Shared => s.master,
        }
    }

    /// Main trials per subject (an adaptive procedure's most: tracks that stop early give
    /// up the rest).
    pub fn main_trial_count(&self) -> u32 {
        let f = &self.file.factors;
        let conditions = (f.scenes.len() * f.point_sets.len() * f.time_filters.len()) as u32;
        let p = &self.file.procedure;
        let n = if p.is_constant() {
            conditions * self.file.levels.len() as u32 * self.file.repeats
        } else {
            conditions * p.tracks_per_condition() * p.trials_per_track()
        };
        // One catch trial per block of `block - 1` procedure trials (`procedure::catch`).
        match &self.file.catch_trials {
            Some(c) => n + n.div_ceil(c.block() - 1),
            None => n,
        }
    }

    /// The instructions text, default or given.
    pub fn instructions(&self) -> String {
        if let Some(t) = &self.file.instructions {
            return t.clone();
        }
        let k = &self.file.keys;
        let (first, second) = match self.file.layout {
            Layout::Sequential => ("first pair", "second pair"),
            Layout::Grid => ("top pair", "bottom pair"),
        };
        format!(
            "Each trial shows two pairs of videos. In one pair both videos are the same; in the \
             other they differ in noise. Watch both pairs, then say which pair differed: press {} \
             for the {first}, {} for the {second}. If you are unsure, guess.\n\n\
             Press Esc at any time to pause.",
            keys::describe(&k.pair1),
            keys::describe(&k.pair2),
        )
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use renderer::paths::lexical_normal;
    use std::path::Path;

    fn cond(scene: &str, point_set: &str, time_filter: &str) -> Condition {
        Condition::new(
            scene,
            point_set.parse().unwrap(),
            time_filter.parse().unwrap(),
        )
    }

    pub(crate) const SMALL: &str = r#"{
        "format": "blurlab-design/1",
        "name": "small",
        "manifest": "../stimuli/small",
        "factors": {"scenes": ["plane", "spheres"], "point_sets": ["hammersley", "poisson"],
                    "time_filters": ["box"]},
        "levels": [1, 8, 27],
        "repeats": 3,
        "seed": {"master": 7}
    }"#;

    pub(crate) fn small() -> Design {
        Design::parse(Path::new("designs/small.json"), SMALL).unwrap()
    }

    fn err(text: &str) -> String {
        format!(
            "{:#}",
            Design::parse(Path::new("d.json"), text).unwrap_err()
        )
    }

    fn edit(f: impl FnOnce(&mut serde_json::Value)) -> String {
        let mut v: serde_json::Value = serde_json::from_str(SMALL).unwrap();
        f(&mut v);
        v.to_string()
    }

    #[test]
    fn defaults_fill_in_and_manifest_resolves_against_the_design_folder() {
        let d = small();
        assert_eq!(d.manifest_path, Path::new("stimuli/small"));
        assert_eq!(
            lexical_normal(Path::new("../a/./b/../../c")),
            Path::new("../c")
        );
        assert_eq!(d.file.layout, Layout::Sequential);
        assert_eq!(d.file.playback, Playback::default());
        assert_eq!(d.practice_levels(), vec![1]);
        assert_eq!(d.main_trial_count(), 2 * 2 * 3 * 3);
        assert_eq!(
            d.reference_id(&cond("plane", "poisson", "box")),
            "plane-reference"
        );
        assert_ne!(d.subject_seed("a"), d.subject_seed("b"));
    }

    #[test]
    fn hash_ignores_layout_of_the_text_but_not_values() {
        let a = small();
        let reordered = edit(|_| {});
        let b = Design::parse(Path::new("x.json"), &reordered).unwrap();
        assert_eq!(a.hash, b.hash);
        let c = Design::parse(
            Path::new("x.json"),
            &edit(|v| v["repeats"] = serde_json::json!(4)),
        )
        .unwrap();
        assert_ne!(a.hash, c.hash);
    }

    #[test]
    fn errors_name_the_file_and_the_field() {
        let cases: Vec<(String, &str)> = vec![
            (
                edit(|v| v["format"] = "blurlab-design/2".into()),
                "`format`",
            ),
            (
                edit(|v| v["levels"] = serde_json::json!([1, 0])),
                "`levels`",
            ),
            (
                edit(|v| v["levels"] = serde_json::json!([8, 8])),
                "`levels`",
            ),
            (edit(|v| v["repeats"] = serde_json::json!(0)), "`repeats`"),
            (edit(|v| v["name"] = "a/b".into()), "`name`"),
            (
                edit(|v| v["factors"]["scenes"] = serde_json::json!([])),
                "`factors.scenes`",
            ),
            (
                edit(|v| v["factors"]["point_sets"] = serde_json::json!(["sobol", "sobol"])),
                "`factors.point_sets`",
            ),
            (
                edit(|v| v["keys"] = serde_json::json!({"pair1": ["1"], "pair2": ["1"]})),
                "`keys.pair1` and `keys.pair2`",
            ),
            (
                edit(|v| v["keys"] = serde_json::json!({"pair1": ["Bogus"], "pair2": ["2"]})),
                "`keys.pair1`",
            ),
            (
                edit(|v| v["keys"] = serde_json::json!({"pair1": ["Space"], "pair2": ["2"]})),
                "reserves",
            ),
            (
                edit(|v| v["practice"] = serde_json::json!({"levels": [64]})),
                "`practice.levels`",
            ),
            (
                edit(|v| v["reference"] = serde_json::json!({"stimuli": {"plane": "p-ref"}})),
                "\"spheres\"",
            ),
            (
                edit(|v| v["playback"] = serde_json::json!({"loops": 0})),
                "`playback.loops`",
            ),
            (
                edit(|v| v["playback"] = serde_json::json!({"fps": 0.5})),
                "`playback.fps`",
            ),
            (
                edit(|v| v["playback"] = serde_json::json!({"fps": 1000})),
                "`playback.fps`",
            ),
            (edit(|v| v["surprise"] = 1.into()), "surprise"),
            (
                edit(|v| v["task"] = serde_json::json!({"alternatives": 1})),
                "`task.alternatives`",
            ),
            (edit(|v| v["task"] = "three_pair".into()), "three_pair"),
        ];
        for (text, field) in cases {
            let e = err(&text);
            assert!(e.starts_with("d.json"), "{e}");
            assert!(e.contains(field), "expected {field} in: {e}");
        }
    }

    #[test]
    fn the_task_gives_the_guess_rate_and_old_files_stay_two_pair() {
        assert_eq!(small().file.task, Task::TwoPair);
        assert_eq!(small().file.task.guess_rate(), 0.5);
        let four = edit(|v| v["task"] = serde_json::json!({"alternatives": 4}));
        let d = Design::parse(Path::new("d.json"), &four).unwrap();
        assert_eq!(d.file.task, Task::Alternatives(4));
        assert_eq!(d.file.task.guess_rate(), 0.25);
        // Written explicitly, the default task changes the hash (the text differs) but not
        // the design.
        let explicit = edit(|v| v["task"] = "two_pair".into());
        assert_eq!(
            Design::parse(Path::new("d.json"), &explicit).unwrap().file,
            small().file
        );
        // Serializing a two-pair design leaves the field out, as old files are.
        let text = serde_json::to_string(&small().file).unwrap();
        assert!(!text.contains("task"), "{text}");
    }

    #[test]
    fn explicit_references_and_shared_seeds() {
        let text = edit(|v| {
            v["reference"] =
                serde_json::json!({"stimuli": {"plane": "plane-x", "spheres": "spheres-y"}});
            v["seed"] = serde_json::json!({"master": 9, "scheme": "shared"});
        });
        let d = Design::parse(Path::new("d.json"), &text).unwrap();
        assert_eq!(
            d.reference_id(&cond("spheres", "hammersley", "box")),
            "spheres-y"
        );
        assert_eq!(d.subject_seed("a"), 9);
        assert_eq!(d.subject_seed("b"), 9);
    }

    #[test]
    fn the_highest_level_is_each_conditions_reference() {
        let d = Design::parse(
            Path::new("d.json"),
            &edit(|v| v["reference"] = "highest_level".into()),
        )
        .unwrap();
        assert_eq!(
            d.reference_id(&cond("plane", "poisson", "box")),
            "plane-poisson-box-0027"
        );
        assert_eq!(
            d.reference_id(&cond("spheres", "hammersley", "box")),
            "spheres-hammersley-box-0027"
        );
    }

    #[test]
    fn committed_designs_load() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
        for study in ["demo", "thesis", "adaptive"] {
            let d = Design::load(&root.join(study).join("design.json")).unwrap();
            assert!(d.main_trial_count() > 0);
        }
        let thesis = Design::load(&root.join("thesis/design.json")).unwrap();
        // The thesis: 2 scenes x 3 point sets x 8 levels x 4 repeats.
        assert_eq!(thesis.main_trial_count(), 192);
    }
}
