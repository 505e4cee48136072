//! The session log (`results/<study>/sessions/<subject>.jsonl`), format `blurlab-session/1`:
//! JSON Lines, append-only. The first line is the [`Header`]; every completed trial adds one
//! [`TrialRecord`] line, written, flushed and synced before the next trial starts (see
//! [`crate::log::writer`]). A session continued after an interruption adds a [`Resume`] line
//! where it picked up.
//! A torn last line (a crash mid-write) is ignored with a warning; any other bad line is an error
//! naming the file and line number.

pub mod sink;
mod timing;
pub mod writer;

pub use timing::Timing;

use anyhow::{Context, Result, bail};
use renderer::condition::{Condition, PointSetKind, TimeFilter};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The format tag in every header; readers refuse any other.
pub const LOG_FORMAT: &str = "blurlab-session/1";

/// One line of a session log.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum LogLine {
    Header(Header),
    Trial(TrialRecord),
    Resume(Resume),
}

/// Where an interrupted session was continued: the trials before it stand, the trials after it
/// were presented by the run described here.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Resume {
    /// Seconds since the Unix epoch when the session was continued (0 for simulated sessions).
    pub started_unix: f64,
    pub app_version: String,
    /// Practice and main trials already answered.
    pub practice_done: u32,
    pub trials_done: u32,
    /// The display of the continued run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub display: Option<Display>,
    /// What the reader tolerated when reopening (a torn last line).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// What the session is: who, which design, how it was randomized, on what display.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Header {
    /// Always [`LOG_FORMAT`].
    pub format: String,
    pub subject: String,
    /// Session number for this subject (1 for the first; a resume keeps the number).
    pub session: u32,
    /// The design's name.
    pub design: String,
    /// SHA-256 of the design file's canonical JSON: a resume or an analysis refuses a mismatch.
    pub design_hash: String,
    /// Master seed of the randomization (trial order, pair and side assignment).
    pub seed: u64,
    /// `blurlab <version>` of the program that wrote the log.
    pub app_version: String,
    /// `gui` for a subject at the lab app, `web` in a browser (`blurlab serve`), `simulated` for
    /// an observer model.
    pub mode: String,
    /// Seconds since the Unix epoch when the log was created.
    pub started_unix: f64,
    /// Trials in the full list, practice excluded.
    pub trials_planned: u32,
    /// The display, when a window was used.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub display: Option<Display>,
    /// The simulated observer's parameters, when simulated.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub observer: Option<serde_json::Value>,
    /// A web participant's platform ids and consent (the design's `online`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub participant: Option<Participant>,
}

/// Who a web participant is on their recruitment platform, and when they consented.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct Participant {
    /// The query parameters the design's `online` names (the id parameter's among them).
    #[serde(default)]
    pub ids: std::collections::BTreeMap<String, String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub consent: Option<Consent>,
}

/// A consent given, before any trial.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Consent {
    /// Seconds since the Unix epoch.
    pub unix: f64,
    /// SHA-256 of the consent text shown.
    pub text_sha256: String,
}

/// The display a session ran on.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Display {
    /// Physical pixels.
    pub width: u32,
    pub height: u32,
    pub pixels_per_point: f32,
    /// Measured median interval between repaints, milliseconds.
    pub refresh_interval_ms: f64,
    /// What a browser measured (`blurlab serve`); absent for the lab app.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub browser: Option<BrowserDisplay>,
}

/// A browser's display facts (`mode: "web"` logs): screen scale by the card method, viewing
/// distance by the blind-spot method ("virtual chinrest", Li et al. 2020), pixels per degree.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct BrowserDisplay {
    /// The browser window's inner size, device pixels.
    pub window_px: [u32; 2],
    /// `window.devicePixelRatio`.
    pub device_pixel_ratio: f64,
    /// Device pixels per millimetre on the screen (an ID-1 card, 85.60 mm, matched on screen).
    pub px_per_mm: f64,
    /// Eye to screen, millimetres (blind-spot method).
    pub viewing_distance_mm: f64,
    pub pixels_per_degree: f64,
    pub user_agent: String,
    pub fullscreen: bool,
}

