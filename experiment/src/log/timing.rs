//! What was measured while a trial was presented: one type for the whole way from the player
//! to the log. The lab app's player and the browser's (through the wire answer) make it, the
//! session passes it on, and the log record carries it flattened, so its fields sit in the
//! trial line exactly where logs have always had them.

use serde::{Deserialize, Serialize};

/// A trial's timing, all in milliseconds; stamps are relative to the start of this run of
/// the session.
///
/// Unknown fields are refused where the type is read on its own (a browser's answer); inside
/// a log line it is flattened, and the line's other fields are the record's.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Timing {
    /// From the end of the last presentation to the answer.
    pub rt_ms: f64,
    /// Onset of each presented video pair.
    #[serde(default)]
    pub onsets_ms: Vec<f64>,
    /// Display time of each drawn frame.
    #[serde(default)]
    pub frame_times_ms: Vec<f64>,
    /// Frames whose index skipped during playback.
    #[serde(default)]
    pub dropped_frames: u32,
    /// Times the subject paused (Esc) during this trial; a pause during playback restarts it.
    #[serde(default)]
    pub pauses: u32,
    /// Spent loading the trial's frames before it could start (0 when simulated).
    #[serde(default)]
    pub preload_ms: f64,
    /// Frames shown later than their refresh (a browser's count; absent for the lab app).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub late_frames: Option<u32>,
    /// The refresh interval the browser measured during this trial.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refresh_interval_ms: Option<f64>,
}

impl Timing {
    /// The fields' names as logs and answers spell them.
    pub const FIELDS: [&str; 8] = [
        "rt_ms",
        "onsets_ms",
        "frame_times_ms",
        "dropped_frames",
        "pauses",
        "preload_ms",
        "late_frames",
        "refresh_interval_ms",
    ];
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_names_every_field() {
        let full = Timing {
            late_frames: Some(0),
            refresh_interval_ms: Some(0.0),
            ..Timing::default()
        };
        let serde_json::Value::Object(map) = serde_json::to_value(full).unwrap() else {
            panic!("not an object")
        };
        let mut names = Timing::FIELDS.to_vec();
        names.sort_unstable();
        assert_eq!(map.keys().collect::<Vec<_>>(), names);
    }
}
