//! Which line of a text file set which field of the model. The readers record every key they
//! take under the model's field path (`objects[0].material`); the checks that run later on the
//! model (`scene::build`, `Job::from_file`) name fields by the same paths, and ask the map for
//! the line, so a text file's errors point at its lines and keys, not at JSON fields the user
//! never wrote.

/// Where a field came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    /// 1-based line, or `None` for a value the reader supplied (a default with no line).
    pub line: Option<usize>,
    /// What stands there, e.g. "key `materialname`" or "block `object`".
    pub what: String,
}

/// Field paths to locations.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SourceMap {
    entries: Vec<(String, Location)>,
}

impl SourceMap {
    /// Record that `field` (and the fields below it, unless recorded themselves) came from
    /// `what` on `line`.
    pub fn add(&mut self, field: impl Into<String>, line: Option<usize>, what: impl Into<String>) {
        self.entries.push((
            field.into(),
            Location {
                line,
                what: what.into(),
            },
        ));
    }

    /// The location of `field`: the entry with the longest path that is `field` itself or one
    /// of its ancestors (`objects[0]` is an ancestor of `objects[0].scale` and of
    /// `objects[0][1]`, not of `objects[01]`).
    pub fn locate(&self, field: &str) -> Option<&Location> {
        self.entries
            .iter()
            .filter(|(p, _)| {
                field
                    .strip_prefix(p.as_str())
                    .is_some_and(|rest| rest.is_empty() || rest.starts_with(['.', '[']))
            })
            .max_by_key(|(p, _)| p.len())
            .map(|(_, l)| l)
    }

    /// An error about `field` of the file at `path`: located at its line and key when the map
    /// knows them (`plane.scene:14: key `materialname` (field `objects[0].material`) names
    /// ...`), else in the JSON formats' style (`plane.json: field `objects[0].material` ...`).
    pub fn error(
        map: Option<&SourceMap>,
        path: &std::path::Path,
        field: &str,
        what: impl std::fmt::Display,
    ) -> anyhow::Error {
        match map.and_then(|m| m.locate(field)) {
            Some(Location {
                line: Some(line),
                what: at,
            }) => anyhow::anyhow!("{}:{line}: {at} (field `{field}`) {what}", path.display()),
            Some(Location {
                line: None,
                what: at,
            }) => {
                anyhow::anyhow!("{}: {at} (field `{field}`) {what}", path.display())
            }
            None => anyhow::anyhow!("{}: field `{field}` {what}", path.display()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn the_longest_ancestor_wins_at_component_boundaries() {
        let mut m = SourceMap::default();
        m.add("objects[0]", Some(10), "block `object`");
        m.add("objects[0].material", Some(12), "key `materialname`");
        m.add("objects[1]", Some(20), "block `object`");
        assert_eq!(m.locate("objects[0].material").unwrap().line, Some(12));
        assert_eq!(m.locate("objects[0].scale").unwrap().line, Some(10));
        assert_eq!(
            m.locate("objects[1].half_extent[0]").unwrap().line,
            Some(20)
        );
        assert_eq!(m.locate("objects[10]"), None);
        assert_eq!(m.locate("camera"), None);
        let e = SourceMap::error(
            Some(&m),
            Path::new("p.scene"),
            "objects[0].material",
            "is x",
        );
        assert_eq!(
            e.to_string(),
            "p.scene:12: key `materialname` (field `objects[0].material`) is x"
        );
        let e = SourceMap::error(None, Path::new("p.json"), "camera.fov", "is x");
        assert_eq!(e.to_string(), "p.json: field `camera.fov` is x");
    }
}
