//! A study run online (issue 49): the design's `online` field (the recruitment platform's
//! query parameters, completion and screen-out URLs, consent and debriefing texts, the display
//! ranges that screen a participant out at the check), `catch_trials` (attention checks
//! interleaved with the main trials) and `exclusion` (the criteria `analyze` applies to every
//! subject). All optional: a design without them runs and analyzes as before.

use anyhow::{Context, Result, bail};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A recruitment platform: which query parameter carries the participant's id, and which
/// others are kept in the log header.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Platform {
    /// `PROLIFIC_PID`, keeping `STUDY_ID` and `SESSION_ID`.
    Prolific,
    /// SONA Systems: `id` (the study URL ends `?id=%SURVEY_CODE%`).
    Sona,
    /// Amazon Mechanical Turk: `workerId`, keeping `assignmentId` and `hitId`.
    Mturk,
    /// The parameters the design names (`id_param`, `params`).
    #[default]
    Custom,
}

renderer::named!(Platform, "platform", [
    Prolific => "prolific", Sona => "sona", Mturk => "mturk", Custom => "custom"
]);

impl Platform {
    /// The id parameter and the kept parameters a platform sends.
    pub fn defaults(self) -> (&'static str, &'static [&'static str]) {
        match self {
            Platform::Prolific => ("PROLIFIC_PID", &["STUDY_ID", "SESSION_ID"]),
            Platform::Sona => ("id", &[]),
            Platform::Mturk => ("workerId", &["assignmentId", "hitId"]),
            Platform::Custom => ("participant", &[]),
        }
    }
}

/// The design's `online` field.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct Online {
    pub platform: Platform,
    /// The query parameter with the participant's id (default: the platform's).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub id_param: Option<String>,
    /// Other query parameters logged in the header (default: the platform's).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub params: Option<Vec<String>>,
    /// Where a finished participant is sent; `{code}` and `{id}` are replaced.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub completion_url: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub completion_code: Option<String>,
    /// Where a screened-out participant is sent (consent declined, display check failed).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub screen_out_url: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub screen_out_code: Option<String>,
    /// Consent text file (Markdown or plain text), relative to the design file.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub consent: Option<String>,
    /// Debriefing text file shown after the last trial.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub debriefing: Option<String>,
    /// Display facts outside these ranges screen the participant out at the display check.
    #[serde(skip_serializing_if = "DisplayRanges::is_empty")]
    pub screening: DisplayRanges,
}

/// Ranges of a browser's display facts (each `[lowest, highest]`, inclusive).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct DisplayRanges {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pixels_per_degree: Option<[f64; 2]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub viewing_distance_mm: Option<[f64; 2]>,
    /// Refresh rate in Hz (1000 / the measured refresh interval).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refresh_hz: Option<[f64; 2]>,
}

/// The design's `catch_trials` field.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CatchTrials {
    /// Share of main trials that are catch trials, in (0, 0.5]: one in every
    /// `round(1 / rate)` main trials, at a place in each block drawn from the subject's seed.
    pub rate: f64,
}

impl CatchTrials {
    /// Main trials per block holding one catch trial.
    pub fn block(&self) -> u32 {
        (1.0 / self.rate).round().max(2.0) as u32
    }
}

/// The design's `exclusion` field: who `analyze` leaves out (every criterion optional).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct Exclusion {
    /// Least share of catch trials answered correctly.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_catch_accuracy: Option<f64>,
    /// Most share of frames dropped or late over the main trials.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_bad_frames: Option<f64>,
    /// A response faster than this (ms after the last video ended) counts as fast...
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_rt_ms: Option<f64>,
    /// ...and a subject with a larger share of fast responses is excluded (default 0.2).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_fast_share: Option<f64>,
    /// Leave out subjects who did not finish every main trial.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub require_finished: bool,
    /// Display facts a subject's browser must have had.
    #[serde(skip_serializing_if = "DisplayRanges::is_empty")]
    pub display: DisplayRanges,
}

