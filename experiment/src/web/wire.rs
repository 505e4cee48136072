//! The JSON the browser and the server exchange (docs/web.md, "HTTP API"). Nothing here names a
//! level, point set, scene, stimulus id or which pair differs: the browser sees opaque video ids
//! (`video_ids.rs`).

use crate::log::Timing;
use serde::{Deserialize, Serialize};

/// What the browser shows now.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct State {
    /// `consent`, `display_check`, `instructions`, `practice`, `main`, `break`, `done` or
    /// `screened_out`.
    pub phase: String,
    pub session: u32,
    pub video: Video,
    pub playback: PlaybackInfo,
    pub keys: Keys,
    /// Device pixels the trial needs at 1:1.
    pub min_window_px: [u32; 2],
    pub progress: Progress,
    pub trial: Option<TrialView>,
    /// Ids of the videos the next trials show that the current trial does not, in the order
    /// they are needed: the browser fetches them while this trial plays.
    pub ahead: Vec<String>,
    pub client: ClientSettings,
    pub message: Option<String>,
    /// Where the browser goes after this screen: the platform's completion URL (`done`) or
    /// screen-out URL (`screened_out`), when the design's `online` names them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub redirect: Option<String>,
}

/// How the browser fetches, keeps and decodes videos (`blurlab serve` options).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct ClientSettings {
    /// Frames decoded ahead of the one shown, per video playing (the rest are decoded while
    /// the video plays).
    pub lookahead_frames: u32,
    /// Most encoded bytes the browser keeps (LRU beyond; never the current or next trial's).
    pub cache_bytes: u64,
    /// Trials whose videos are fetched ahead.
    pub fetch_ahead_trials: u32,
    /// Where videos are fetched: `None` for this server (`/api/s/{token}/video/{id}`), else a
    /// static server's URL: `{video_base}/{id}.webpframes`.
    pub video_base: Option<String>,
}

impl Default for ClientSettings {
    fn default() -> Self {
        Self {
            lookahead_frames: 24,
            cache_bytes: 4 << 30,
            fetch_ahead_trials: 4,
            video_base: None,
        }
    }
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Video {
    pub width: u32,
    pub height: u32,
    pub fps: f64,
    pub frames: u32,
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct PlaybackInfo {
    /// `sequential` or `simultaneous` (the design's `grid`).
    pub layout: String,
    pub loops: u32,
    pub fixation_ms: u32,
    pub gap_ms: u32,
    pub spacing_px: u32,
    pub background: [u8; 3],
}

/// `KeyboardEvent.key` values that answer each pair.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Keys {
    pub pair1: Vec<String>,
    pub pair2: Vec<String>,
}

#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct Progress {
    pub practice_done: usize,
    pub practice_planned: usize,
    pub done: usize,
    pub planned: usize,
}

/// The trial to present: `pairs[p][s]` is the video id of pair `p + 1`'s left (0) or right (1)
/// video. Pair 1 is shown first.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct TrialView {
    pub practice: bool,
    pub index: u32,
    pub pairs: [[String; 2]; 2],
}

/// `POST .../claim`.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Claim {
    pub tab: String,
}

/// `POST .../advance`.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Advance {
    pub tab: String,
    /// `instructions` or `break`.
    pub from: String,
}

/// `POST .../consent`: the participant's answer to the consent text.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConsentAnswer {
    pub tab: String,
    pub accept: bool,
}

/// `POST .../screen_out`: the page found a reason the participant cannot take part.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScreenOut {
    pub tab: String,
    /// `window_too_small` or `browser_unsupported`.
    pub reason: String,
}

/// `POST .../display`: what the browser measured before the first trial.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DisplayFacts {
    pub tab: String,
    pub screen_px: [u32; 2],
    pub window_px: [u32; 2],
    pub device_pixel_ratio: f64,
    pub px_per_mm: f64,
    pub viewing_distance_mm: f64,
    pub pixels_per_degree: f64,
    pub refresh_interval_ms: f64,
    pub user_agent: String,
    pub fullscreen: bool,
}

/// `POST .../answer`.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Answer {
    pub tab: String,
    pub session: u32,
    pub practice: bool,
    pub trial: u32,
    pub response: u8,
    /// What the browser measured, as the log keeps it (a browser does not pause: `pauses` 0).
    pub timing: Timing,
}

/// Which answer an acknowledgement is for: the idempotency key (with the subject's token).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq, Hash)]
pub struct Ack {
    pub session: u32,
    pub practice: bool,
    pub trial: u32,
}

#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct Feedback {
    pub correct: bool,
}

/// The reply to an answer: sent only once its log line is on disk.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct AnswerReply {
    pub ack: Ack,
    pub feedback: Option<Feedback>,
    pub state: State,
}

/// Every error body.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct ErrorBody {
    pub error: String,
}
