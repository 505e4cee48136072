//! Reading a `.job` file into a [`JobFile`], with the [`SourceMap`] that lets the job's checks
//! name lines and keys.

use super::{DEFAULT_SEED, LINES, default_scene};
use crate::job::{IndependentReference, JOB_FORMAT, JobFile, Overrides, ReferenceSpec};
use crate::text::sampling::{self as options, Host};
use crate::text::{self, Entries, Entry, Line, SourceMap, at_line, names};
use anyhow::Result;
use std::path::Path;

/// The seven lines' model fields (the counts have none: they are implied by the lists).
const FIELDS: [&str; 7] = ["name", "", "levels", "", "point_sets", "", "time_filters"];

/// Read job text as if from `path` (for messages and the default scene).
pub fn read(text: &str, path: &Path) -> Result<(JobFile, SourceMap)> {
    let lines = text::lines(text, path)?;
    if lines.len() < 7 {
        let next = LINES[lines.len()];
        return Err(anyhow::anyhow!(
            "{}: has {} of the seven lines of a job (thesis Figure 12: {}); the next line \
             would be the {next}",
            path.display(),
            lines.len(),
            LINES.join("; ")
        ));
    }
    let mut map = SourceMap::default();
    for (k, field) in FIELDS.iter().enumerate().filter(|(_, f)| !f.is_empty()) {
        map.add(
            *field,
            Some(lines[k].number),
            format!("`{}` (line {} of 7)", LINES[k], k + 1),
        );
    }
    let name = match &lines[0].words[..] {
        [n] => n.clone(),
        w => {
            return Err(at_line(
                path,
                lines[0].number,
                format!("the job's `name` is one word; found `{}`", w.join(" ")),
            ));
        }
    };
    let levels: Vec<u32> = counted(path, &lines, 1)?
        .iter()
        .map(|w| {
            w.parse().map_err(|_| {
                at_line(
                    path,
                    lines[2].number,
                    format!("`levels`: `{w}` is not a whole number of samples per pixel"),
                )
            })
        })
        .collect::<Result<_>>()?;
    // Each word is checked here, located by the map: `point_sets[2]` on line 5.
    let point_sets = counted(path, &lines, 3)?
        .iter()
        .enumerate()
        .map(|(i, w)| {
            names::point_set_from_text(w)
                .map_err(|e| SourceMap::error(Some(&map), path, &format!("point_sets[{i}]"), e))
        })
        .collect::<Result<_>>()?;
    let time_filters = counted(path, &lines, 5)?
        .iter()
        .enumerate()
        .map(|(i, w)| {
            names::time_filter_from_text(w)
                .map_err(|e| SourceMap::error(Some(&map), path, &format!("time_filters[{i}]"), e))
        })
        .collect::<Result<_>>()?;
    let extension: Vec<Entry> = lines[7..].iter().map(Entry::of).collect();
    let first = extension.first().map_or(lines[6].number, |e| e.line);
    let context = "the job's extension lines (after the seven)".to_string();
    let mut e = Entries::new(path, context, first, "", extension, &["scene"], &mut map)?;
    let scenes = scenes(&mut e)?;
    let reference = reference(&mut e)?;
    let seed = e.integer::<u64>("seed", "seed")?.unwrap_or(DEFAULT_SEED);
    let overrides = Overrides {
        width: e.integer("width", "overrides.width")?,
        height: e.integer("height", "overrides.height")?,
        frames: e.integer("frames", "overrides.frames")?,
        first_frame: e.integer("firstframe", "overrides.first_frame")?,
        exr: e.boolean("exr", "overrides.exr")?,
        sampling: options::read(&mut e, "overrides.sampling", Host::Job)?,
    };
    let frames_per_unit = e.integer("framesperunit", "frames_per_unit")?;
    e.finish()?;
    if scenes.is_empty() {
        let d = default_scene(path);
        map.add(
            "scenes",
            None,
            format!(
                "the default scene `{d}` (no `scene` line, so the file named after the job, \
                 beside it; add a line `scene <file>` or pass --scene)"
            ),
        );
    }
    Ok((
        JobFile {
            format: JOB_FORMAT.into(),
            name,
            scenes: if scenes.is_empty() {
                vec![default_scene(path)]
            } else {
                scenes
            },
            levels,
            point_sets,
            time_filters,
            reference,
            seed,
            overrides,
            frames_per_unit,
        },
        map,
    ))
}