impl Exclusion {
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }
}

impl DisplayRanges {
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }

    /// Each range with its field name.
    pub fn named(&self) -> [(&'static str, Option<[f64; 2]>); 3] {
        [
            ("pixels_per_degree", self.pixels_per_degree),
            ("viewing_distance_mm", self.viewing_distance_mm),
            ("refresh_hz", self.refresh_hz),
        ]
    }

    /// The first fact outside its range, as a reason ("pixels_per_degree 12.3 outside [20, 80]").
    pub fn violation(
        &self,
        ppd: f64,
        distance_mm: f64,
        refresh_interval_ms: f64,
    ) -> Option<String> {
        let hz = if refresh_interval_ms > 0.0 {
            1000.0 / refresh_interval_ms
        } else {
            0.0
        };
        self.named()
            .into_iter()
            .zip([ppd, distance_mm, hz])
            .find_map(|((name, range), x)| {
                let [lo, hi] = range?;
                (!(lo..=hi).contains(&x)).then(|| format!("{name} {x:.1} outside [{lo}, {hi}]"))
            })
    }

    pub fn validate(&self, field: &str) -> Result<()> {
        for (name, range) in self.named() {
            if let Some([lo, hi]) = range
                && !(lo.is_finite() && hi.is_finite() && 0.0 <= lo && lo <= hi)
            {
                bail!(
                    "field `{field}.{name}` is [{lo}, {hi}]; expected [lowest, highest], 0 <= lowest <= highest"
                );
            }
        }
        Ok(())
    }
}

/// A query parameter's name: 1 to 64 letters, digits, `_`, `-` or `.`.
pub fn check_param_name(field: &str, name: &str) -> Result<()> {
    if name.is_empty()
        || name.len() > 64
        || !name
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'-' | b'.'))
    {
        bail!("field `{field}` is {name:?}; expected 1 to 64 letters, digits, `_`, `-` or `.`");
    }
    Ok(())
}

/// A completion or screen-out code: 1 to 64 letters, digits, `_` or `-`.
fn check_code(field: &str, code: &str) -> Result<()> {
    if code.is_empty()
        || code.len() > 64
        || !code
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'-'))
    {
        bail!("field `{field}` is {code:?}; expected 1 to 64 letters, digits, `_` or `-`");
    }
    Ok(())
}

/// An http(s) URL with no spaces, quotes or angle brackets (it becomes a redirect).
pub fn check_url(field: &str, url: &str) -> Result<()> {
    if !is_plain_url(url) {
        bail!("field `{field}` is {url:?}; expected {PLAIN_URL}");
    }
    Ok(())
}

/// What [`is_plain_url`] accepts, for messages.
pub const PLAIN_URL: &str = "an http:// or https:// URL with a host, of at most 2000 characters \
                             without spaces, quotes, `<`, `>` or `\\`";

/// An absolute http(s) URL with a host that is safe to put in a header or a redirect.
pub fn is_plain_url(url: &str) -> bool {
    let scheme = url.starts_with("https://") || url.starts_with("http://");
    let host = url.split("://").nth(1).unwrap_or("");
    scheme
        && !host.is_empty()
        && !host.starts_with('/')
        && url.len() <= 2000
        && !url.chars().any(|c| {
            c.is_whitespace() || c.is_control() || matches!(c, '"' | '\'' | '<' | '>' | '\\')
        })
}

impl Online {
    /// The id parameter and the kept ones, defaults filled in.
    pub fn id_param(&self) -> String {
        self.id_param
            .clone()
            .unwrap_or_else(|| self.platform.defaults().0.to_string())
    }

    pub fn params(&self) -> Vec<String> {
        self.params.clone().unwrap_or_else(|| {
            self.platform
                .defaults()
                .1
                .iter()
                .map(|s| s.to_string())
                .collect()
        })
    }

