//! Reading session logs into a [`Dataset`]: the files of a folder or the files given, every
//! main trial checked ([`crate::validate`]), against the design and its manifest when given.

use super::dropped::DroppedFrames;
use super::{Dataset, Observation};
use anyhow::{Result, bail};
use experiment::Design;
use experiment::log::{SessionLog, TornHeader};
use renderer::manifest::Manifest;
use std::path::{Path, PathBuf};

impl Dataset {
    /// Read session logs: every `*.jsonl` in a folder, or the given files. Refuses an empty
    /// selection, mixed designs, unknown formats (the reader) and level 0.
    /// Files ending in `.csv` are counts tables ([`Dataset::read_counts`]); logs and tables
    /// cannot be mixed.
    pub fn read(inputs: &[PathBuf]) -> Result<Self> {
        Self::read_checked(inputs, None, false)
    }

    /// [`Dataset::read`], with every main trial of the logs checked ([`crate::validate`]),
    /// against `design` when given. A finding is an error naming file, line and field; with
    /// `lenient` the trial is left out instead and the finding becomes a warning (counted, and
    /// printed by the report).
    pub fn read_checked(
        inputs: &[PathBuf],
        design: Option<&Design>,
        lenient: bool,
    ) -> Result<Self> {
        Self::read_with(inputs, design, lenient, None)
    }

    /// [`Dataset::read_checked`], with trials over a number of dropped frames named (and left
    /// out when `dropped` says so, [`super::dropped`]).
    pub fn read_with(
        inputs: &[PathBuf],
        design: Option<&Design>,
        lenient: bool,
        dropped: Option<&DroppedFrames>,
    ) -> Result<Self> {
        let files = collect_files(inputs)?;
        let is_csv = |f: &PathBuf| f.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv"));
        if let Some(csv) = files.iter().find(|f| is_csv(f)) {
            if let Some(log) = files.iter().find(|f| !is_csv(f)) {
                bail!(
                    "{} is a counts table and {} a session log; analyze one kind of input at a time",
                    csv.display(),
                    log.display()
                );
            }
            return Self::read_counts(&files);
        }
        let mut logs = Vec::with_capacity(files.len());
        let mut skipped = Vec::new();
        for f in &files {
            match SessionLog::read(f) {
                Ok(log) => logs.push(log),
                Err(e) => match e.downcast_ref::<TornHeader>() {
                    Some(torn) if lenient => skipped.push(format!("{torn}: skipped (--lenient)")),
                    Some(_) => bail!(
                        "{e}; remove the file, or `blurlab analyze --lenient` skips it with a warning"
                    ),
                    None => return Err(e),
                },
            }
        }
        if logs.is_empty() && !skipped.is_empty() {
            bail!("no session log to analyze: {}", skipped.join("; "));
        }
        let manifest = match design {
            Some(d) if d.manifest_path.exists() => Some(Manifest::load(&d.manifest_path)?),
            Some(d) => {
                skipped.push(format!(
                    "the design's manifest {} is not here: the trials' stimuli were checked \
                     against the design only",
                    d.manifest_path.display()
                ));
                None
            }
            None => None,
        };
        let mut ds = Self::from_logs_with(&logs, design, manifest.as_ref(), lenient, dropped)?;
        ds.warnings.append(&mut skipped);
        Ok(ds)
    }

    /// Aggregate already-read logs (see [`Dataset::read`] for the checks).
    pub fn from_logs(logs: &[SessionLog]) -> Result<Self> {
        Self::from_logs_against(logs, None, None, false)
    }

    /// [`Dataset::from_logs`] with the checks of [`Dataset::read_checked`]: every main trial,
    /// against `design` and its `manifest` when given; `lenient` leaves failing trials out.
    pub fn from_logs_against(
        logs: &[SessionLog],
        design: Option<&Design>,
        manifest: Option<&Manifest>,
        lenient: bool,
    ) -> Result<Self> {
        Self::from_logs_with(logs, design, manifest, lenient, None)
    }