/// Which pair of the trial, or which side of a pair.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq, Hash)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    Left,
    Right,
}

/// One answered trial.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct TrialRecord {
    /// Position in the subject's trial list (practice trials count separately from 0).
    pub index: u32,
    /// Practice trials are logged but never analyzed.
    pub practice: bool,
    pub scene: String,
    pub point_set: PointSetKind,
    pub time_filter: TimeFilter,
    /// The test video's samples per pixel.
    pub level: u32,
    pub test_stimulus: String,
    pub reference_stimulus: String,
    /// Which pair (1 or 2) held reference/test.
    pub diff_pair: u8,
    /// Side of the test video within its pair.
    pub test_side: Side,
    /// The pair the subject chose (1 or 2).
    pub response: u8,
    pub correct: bool,
    /// What was measured while the trial was presented (flattened: `rt_ms`, `onsets_ms`,
    /// `frame_times_ms`, `dropped_frames`, `pauses`, `preload_ms`, `late_frames`,
    /// `refresh_interval_ms`, in that order, as logs have always had them).
    #[serde(flatten)]
    pub timing: Timing,
    /// An attention check (the design's `catch_trials`): never fitted.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub catch: bool,
}

impl TrialRecord {
    /// The trial's condition. (The record keeps scene, point set and time filter as its own
    /// fields, in the order logs have always had them.)
    pub fn condition(&self) -> Condition {
        Condition::new(self.scene.clone(), self.point_set, self.time_filter)
    }
}

/// A whole log read back.
#[derive(Clone, Debug)]
pub struct SessionLog {
    pub path: PathBuf,
    pub header: Header,
    pub trials: Vec<TrialRecord>,
    /// The line number (1-based) of each of `trials`, for messages.
    pub trial_lines: Vec<usize>,
    /// Where the session was continued after an interruption.
    pub resumes: Vec<Resume>,
    /// Problems that were tolerated (a torn last line).
    pub warnings: Vec<String>,
}

impl SessionLog {
    /// Read a log, refusing unknown formats and corrupt lines (except a torn last line).
    pub fn read(path: &Path) -> Result<Self> {
        let bytes = std::fs::read(path)
            .with_context(|| format!("cannot read session log {}", path.display()))?;
        Self::parse(path, bytes)
    }

    /// [`SessionLog::read`] of a log's bytes (a file's, or a [`crate::log::sink::MemoryLog`]'s);
    /// `path` names it in messages.
    pub fn parse(path: &Path, bytes: Vec<u8>) -> Result<Self> {
        parse_log(path, &utf8_text(path, bytes)?)
    }

    /// The main trials (catch trials among them), in log order: what the procedure replays.
    pub fn main_trials(&self) -> impl Iterator<Item = &TrialRecord> {
        self.trials.iter().filter(|t| !t.practice)
    }

    /// The trials that count for analysis: main trials that are not catch trials.
    pub fn analyzed_trials(&self) -> impl Iterator<Item = &TrialRecord> {
        self.trials.iter().filter(|t| !t.practice && !t.catch)
    }
}

/// A log whose header line was cut off by a crash while it was written: the session never
/// started, so the file holds no answers. `analyze --lenient` skips such a log with a warning
/// (it finds this error with `downcast_ref`); everything else refuses it.
#[derive(Debug, thiserror::Error)]
#[error(
    "{}:1: the header line is incomplete (the session was interrupted while writing it); the \
     log holds no answers",
    path.display()
)]
pub struct TornHeader {
    pub path: PathBuf,
}