    /// The query a platform's study URL ends with: its placeholders for the ids (MTurk adds
    /// its own), or `?PARAM=<id>` for a custom one.
    pub fn study_query(&self) -> String {
        match (self.platform, &self.id_param) {
            (Platform::Prolific, None) => {
                "?PROLIFIC_PID={{%PROLIFIC_PID%}}&STUDY_ID={{%STUDY_ID%}}&SESSION_ID={{%SESSION_ID%}}"
                    .into()
            }
            (Platform::Sona, None) => "?id=%SURVEY_CODE%".into(),
            (Platform::Mturk, None) => String::new(),
            _ => format!("?{}=<participant id>", self.id_param()),
        }
    }

    pub fn validate(&self) -> Result<()> {
        check_param_name("online.id_param", &self.id_param())?;
        for p in self.params() {
            check_param_name("online.params", &p)?;
        }
        for (field, url, code) in [
            ("completion", &self.completion_url, &self.completion_code),
            ("screen_out", &self.screen_out_url, &self.screen_out_code),
        ] {
            if let Some(u) = url {
                check_url(&format!("online.{field}_url"), u)?;
            }
            if let Some(c) = code {
                check_code(&format!("online.{field}_code"), c)?;
            }
            if code.is_some() && url.as_ref().is_none_or(|u| !u.contains("{code}")) {
                bail!(
                    "field `online.{field}_code` is given, but `online.{field}_url` has no \
                     `{{code}}` to put it in"
                );
            }
        }
        for (field, file) in [("consent", &self.consent), ("debriefing", &self.debriefing)] {
            if file.as_ref().is_some_and(|f| f.trim().is_empty()) {
                bail!("field `online.{field}` is empty; expected a text file's path");
            }
        }
        self.screening.validate("online.screening")
    }

    /// `url` with `{code}` and `{id}` replaced (the id percent-encoded).
    pub fn fill(url: &str, code: Option<&str>, id: &str) -> String {
        url.replace("{code}", code.unwrap_or(""))
            .replace("{id}", &percent_encode(id))
    }
}

fn percent_encode(s: &str) -> String {
    s.bytes()
        .map(|b| {
            if b.is_ascii_alphanumeric() || matches!(b, b'-' | b'_' | b'.' | b'~') {
                (b as char).to_string()
            } else {
                format!("%{b:02X}")
            }
        })
        .collect()
}

impl CatchTrials {
    pub fn validate(&self) -> Result<()> {
        if !(self.rate > 0.0 && self.rate <= 0.5) {
            bail!(
                "field `catch_trials.rate` is {}; expected a share of main trials in (0, 0.5]",
                self.rate
            );
        }
        Ok(())
    }
}

impl Exclusion {
    pub fn validate(&self) -> Result<()> {
        for (name, x) in [
            ("min_catch_accuracy", self.min_catch_accuracy),
            ("max_bad_frames", self.max_bad_frames),
            ("max_fast_share", self.max_fast_share),
        ] {
            if let Some(x) = x
                && !(0.0..=1.0).contains(&x)
            {
                bail!("field `exclusion.{name}` is {x}; expected a share from 0 to 1");
            }
        }
        if let Some(ms) = self.min_rt_ms
            && !(0.0..=60_000.0).contains(&ms)
        {
            bail!("field `exclusion.min_rt_ms` is {ms}; expected milliseconds from 0 to 60000");
        }
        self.display.validate("exclusion.display")
    }
}

/// A consent or debriefing text, read for serving: its text and SHA-256.
#[derive(Clone, Debug, PartialEq)]
pub struct Text {
    pub path: PathBuf,
    pub text: String,
    pub sha256: String,
}

/// Longest consent or debriefing text.
pub const MAX_TEXT_BYTES: u64 = 64 * 1024;