/// The list on line `k + 1` (0-based `k + 1`), checked against the count on line `k`.
fn counted<'l>(path: &Path, lines: &'l [Line], k: usize) -> Result<&'l [String]> {
    let (count_line, list_line) = (&lines[k], &lines[k + 1]);
    let count: usize = match &count_line.words[..] {
        [w] => w.parse().ok(),
        _ => None,
    }
    .ok_or_else(|| {
        at_line(
            path,
            count_line.number,
            format!(
                "`{}` (line {} of 7) is one whole number; found `{}`",
                LINES[k],
                k + 1,
                count_line.words.join(" ")
            ),
        )
    })?;
    let list = &list_line.words;
    if list.len() != count {
        return Err(at_line(
            path,
            list_line.number,
            format!(
                "`{}` lists {} ({}), but the `{}` on line {} is {count}; expected as many as \
                 the count",
                LINES[k + 1],
                list.len(),
                list.join(" "),
                LINES[k],
                count_line.number
            ),
        ));
    }
    Ok(list)
}

/// `scene <file>` lines, in order.
fn scenes(e: &mut Entries) -> Result<Vec<String>> {
    let mut out = Vec::new();
    for entry in e.take_all("scene", |k| format!("scenes[{k}]")) {
        match &entry.values[..] {
            [file] => out.push(file.clone()),
            v => {
                return Err(e.error(
                    &entry,
                    format!(
                        "expects one scene file (quote a name with spaces), found {} value(s)",
                        v.len()
                    ),
                ));
            }
        }
    }
    Ok(out)
}

/// `reference highestlevel` (the default) or `reference <spp>` with optional
/// `referencepointset` and `referencetimefilter`.
fn reference(e: &mut Entries) -> Result<ReferenceSpec> {
    let point_set = e.choice(
        "referencepointset",
        "reference.point_set",
        &names::POINT_SET_WORDS,
    )?;
    let time_filter = e.choice(
        "referencetimefilter",
        "reference.time_filter",
        &names::TIME_FILTER_WORDS,
    )?;
    let given = e.take("reference", "reference");
    let spp = match &given {
        None => None,
        Some(entry) => match &entry.values[..] {
            [w] if w == "highestlevel" => None,
            [w] => Some(w.parse::<u32>().map_err(|_| {
                e.error(
                    entry,
                    format!(
                        "expects `highestlevel` or the reference's samples per pixel; found `{w}`"
                    ),
                )
            })?),
            v => {
                return Err(e.error(
                    entry,
                    format!(
                        "expects `highestlevel` or the reference's samples per pixel; found \
                         `{}`",
                        v.join(" ")
                    ),
                ));
            }
        },
    };
    match spp {
        Some(spp) => Ok(ReferenceSpec::Independent(IndependentReference {
            spp,
            // `choice` admitted only these words.
            point_set: point_set.map(|w| names::point_set_from_text(&w).expect("a text word")),
            time_filter: time_filter
                .map(|w| names::time_filter_from_text(&w).expect("a text word")),
        })),
        None if point_set.is_some() || time_filter.is_some() => {
            let what = "`referencepointset` and `referencetimefilter` apply only to an \
                        independent reference (`reference <spp>`); the highest level has each \
                        condition's own point set and time filter";
            Err(match &given {
                Some(entry) => e.error(entry, format!("is `highestlevel`, but {what}")),
                None => e.block_error(format!("have no `reference <spp>` line, but {what}")),
            })
        }
        None => Ok(ReferenceSpec::HighestLevel),
    }
}
