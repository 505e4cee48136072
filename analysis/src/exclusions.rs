//! Applying the exclusion criteria (issue 49): the design's `exclusion` with `analyze`'s flags
//! in place of the fields they set, checked against every subject of the session logs
//! ([`crate::data::screening`]); the failing subjects named in the report and left out of the
//! fits (or kept, named, with `--keep-excluded`).

use crate::data::screening::{self, SubjectFacts};
use crate::data::{Dataset, Source};
use anyhow::Result;
use experiment::design::online::Exclusion;
use experiment::log::SessionLog;

/// The design's criteria with every field the flags set replaced.
pub fn merged(design: Option<&Exclusion>, flags: &Exclusion) -> Exclusion {
    let mut c = design.cloned().unwrap_or_default();
    let d = &flags.display;
    c.min_catch_accuracy = flags.min_catch_accuracy.or(c.min_catch_accuracy);
    c.max_bad_frames = flags.max_bad_frames.or(c.max_bad_frames);
    c.min_rt_ms = flags.min_rt_ms.or(c.min_rt_ms);
    c.max_fast_share = flags.max_fast_share.or(c.max_fast_share);
    c.require_finished |= flags.require_finished;
    c.display.pixels_per_degree = d.pixels_per_degree.or(c.display.pixels_per_degree);
    c.display.viewing_distance_mm = d.viewing_distance_mm.or(c.display.viewing_distance_mm);
    c.display.refresh_hz = d.refresh_hz.or(c.display.refresh_hz);
    c
}

/// Check every subject of `ds` (session logs) against `c`; unless `keep`, leave the failing
/// ones out with their reasons. Returns `exclusions.csv`'s text, or `None` when there are no
/// criteria (nothing changes: the report is as without this step).
pub fn screen(c: &Exclusion, keep: bool, ds: &mut Dataset) -> Result<Option<String>> {
    if c.is_empty() || ds.source != Source::SessionLogs {
        return Ok(None);
    }
    c.validate()?;
    let logs = ds
        .files
        .iter()
        .map(|f| SessionLog::read(f))
        .collect::<Result<Vec<_>>>()?;
    let rows: Vec<(SubjectFacts, Vec<String>)> = screening::facts(&logs)
        .into_iter()
        .map(|f| {
            let why = screening::reasons(&f, c);
            (f, why)
        })
        .collect();
    let failing: Vec<(String, Option<String>)> = rows
        .iter()
        .filter(|(f, why)| !why.is_empty() && ds.subjects.contains(&f.subject))
        .map(|(f, why)| (f.subject.clone(), Some(why.join("; "))))
        .collect();
    let named: Vec<String> = failing
        .iter()
        .map(|(s, why)| format!("{s} ({})", why.as_deref().unwrap_or("")))
        .collect();
    if keep && !failing.is_empty() {
        ds.warnings.push(format!(
            "the exclusion criteria name {} subject(s), kept in the fits (--keep-excluded): {}",
            failing.len(),
            named.join(", ")
        ));
    } else if !failing.is_empty() {
        ds.exclude(&failing)?;
    }
    Ok(Some(screening::csv(&rows, c.min_rt_ms)))
}