    /// [`Dataset::from_logs_against`] with the dropped-frames policy of
    /// [`Dataset::read_with`].
    pub fn from_logs_with(
        logs: &[SessionLog],
        design: Option<&Design>,
        manifest: Option<&Manifest>,
        lenient: bool,
        dropped: Option<&DroppedFrames>,
    ) -> Result<Self> {
        let Some(first) = logs.first() else {
            bail!("no session logs to analyze");
        };
        // One design first: trials of two designs are not comparable, trial by trial or at all.
        for log in logs {
            if log.header.design_hash != first.header.design_hash {
                bail!(
                    "{}: field `design_hash` is {:?} (design {:?}), but {} has {:?} (design {:?}); \
                     analyze one design at a time",
                    log.path.display(),
                    log.header.design_hash,
                    log.header.design,
                    first.path.display(),
                    first.header.design_hash,
                    first.header.design
                );
            }
        }
        let findings = crate::validate::check(logs, design, manifest);
        if let (Some(f), false) = (findings.first(), lenient) {
            bail!(
                "{}{}; `blurlab analyze --lenient` leaves such trials out with a warning",
                f.message,
                match findings.len() {
                    1 => String::new(),
                    n => format!(" (and {} more findings)", n - 1),
                }
            );
        }
        let mut skip: std::collections::HashSet<(usize, usize)> =
            findings.iter().map(|f| (f.log, f.trial)).collect();
        let mut obs = Vec::new();
        let mut warnings = Vec::new();
        if !findings.is_empty() {
            warnings.push(format!(
                "{} main trials left out (--lenient): they failed the checks listed below",
                findings.len()
            ));
            warnings.extend(findings.iter().map(|f| f.message.clone()));
        }
        if let Some(d) = dropped {
            let (over, mut named) = super::dropped::over_limit(logs, &skip, d);
            skip.extend(over);
            warnings.append(&mut named);
        }
        for (li, log) in logs.iter().enumerate() {
            warnings.extend(log.warnings.iter().cloned());
            let kept = log.trials.iter().enumerate();
            for (_, t) in
                kept.filter(|(ti, t)| !t.practice && !t.catch && !skip.contains(&(li, *ti)))
            {
                obs.push(Observation {
                    subject: log.header.subject.clone(),
                    scene: t.scene.clone(),
                    point_set: t.point_set.to_string(),
                    time_filter: t.time_filter.to_string(),
                    level: t.level,
                    correct: t.correct,
                });
            }
        }
        if obs.is_empty() {
            let files: Vec<String> = logs.iter().map(|l| l.path.display().to_string()).collect();
            bail!(
                "{}: no main `trial` lines to analyze (practice trials are not analyzed, and \
                 --lenient leaves out those that fail the checks)",
                files.join(", ")
            );
        }
        let mut ds = Self::from_observations(&obs);
        ds.same_video_levels = same_video_levels(logs, &skip);
        ds.design = first.header.design.clone();
        ds.design_hash = first.header.design_hash.clone();
        for log in logs {
            *ds.sessions_by_mode
                .entry(log.header.mode.clone())
                .or_default() += 1;
        }
        ds.files = logs.iter().map(|l| l.path.clone()).collect();
        ds.files.sort();
        ds.warnings = warnings;
        Ok(ds)
    }
}

/// The levels whose every analyzed main trial compared a video with itself.
fn same_video_levels(
    logs: &[SessionLog],
    skip: &std::collections::HashSet<(usize, usize)>,
) -> Vec<u32> {
    // level -> whether every trial so far showed test = reference.
    let mut levels: std::collections::BTreeMap<u32, bool> = Default::default();
    for (li, log) in logs.iter().enumerate() {
        for (ti, t) in log.trials.iter().enumerate() {
            if !t.practice && !t.catch && !skip.contains(&(li, ti)) {
                let same = levels.entry(t.level).or_insert(true);
                *same &= t.test_stimulus == t.reference_stimulus;
            }
        }
    }
    levels
        .into_iter()
        .filter_map(|(level, same)| same.then_some(level))
        .collect()
}

/// Folders expand to their `*.jsonl` files (not recursive); files are taken as given.
fn collect_files(inputs: &[PathBuf]) -> Result<Vec<PathBuf>> {
    if inputs.is_empty() {
        bail!("no input: give a sessions folder or session log files");
    }
    let mut files = Vec::new();
    for input in inputs {
        if input.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(input)
                .map_err(|e| anyhow::anyhow!("cannot list folder {}: {e}", input.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| is_log(p))
                .collect();
            if found.is_empty() {
                bail!("folder {} holds no session logs (*.jsonl)", input.display());
            }
            files.append(&mut found);
        } else if input.is_file() {
            files.push(input.clone());
        } else {
            bail!("input {} does not exist", input.display());
        }
    }
    files.sort();
    files.dedup();
    Ok(files)
}

fn is_log(p: &Path) -> bool {
    p.is_file() && p.extension().is_some_and(|e| e == "jsonl")
}
