//! Loading a design file (`Design::load`, `Design::parse`): parsing, and every check a session
//! relies on, each message naming the file and the field. A module of its own above both the
//! design's types (`crate::design`) and the procedures: a design is refused when its adaptive
//! procedure could not run it (`crate::procedure::check`), and the procedures read the design's
//! types, so the types cannot do the loading without a module cycle.

use crate::design::keys::{self, RESERVED_KEYS};
use crate::design::{
    DESIGN_FORMAT, Design, DesignFile, MAX_ALTERNATIVES, MAX_PLAYBACK_FPS, MAX_TRIALS, Playback,
    ReferenceChoice, ResponseKeys, Task,
};
use anyhow::{Result, bail};
use renderer::paths::lexical_normal;
use std::collections::BTreeSet;
use std::path::Path;

impl Design {
    /// Read, parse and validate a design file.
    pub fn load(path: &Path) -> Result<Self> {
        let text = renderer::utf8::read(path, "design file")?;
        Self::parse(path, &text)
    }

    /// Parse and validate design text; `path` names it in messages and anchors `manifest`.
    pub fn parse(path: &Path, text: &str) -> Result<Self> {
        let value: serde_json::Value = renderer::json::from_str(text, path, "design file")?;
        let format = value.get("format").and_then(|f| f.as_str());
        if format != Some(DESIGN_FORMAT) {
            bail!(
                "{}: field `format` is {}; this version reads {DESIGN_FORMAT:?}",
                path.display(),
                value
                    .get("format")
                    .map_or("missing".into(), |f| f.to_string())
            );
        }
        // serde's message for an enum given two keys is "expected value at line n".
        if let Some(p) = value.get("procedure").and_then(|p| p.as_object())
            && p.len() != 1
        {
            let keys: Vec<&str> = p.keys().map(String::as_str).collect();
            bail!(
                "{}: field `procedure` names {} procedures ({}); expected exactly one procedure: \
                 \"constant_stimuli\", {{\"quest_plus\": {{...}}}} or {{\"staircase\": {{...}}}}",
                path.display(),
                keys.len(),
                keys.join(", ")
            );
        }
        // Parsed again from the text (not the value) so that errors name the line.
        let file: DesignFile = renderer::json::from_str(text, path, "design file")?;
        validate(&file).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        let folder = path.parent().unwrap_or(Path::new(""));
        Ok(Self {
            path: path.to_path_buf(),
            manifest_path: lexical_normal(&folder.join(&file.manifest)),
            hash: canonical_hash(&value),
            file,
        })
    }
}

/// SHA-256 of the canonical form: serde_json's map is sorted by key, and `to_string` is compact,
/// so whitespace and key order in the file do not change the hash but any value does.
fn canonical_hash(value: &serde_json::Value) -> String {
    let canonical = serde_json::to_string(value).expect("a parsed Value serializes");
    renderer::digest::sha256_hex(canonical.as_bytes())
}

/// Every check a session relies on; the message names the field.
fn validate(f: &DesignFile) -> Result<()> {
    if f.name.is_empty() || !f.name.chars().all(is_name_char) {
        bail!(
            "field `name` is {:?}; expected letters, digits, `-` or `_` (it names a folder)",
            f.name
        );
    }
    if f.manifest.is_empty() {
        bail!("field `manifest` is empty; expected the stimulus manifest's path");
    }
    names("factors.scenes", &f.factors.scenes)?;
    names("factors.point_sets", &f.factors.point_sets)?;
    names("factors.time_filters", &f.factors.time_filters)?;
    levels("levels", &f.levels)?;
    if f.repeats == 0 {
        bail!("field `repeats` is 0; expected at least 1 trial per condition and level");
    }
    let fac = &f.factors;
    let trials = [
        fac.scenes.len(),
        fac.point_sets.len(),
        fac.time_filters.len(),
        f.levels.len(),
    ]
    .iter()
    .fold(u64::from(f.repeats), |n, &k| n.saturating_mul(k as u64));
    if trials > MAX_TRIALS {
        bail!(
            "field `repeats` is {}: with {} conditions x {} levels that plans {trials} main trials \
             per subject; expected at most {MAX_TRIALS}",
            f.repeats,
            fac.scenes.len() * fac.point_sets.len() * fac.time_filters.len(),
            f.levels.len()
        );
    }
    if f.practice.trials > MAX_TRIALS as u32 {
        bail!(
            "field `practice.trials` is {}; expected at most {MAX_TRIALS}",
            f.practice.trials
        );
    }
    if let Task::Alternatives(m) = f.task
        && !(2..=MAX_ALTERNATIVES).contains(&m)
    {
        bail!("field `task.alternatives` is {m}; expected 2 to {MAX_ALTERNATIVES} alternatives");
    }
    playback(&f.playback)?;
    if let ReferenceChoice::Stimuli(m) = &f.reference {
        for scene in &f.factors.scenes {
            if m.get(scene).is_none_or(|id| id.is_empty()) {
                bail!("field `reference.stimuli` names no reference stimulus for scene {scene:?}");
            }
        }
    }
    if let Some(l) = &f.practice.levels {
        levels("practice.levels", l)?;
        if let Some(x) = l.iter().find(|x| !f.levels.contains(x)) {
            bail!(
                "field `practice.levels` holds {x}, which is not among `levels` {:?}; practice \
                 uses the study's stimuli",
                f.levels
            );
        }
    }
    if let Some(d) = &f.display {
        d.validate()?;
    }
    adaptive(f)?;
    if let Some(c) = &f.catch_trials {
        c.validate()?;
    }
    if let Some(o) = &f.online {
        o.validate()?;
    }
    if let Some(e) = &f.exclusion {
        e.validate()?;
    }
    validate_keys(&f.keys)
}

