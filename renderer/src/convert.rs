//! Converting scenes and jobs between the JSON formats and the thesis's text formats
//! (`render convert IN OUT`, format by extension: `.json`, `.scene`, `.job`). Both sides read
//! into the same model ([`SceneFile`], [`JobFile`]), so nothing is lost: JSON -> text -> JSON
//! gives the same model and the same JSON, and text -> JSON -> text reads back to the same
//! model (the text may differ in comments, order and left-out defaults). Relative paths inside
//! the file (models, environment maps, a job's scenes) are rewritten when the output lies in
//! another folder, so that they still name the same files.

use crate::job::{JobFile, line_format};
use crate::paths::{lexical_normal as normal, relative};
use crate::scene::{SceneFile, block_format};
use anyhow::{Result, bail};
use serde::Serialize;
use std::path::Path;

/// What a file holds.
#[derive(Clone, Debug, PartialEq)]
pub enum Document {
    Scene(SceneFile),
    Job(JobFile),
}

/// The formats, by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Json,
    SceneText,
    JobText,
}

fn format_of(path: &Path) -> Result<Format> {
    match path.extension().and_then(|e| e.to_str()) {
        Some("json") => Ok(Format::Json),
        Some(block_format::EXTENSION) => Ok(Format::SceneText),
        Some(line_format::EXTENSION) => Ok(Format::JobText),
        _ => bail!(
            "{}: expected a file ending in .json, .scene (thesis Figure 13) or .job (thesis \
             Figure 12)",
            path.display()
        ),
    }
}

/// Read a scene or job in any of the formats.
pub fn read(path: &Path) -> Result<Document> {
    let format = format_of(path)?;
    let text = crate::utf8::read(path, "file to convert")?;
    Ok(match format {
        Format::SceneText => Document::Scene(block_format::read(&text, path)?.0),
        Format::JobText => Document::Job(line_format::read(&text, path)?.0),
        Format::Json => {
            #[derive(serde::Deserialize)]
            struct Head {
                format: Option<String>,
            }
            let head: Head = crate::json::from_str(&text, path, "JSON scene or job file")?;
            match head.format.as_deref() {
                Some(crate::scene::SCENE_FORMAT) => {
                    Document::Scene(crate::scene::build::parse(&text, path)?)
                }
                Some(crate::job::JOB_FORMAT) => {
                    Document::Job(crate::json::from_str(&text, path, "job file")?)
                }
                other => bail!(
                    "{}: field `format` {}; expected {:?} or {:?}",
                    path.display(),
                    other.map_or("is missing".into(), |f| format!("is {f:?}")),
                    crate::scene::SCENE_FORMAT,
                    crate::job::JOB_FORMAT
                ),
            }
        }
    })
}

/// The text of `doc` in the format of `path`'s extension.
pub fn text(doc: &Document, path: &Path) -> Result<String> {
    let in_file = |e: anyhow::Error| e.context(format!("cannot write {}", path.display()));
    Ok(match (format_of(path)?, doc) {
        (Format::Json, Document::Scene(s)) => json(s)?,
        (Format::Json, Document::Job(j)) => json(j)?,
        (Format::SceneText, Document::Scene(s)) => block_format::write(s).map_err(in_file)?,
        (Format::JobText, Document::Job(j)) => line_format::write(j).map_err(in_file)?,
        (Format::SceneText, Document::Job(_)) => {
            bail!(
                "{}: a job cannot be written as a scene (.scene); write .job or .json",
                path.display()
            )
        }
        (Format::JobText, Document::Scene(_)) => {
            bail!(
                "{}: a scene cannot be written as a job (.job); write .scene or .json",
                path.display()
            )
        }
    })
}

/// Convert `input` into `output` (written atomically); paths inside are rebased from
/// `input`'s folder to `output`'s.
pub fn convert(input: &Path, output: &Path) -> Result<Document> {
    let mut doc = read(input)?;
    rebase_paths(&mut doc, folder(input), folder(output))?;
    let text = text(&doc, output)?;
    crate::atomic::write_atomic(output, text.as_bytes())?;
    Ok(doc)
}