/// A log's bytes as text. A byte that is not UTF-8 is an error naming its line and column,
/// except inside a torn last line (a crash can cut a character in two), which is read lossily
/// and then dropped by [`parse_log`] like any torn last line.
fn utf8_text(path: &Path, bytes: Vec<u8>) -> Result<String> {
    let bytes = renderer::utf8::without_bom(bytes);
    let torn_at = match std::str::from_utf8(&bytes) {
        Ok(_) => None,
        Err(e) => Some(e.valid_up_to()),
    };
    match torn_at {
        Some(at) if !bytes[at..].contains(&b'\n') => {
            Ok(String::from_utf8_lossy(&bytes).into_owned())
        }
        _ => renderer::utf8::decode(path, bytes, "session log"),
    }
}

/// One line, with a type error naming its field (`field `response`: invalid type ...`).
/// The line is read as a JSON value first and then as the type its `kind` names: serde's
/// internally tagged enums buffer their content and lose the field path.
fn parse_line(line: &str) -> Result<LogLine, String> {
    let value: serde_json::Value = serde_json::from_str(line).map_err(|e| e.to_string())?;
    let kind = value
        .get("kind")
        .and_then(|k| k.as_str())
        .map(str::to_owned);
    let mut fields = value;
    if let Some(map) = fields.as_object_mut() {
        map.remove("kind");
    }
    match kind.as_deref() {
        Some("header") => typed(fields).map(LogLine::Header),
        Some("trial") => typed(fields.clone())
            .map(LogLine::Trial)
            .map_err(|e| timing_problem(&fields).unwrap_or(e)),
        Some("resume") => typed(fields).map(LogLine::Resume),
        Some(other) => Err(format!(
            "field `kind` is {other:?}; expected \"header\", \"trial\" or \"resume\""
        )),
        None => Err("no field `kind` (a string); expected a log line object".into()),
    }
}

/// `v` read as a `T`, or the error with the path of the field it is in.
fn typed<T: serde::de::DeserializeOwned>(v: serde_json::Value) -> Result<T, String> {
    serde_path_to_error::deserialize(v).map_err(|e| match e.path().to_string() {
        p if p == "." => e.inner().to_string(),
        p => format!("field `{p}`: {}", e.inner()),
    })
}

/// What is wrong with a trial line's timing fields, named by field. (Inside the record the
/// timing is flattened, and serde's flattening loses the field path.)
fn timing_problem(fields: &serde_json::Value) -> Option<String> {
    let timing: serde_json::Map<_, _> = fields
        .as_object()?
        .iter()
        .filter(|(k, _)| Timing::FIELDS.contains(&k.as_str()))
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect();
    typed::<Timing>(serde_json::Value::Object(timing)).err()
}