/// Read the text file `field` names, relative to the design file at `design_path`.
pub fn read_text(design_path: &Path, field: &str, file: &str) -> Result<Text> {
    let path = design_path.parent().unwrap_or(Path::new("")).join(file);
    let len = std::fs::metadata(&path)
        .with_context(|| {
            format!(
                "{}: field `online.{field}` names {}, which cannot be read",
                design_path.display(),
                path.display()
            )
        })?
        .len();
    if len > MAX_TEXT_BYTES {
        bail!(
            "{}: field `online.{field}`: {} is {len} bytes; expected at most {MAX_TEXT_BYTES}",
            design_path.display(),
            path.display()
        );
    }
    let text = renderer::utf8::read(&path, field)?;
    if text.trim().is_empty() {
        bail!(
            "{}: field `online.{field}`: {} is empty",
            design_path.display(),
            path.display()
        );
    }
    Ok(Text {
        sha256: renderer::digest::sha256_hex(text.as_bytes()),
        path,
        text,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_fields_are_named() {
        let bad = |o: Online, field: &str| {
            let e = format!("{:#}", o.validate().unwrap_err());
            assert!(e.contains(field), "{field}: {e}");
        };
        bad(
            Online {
                id_param: Some("a b".into()),
                ..Online::default()
            },
            "online.id_param",
        );
        bad(
            Online {
                completion_url: Some("javascript:alert(1)".into()),
                ..Online::default()
            },
            "online.completion_url",
        );
        bad(
            Online {
                completion_url: Some("https://x.org/?cc=\"a\"".into()),
                ..Online::default()
            },
            "online.completion_url",
        );
        bad(
            Online {
                completion_url: Some("https://x.org/done".into()),
                completion_code: Some("C1".into()),
                ..Online::default()
            },
            "online.completion_code",
        );
        bad(
            Online {
                screen_out_url: Some("https://x.org/?cc={code}".into()),
                screen_out_code: Some("bad code!".into()),
                ..Online::default()
            },
            "online.screen_out_code",
        );
        bad(
            Online {
                screening: DisplayRanges {
                    refresh_hz: Some([70.0, 50.0]),
                    ..DisplayRanges::default()
                },
                ..Online::default()
            },
            "online.screening.refresh_hz",
        );
        let e = CatchTrials { rate: 0.7 }.validate().unwrap_err();
        assert!(e.to_string().contains("catch_trials.rate"));
        let e = Exclusion {
            min_catch_accuracy: Some(1.5),
            ..Exclusion::default()
        }
        .validate()
        .unwrap_err();
        assert!(e.to_string().contains("exclusion.min_catch_accuracy"));
    }

    #[test]
    fn platforms_fill_in_their_parameters_and_urls_their_codes() {
        let o = Online {
            platform: Platform::Prolific,
            ..Online::default()
        };
        assert_eq!(o.id_param(), "PROLIFIC_PID");
        assert_eq!(o.params(), ["STUDY_ID", "SESSION_ID"]);
        assert_eq!(
            Online::fill("https://x.org/c?cc={code}&p={id}", Some("C1"), "a b&"),
            "https://x.org/c?cc=C1&p=a%20b%26"
        );
        assert_eq!(CatchTrials { rate: 0.1 }.block(), 10);
        assert_eq!(CatchTrials { rate: 0.5 }.block(), 2);
    }

    #[test]
    fn display_ranges_name_the_fact_outside() {
        let r = DisplayRanges {
            pixels_per_degree: Some([20.0, 80.0]),
            refresh_hz: Some([55.0, 65.0]),
            ..DisplayRanges::default()
        };
        assert_eq!(r.violation(40.0, 500.0, 1000.0 / 60.0), None);
        assert!(
            r.violation(10.0, 500.0, 16.7)
                .unwrap()
                .contains("pixels_per_degree")
        );
        assert!(
            r.violation(40.0, 500.0, 1000.0 / 144.0)
                .unwrap()
                .contains("refresh_hz 144")
        );
    }
}