/// An adaptive procedure's own fields, and its most trials per subject.
fn adaptive(f: &DesignFile) -> Result<()> {
    f.procedure.validate(&f.levels)?;
    crate::procedure::check(&f.procedure, &f.levels)?;
    let p = &f.procedure;
    let conditions = [
        f.factors.scenes.len(),
        f.factors.point_sets.len(),
        f.factors.time_filters.len(),
    ]
    .iter()
    .fold(1u64, |n, &k| n.saturating_mul(k as u64));
    let trials = conditions
        .saturating_mul(p.tracks_per_condition() as u64)
        .saturating_mul(p.trials_per_track() as u64);
    if trials > MAX_TRIALS {
        bail!(
            "field `procedure`: {conditions} conditions x {} tracks x {} trials plan {trials} main \
             trials per subject; expected at most {MAX_TRIALS}",
            p.tracks_per_condition(),
            p.trials_per_track()
        );
    }
    Ok(())
}

fn playback(p: &Playback) -> Result<()> {
    if let Some(fps) = p.fps
        && !(1.0..=MAX_PLAYBACK_FPS).contains(&fps)
    {
        bail!(
            "field `playback.fps` is {}; expected frames per second from 1 to \
             {MAX_PLAYBACK_FPS}",
            renderer::limits::shortest(fps)
        );
    }
    if !(1..=100).contains(&p.loops) {
        bail!("field `playback.loops` is {}; expected 1 to 100", p.loops);
    }
    for (field, ms) in [("fixation_ms", p.fixation_ms), ("gap_ms", p.gap_ms)] {
        if ms > 60_000 {
            bail!("field `playback.{field}` is {ms}; expected at most 60000 (a minute)");
        }
    }
    let most = renderer::limits::MAX_IMAGE_SIDE;
    if p.spacing_px > most {
        bail!(
            "field `playback.spacing_px` is {}; expected at most {most} pixels",
            p.spacing_px
        );
    }
    Ok(())
}

fn validate_keys(k: &ResponseKeys) -> Result<()> {
    for (field, list) in [("keys.pair1", &k.pair1), ("keys.pair2", &k.pair2)] {
        if list.is_empty() {
            bail!("field `{field}` is empty; expected at least one key");
        }
        for key in list {
            if !keys::is_known(key) {
                bail!(
                    "field `{field}` holds {key:?}, not a key name this app knows; use one of {}",
                    keys::KNOWN_KEYS.join(", ")
                );
            }
            if RESERVED_KEYS.contains(&keys::canonical(key)) {
                bail!(
                    "field `{field}` holds {key:?}, which the app reserves (Esc pauses, Space continues)"
                );
            }
        }
    }
    let one: BTreeSet<&str> = k.pair1.iter().map(|s| keys::canonical(s)).collect();
    if let Some(both) = k.pair2.iter().find(|s| one.contains(keys::canonical(s))) {
        bail!("fields `keys.pair1` and `keys.pair2` both hold {both:?}");
    }
    Ok(())
}

fn is_name_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '-' || c == '_'
}

fn names<T: Ord + std::fmt::Debug + std::fmt::Display>(field: &str, list: &[T]) -> Result<()> {
    if list.is_empty() {
        bail!("field `{field}` is empty; expected at least one name");
    }
    let mut seen = BTreeSet::new();
    for n in list {
        if n.to_string().is_empty() {
            bail!("field `{field}` holds an empty name");
        }
        if !seen.insert(n) {
            bail!("field `{field}` names {n:?} twice");
        }
    }
    Ok(())
}

fn levels(field: &str, list: &[u32]) -> Result<()> {
    if list.is_empty() {
        bail!("field `{field}` is empty; expected samples-per-pixel levels");
    }
    let most = renderer::limits::MAX_SPP;
    if let Some(x) = list.iter().find(|&&x| x == 0 || x > most) {
        bail!("field `{field}` holds {x}; expected samples per pixel from 1 to {most}");
    }
    let set: BTreeSet<_> = list.iter().collect();
    if set.len() != list.len() {
        bail!("field `{field}` holds a level twice: {list:?}");
    }
    Ok(())
}