/// Parse a log's text; `path` names it in messages.
pub(crate) fn parse_log(path: &Path, text: &str) -> Result<SessionLog> {
    let torn_tail = !text.is_empty() && !text.ends_with('\n');
    let lines: Vec<&str> = text.lines().collect();
    let mut header = None;
    let mut trials = Vec::new();
    let mut trial_lines = Vec::new();
    let mut resumes = Vec::new();
    let mut warnings = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let lineno = i + 1;
        if line.trim().is_empty() {
            continue;
        }
        let parsed = parse_line(line);
        let is_last = i + 1 == lines.len();
        match parsed {
            Ok(LogLine::Header(h)) if header.is_none() && trials.is_empty() => {
                if h.format != LOG_FORMAT {
                    bail!(
                        "{}:{lineno}: field `format` is {:?}; this version reads {:?}",
                        path.display(),
                        h.format,
                        LOG_FORMAT
                    );
                }
                header = Some(h);
            }
            Ok(LogLine::Header(_)) => {
                bail!("{}:{lineno}: a second header line", path.display())
            }
            Ok(LogLine::Trial(_)) if header.is_none() => {
                bail!("{}:{lineno}: trial before the header line", path.display())
            }
            Ok(LogLine::Trial(t)) => {
                trials.push(t);
                trial_lines.push(lineno);
            }
            Ok(LogLine::Resume(_)) if header.is_none() => {
                bail!("{}:{lineno}: resume line before the header line", path.display())
            }
            Ok(LogLine::Resume(r)) => resumes.push(r),
            Err(_) if is_last && torn_tail && header.is_none() => {
                return Err(TornHeader {
                    path: path.to_path_buf(),
                }
                .into());
            }
            Err(e) if is_last && torn_tail => warnings.push(format!(
                "{}:{lineno}: ignoring an incomplete last line (the session was interrupted while writing it): {e}",
                path.display()
            )),
            Err(e) => bail!(
                "{}:{lineno}: not a valid log line: {}",
                path.display(),
                renderer::quote::clip_quoted(&e.to_string())
            ),
        }
    }
    let Some(header) = header else {
        bail!("{}: no header line; not a session log", path.display());
    };
    Ok(SessionLog {
        path: path.to_path_buf(),
        header,
        trials,
        trial_lines,
        resumes,
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) fn header() -> Header {
        Header {
            format: LOG_FORMAT.into(),
            subject: "s01".into(),
            session: 1,
            design: "demo".into(),
            design_hash: "ab".into(),
            seed: 3,
            app_version: "blurlab 0.1.0".into(),
            mode: "simulated".into(),
            started_unix: 0.0,
            trials_planned: 2,
            display: None,
            observer: None,
            participant: None,
        }
    }

    fn trial(index: u32) -> TrialRecord {
        TrialRecord {
            index,
            practice: false,
            scene: "plane".into(),
            point_set: PointSetKind::Hammersley,
            time_filter: TimeFilter::TruncatedBox,
            level: 8,
            test_stimulus: "t".into(),
            reference_stimulus: "r".into(),
            diff_pair: 1,
            test_side: Side::Left,
            response: 1,
            correct: true,
            timing: Timing {
                rt_ms: 500.0,
                ..Timing::default()
            },
            catch: false,
        }
    }

    fn text(lines: &[LogLine]) -> String {
        lines
            .iter()
            .map(|l| serde_json::to_string(l).unwrap() + "\n")
            .collect()
    }

    #[test]
    fn torn_last_line_is_ignored_with_warning() {
        let mut t = text(&[LogLine::Header(header()), LogLine::Trial(trial(0))]);
        let whole = serde_json::to_string(&LogLine::Trial(trial(1))).unwrap();
        t.push_str(&whole[..whole.len() / 2]);
        let log = parse_log(Path::new("x.jsonl"), &t).unwrap();
        assert_eq!(log.trials.len(), 1);
        assert_eq!(log.warnings.len(), 1);
    }

    #[test]
    fn corrupt_middle_line_is_an_error_with_line_number() {
        let mut t = text(&[LogLine::Header(header())]);
        t.push_str("{garbage\n");
        t.push_str(&text(&[LogLine::Trial(trial(0))]));
        let err = parse_log(Path::new("x.jsonl"), &t).unwrap_err().to_string();
        assert!(err.contains("x.jsonl:2"), "{err}");
    }

    #[test]
    fn a_torn_header_is_its_own_error() {
        let whole = serde_json::to_string(&LogLine::Header(header())).unwrap();
        let err = parse_log(Path::new("x.jsonl"), &whole[..40]).unwrap_err();
        assert!(err.downcast_ref::<TornHeader>().is_some(), "{err}");
        assert!(
            err.to_string().starts_with("x.jsonl:1: the header line"),
            "{err}"
        );
    }

    #[test]
    fn a_byte_that_is_not_utf8_is_named_by_line_and_column() {
        let mut t = text(&[LogLine::Header(header())]).into_bytes();
        t.extend_from_slice(b"{\"kind\": \xff}\n");
        let err = utf8_text(Path::new("x.jsonl"), t).unwrap_err().to_string();
        assert!(
            err.starts_with("x.jsonl:2: byte 0xff at column 10"),
            "{err}"
        );
    }

    #[test]
    fn a_character_cut_by_a_crash_in_the_last_line_is_a_torn_line() {
        let mut t = text(&[LogLine::Header(header())]).into_bytes();
        let whole = serde_json::to_string(&LogLine::Trial(trial(0))).unwrap();
        t.extend_from_slice(&whole.as_bytes()[..20]);
        t.extend_from_slice(&"é".as_bytes()[..1]);
        let log = parse_log(
            Path::new("x.jsonl"),
            &utf8_text(Path::new("x.jsonl"), t).unwrap(),
        );
        assert_eq!(log.unwrap().warnings.len(), 1);
    }

    #[test]
    fn unknown_format_is_refused() {
        let mut h = header();
        h.format = "blurlab-session/7".into();
        let err = parse_log(Path::new("x.jsonl"), &text(&[LogLine::Header(h)])).unwrap_err();
        assert!(err.to_string().contains("blurlab-session/1"));
    }

    /// Lines as the code before the shared `Timing` wrote them (a browser's with every field, a
    /// lab app's without the browser's two, a simulation's), read and written back byte for
    /// byte.
    #[test]
    fn trial_lines_keep_their_bytes_through_the_shared_timing() {
        let lines = [
            r#"{"kind":"trial","index":3,"practice":false,"scene":"plane","point_set":"hammersley","time_filter":"box","level":8,"test_stimulus":"t","reference_stimulus":"r","diff_pair":2,"test_side":"right","response":2,"correct":true,"rt_ms":612.5,"onsets_ms":[10.0,1210.25],"frame_times_ms":[10.0,26.7,43.35],"dropped_frames":1,"pauses":0,"preload_ms":12.0,"late_frames":2,"refresh_interval_ms":16.7,"catch":true}"#,
            r#"{"kind":"trial","index":0,"practice":true,"scene":"spheres","point_set":"stratified","time_filter":"triangle","level":16,"test_stimulus":"t","reference_stimulus":"r","diff_pair":1,"test_side":"left","response":2,"correct":false,"rt_ms":0.0,"onsets_ms":[0.0],"frame_times_ms":[0.0],"dropped_frames":0,"pauses":3,"preload_ms":0.5}"#,
            r#"{"kind":"trial","index":1,"practice":false,"scene":"plane","point_set":"hammersley","time_filter":"box","level":8,"test_stimulus":"t","reference_stimulus":"r","diff_pair":1,"test_side":"left","response":1,"correct":true,"rt_ms":0.0,"onsets_ms":[],"frame_times_ms":[],"dropped_frames":0,"pauses":0,"preload_ms":0.0}"#,
        ];
        for line in lines {
            let parsed = parse_line(line).unwrap();
            assert_eq!(serde_json::to_string(&parsed).unwrap(), line);
        }
    }

    /// Old logs without the timing fields (only `rt_ms` was ever required) still read.
    #[test]
    fn a_trial_line_with_only_rt_ms_reads_with_default_timing() {
        let line = r#"{"kind":"trial","index":0,"practice":false,"scene":"plane","point_set":"hammersley","time_filter":"box","level":8,"test_stimulus":"t","reference_stimulus":"r","diff_pair":1,"test_side":"left","response":1,"correct":true,"rt_ms":500}"#;
        let LogLine::Trial(t) = parse_line(line).unwrap() else {
            panic!("not a trial")
        };
        assert_eq!(t.timing, trial(0).timing);
        let missing = line.replace(r#","rt_ms":500"#, "");
        assert!(parse_line(&missing).unwrap_err().contains("`rt_ms`"));
    }

    /// A timing field of the wrong type is named, as every other field is.
    #[test]
    fn a_bad_timing_field_is_named() {
        let line = r#"{"kind":"trial","index":0,"practice":false,"scene":"plane","point_set":"hammersley","time_filter":"box","level":8,"test_stimulus":"t","reference_stimulus":"r","diff_pair":1,"test_side":"left","response":1,"correct":true,"rt_ms":500,"frame_times_ms":"fast"}"#;
        let err = parse_line(line).unwrap_err();
        assert!(err.contains("field `frame_times_ms`"), "{err}");
    }
}