/// The folder holding `file`: `.` for a bare file name, whose parent is the empty path (which
/// `std::path::absolute` refuses: `convert plane.scene out/plane.json` used to write
/// `../../../../plane.scene`-like paths, and the README's example absolute ones).
fn folder(file: &Path) -> &Path {
    match file.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Rewrite the relative paths a document holds so that, read from `to`, they name the files
/// they named read from `from`.
pub fn rebase_paths(doc: &mut Document, from: &Path, to: &Path) -> Result<()> {
    let from = std::path::absolute(from).unwrap_or_else(|_| from.to_path_buf());
    let to = std::path::absolute(to).unwrap_or_else(|_| to.to_path_buf());
    let (from, to) = (normal(&from), normal(&to));
    if from == to {
        return Ok(());
    }
    let fix = |p: &mut String| {
        if !Path::new(p.as_str()).is_absolute() {
            *p = relative(&normal(&from.join(&*p)), &to)
                .to_string_lossy()
                .into_owned();
        }
    };
    match doc {
        Document::Scene(s) => {
            for o in &mut s.objects {
                o.file.as_mut().map(fix);
            }
            if let Some(e) = &mut s.settings.environment {
                fix(&mut e.file);
            }
        }
        Document::Job(j) => j.scenes.iter_mut().for_each(fix),
    }
    Ok(())
}

/// Pretty JSON with arrays of numbers and strings on one line (`"location": [0, 0, 420]`),
/// ending in a newline. Serialized from the model directly, so f32 values keep their shortest
/// form (`0.3`, not `0.30000001192092896`).
pub fn json<T: Serialize>(value: &T) -> Result<String> {
    let pretty = serde_json::to_string_pretty(value)?;
    let mut out = String::with_capacity(pretty.len());
    let lines: Vec<&str> = pretty.lines().collect();
    let mut i = 0;
    while i < lines.len() {
        let line = lines[i];
        if line.ends_with('[') {
            // Collect the elements up to the closing bracket if all are scalars.
            let mut j = i + 1;
            let mut items = Vec::new();
            while j < lines.len() {
                let t = lines[j].trim();
                if t == "]" || t == "]," {
                    break;
                }
                if t.ends_with('{') || t.ends_with('[') {
                    items.clear();
                    j = lines.len();
                    break;
                }
                items.push(t.trim_end_matches(','));
                j += 1;
            }
            if j < lines.len() {
                let close = lines[j].trim();
                out.push_str(line);
                out.push_str(&items.join(", "));
                out.push_str(close);
                out.push('\n');
                i = j + 1;
                continue;
            }
        }
        out.push_str(line);
        out.push('\n');
        i += 1;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_are_rebased_relative_from_a_bare_file_name() {
        let demo = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/demo/job.json");
        let job = |scenes: &[&str]| {
            let Ok(Document::Job(mut j)) = read(Path::new(demo)) else {
                panic!("{demo} is a job")
            };
            j.scenes = scenes.iter().map(|s| s.to_string()).collect();
            Document::Job(j)
        };
        let cases = [
            ("plane.job", "out/sub/plane.json", "../../plane.scene"),
            ("scenes/jobs/t.json", "t.job", "scenes/thesis/plane.scene"),
            ("a/t.job", "b/t.json", "../a/plane.scene"),
        ];
        for (input, output, want) in cases {
            let scene = if input.starts_with("scenes") {
                "../thesis/plane.scene"
            } else {
                "plane.scene"
            };
            let mut doc = job(&[scene, "/abs/x.scene"]);
            rebase_paths(
                &mut doc,
                folder(Path::new(input)),
                folder(Path::new(output)),
            )
            .unwrap();
            let Document::Job(j) = doc else { panic!() };
            assert_eq!(j.scenes, [want, "/abs/x.scene"], "{input} -> {output}");
        }
    }

    #[test]
    fn scalar_arrays_go_on_one_line_and_parse_back() {
        let v = serde_json::json!({"a": [1.5, -0.0, 3], "b": [{"c": ["x, y", "]"]}], "d": []});
        let text = json(&v).unwrap();
        assert!(text.contains("\"a\": [1.5, -0.0, 3],"), "{text}");
        assert!(text.contains("\"c\": [\"x, y\", \"]\"]"), "{text}");
        assert_eq!(serde_json::from_str::<serde_json::Value>(&text).unwrap(), v);
        let f: f32 = 0.3;
        assert_eq!(json(&[f]).unwrap(), "[0.3]\n");
    }

    #[test]
    fn relative_paths_follow_the_output_folder() {
        let mut doc = Document::Job(JobFile {
            format: crate::job::JOB_FORMAT.into(),
            name: "j".into(),
            scenes: vec!["../plane.json".into(), "/abs/s.scene".into()],
            levels: vec![1],
            point_sets: vec![crate::condition::PointSetKind::Random],
            time_filters: vec![crate::condition::TimeFilter::Box],
            reference: crate::job::ReferenceSpec::HighestLevel,
            seed: 1,
            overrides: Default::default(),
            frames_per_unit: None,
        });
        rebase_paths(
            &mut doc,
            Path::new("/r/scenes/jobs"),
            Path::new("/r/scenes/thesis"),
        )
        .unwrap();
        let Document::Job(j) = &doc else { panic!() };
        assert_eq!(j.scenes, ["../plane.json", "/abs/s.scene"]);
        rebase_paths(&mut doc, Path::new("/r/scenes/thesis"), Path::new("/r")).unwrap();
        let Document::Job(j) = &doc else { panic!() };
        assert_eq!(j.scenes[0], "scenes/plane.json");
    }
}
