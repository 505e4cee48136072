//! `key value ...` lines (a block of Figure 13, the extension lines of a job) taken by key.
//!
//! A reader asks for each key it knows, with the type it expects and the model field it fills;
//! [`Entries::finish`] then refuses any key nobody asked for, listing the known ones. Every
//! error names the file, the line and the key and says what was expected; every key taken is
//! recorded in the [`SourceMap`] under its field.

use super::{Line, SourceMap, at_line};
use anyhow::Result;
use std::path::Path;
use std::str::FromStr;

/// One `key value ...` line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Entry {
    pub key: String,
    pub line: usize,
    pub values: Vec<String>,
}

impl Entry {
    /// The entry of a line (its first word is the key).
    pub fn of(line: &Line) -> Self {
        Self {
            key: line.words[0].clone(),
            line: line.number,
            values: line.words[1..].to_vec(),
        }
    }
}

/// The entries of one block (or of a job's extension lines), taken key by key.
pub struct Entries<'a> {
    path: &'a Path,
    /// What holds the entries, for messages: "block `object` (line 12)".
    context: String,
    /// Where a missing key would have gone.
    context_line: usize,
    /// Model field path of the block (`objects[0]`); fields below it are `prefix.field`.
    prefix: String,
    entries: Vec<Entry>,
    used: Vec<bool>,
    known: Vec<&'static str>,
    map: &'a mut SourceMap,
}

impl<'a> Entries<'a> {
    /// Entries of one block; a key given twice is an error unless it is `repeatable`.
    pub fn new(
        path: &'a Path,
        context: String,
        context_line: usize,
        prefix: &str,
        entries: Vec<Entry>,
        repeatable: &[&str],
        map: &'a mut SourceMap,
    ) -> Result<Self> {
        for (i, e) in entries.iter().enumerate() {
            if repeatable.contains(&e.key.as_str()) {
                continue;
            }
            if let Some(first) = entries[..i].iter().find(|f| f.key == e.key) {
                return Err(at_line(
                    path,
                    e.line,
                    format!(
                        "key `{}` is given twice in {context} (first on line {}); expected it \
                         once",
                        e.key, first.line
                    ),
                ));
            }
        }
        Ok(Self {
            path,
            context,
            context_line,
            prefix: prefix.to_string(),
            used: vec![false; entries.len()],
            entries,
            known: Vec::new(),
            map,
        })
    }

    /// The model path of `field` inside this block.
    pub fn field(&self, field: &str) -> String {
        match (self.prefix.is_empty(), field.is_empty()) {
            (true, _) => field.to_string(),
            (false, true) => self.prefix.clone(),
            (false, false) => format!("{}.{field}", self.prefix),
        }
    }

    /// The next unused entry with `key`, marked used and recorded under `field`.
    pub fn take(&mut self, key: &'static str, field: &str) -> Option<Entry> {
        if !self.known.contains(&key) {
            self.known.push(key);
        }
        let i = (0..self.entries.len()).find(|&i| !self.used[i] && self.entries[i].key == key)?;
        self.used[i] = true;
        let e = self.entries[i].clone();
        let path = self.field(field);
        self.map.add(path, Some(e.line), format!("key `{key}`"));
        Some(e)
    }

    /// Every entry with `key`, in file order; entry k is recorded under `field(k)`.
    pub fn take_all(&mut self, key: &'static str, field: impl Fn(usize) -> String) -> Vec<Entry> {
        let mut out = Vec::new();
        while let Some(e) = self.take(key, &field(out.len())) {
            out.push(e);
        }
        if out.is_empty() {
            self.take(key, "");
        }
        out
    }

    /// An error at an entry's line, naming its key.
    pub fn error(&self, e: &Entry, what: impl std::fmt::Display) -> anyhow::Error {
        at_line(self.path, e.line, format!("key `{}` {what}", e.key))
    }

    /// `key`'s values, which must number exactly `n` (`what` describes them for messages).
    fn exactly(
        &mut self,
        key: &'static str,
        field: &str,
        n: usize,
        what: &str,
    ) -> Result<Option<Entry>> {
        let Some(e) = self.take(key, field) else {
            return Ok(None);
        };
        if e.values.len() != n {
            return Err(self.error(
                &e,
                format!(
                    "expects {what}, found {} value(s){}",
                    e.values.len(),
                    shown(&e.values)
                ),
            ));
        }
        Ok(Some(e))
    }

    fn parse<T: FromStr>(&self, e: &Entry, word: &str, what: &str) -> Result<T> {
        word.parse()
            .map_err(|_| self.error(e, format!("expects {what}; `{word}` is not one")))
    }

    /// A finite number from one of an entry's words.
    pub fn finite<T: FromStr + Into<f64> + Copy>(&self, e: &Entry, word: &str) -> Result<T> {
        let v: T = self.parse(e, word, "a number")?;
        if !v.into().is_finite() {
            return Err(self.error(e, format!("expects finite numbers; `{word}` is not")));
        }
        // `1e-50` parses to 0 as a 32-bit float: refused like `1e39`, not taken silently.
        if v.into() == 0.0 && word.parse::<f64>().is_ok_and(|x| x != 0.0) {
            return Err(self.error(
                e,
                format!(
                    "holds `{word}`, which 32-bit floats round to 0; expected 0 or a magnitude \
                     of at least {:e}",
                    f32::MIN_POSITIVE
                ),
            ));
        }
        Ok(v)
    }

    pub fn f32(&mut self, key: &'static str, field: &str) -> Result<Option<f32>> {
        match self.exactly(key, field, 1, "one number")? {
            Some(e) => Ok(Some(self.finite(&e, &e.values[0])?)),
            None => Ok(None),
        }
    }

    pub fn f64(&mut self, key: &'static str, field: &str) -> Result<Option<f64>> {
        match self.exactly(key, field, 1, "one number")? {
            Some(e) => Ok(Some(self.finite(&e, &e.values[0])?)),
            None => Ok(None),
        }
    }

    /// `N` numbers (a vector, a colour).
    pub fn numbers<const N: usize>(
        &mut self,
        key: &'static str,
        field: &str,
        what: &str,
    ) -> Result<Option<[f32; N]>> {
        let Some(e) = self.exactly(key, field, N, what)? else {
            return Ok(None);
        };
        let mut out = [0.0; N];
        for (o, w) in out.iter_mut().zip(&e.values) {
            *o = self.finite(&e, w)?;
        }
        Ok(Some(out))
    }

    /// Three numbers: `x y z`.
    pub fn vec3(&mut self, key: &'static str, field: &str) -> Result<Option<[f32; 3]>> {
        self.numbers::<3>(key, field, "3 numbers (x y z)")
    }

    /// Three numbers: `r g b`.
    pub fn colour(&mut self, key: &'static str, field: &str) -> Result<Option<[f32; 3]>> {
        self.numbers::<3>(key, field, "3 numbers (r g b)")
    }

    /// A whole number.
    pub fn integer<T: FromStr>(&mut self, key: &'static str, field: &str) -> Result<Option<T>> {
        match self.exactly(key, field, 1, "one whole number")? {
            Some(e) => Ok(Some(self.parse(&e, &e.values[0], "a whole number >= 0")?)),
            None => Ok(None),
        }
    }

    /// One word.
    pub fn word(&mut self, key: &'static str, field: &str) -> Result<Option<String>> {
        Ok(self
            .exactly(key, field, 1, "one word")?
            .map(|e| e.values[0].clone()))
    }

    /// Any number of words (none included).
    pub fn words(&mut self, key: &'static str, field: &str) -> Option<Vec<String>> {
        self.take(key, field).map(|e| e.values)
    }

    /// One of `options`.
    pub fn choice(
        &mut self,
        key: &'static str,
        field: &str,
        options: &[&str],
    ) -> Result<Option<String>> {
        let what = format!("one of {}", options.join(", "));
        let Some(e) = self.exactly(key, field, 1, &what)? else {
            return Ok(None);
        };
        if !options.contains(&e.values[0].as_str()) {
            return Err(self.error(&e, format!("expects {what}; found `{}`", e.values[0])));
        }
        Ok(Some(e.values[0].clone()))
    }

    /// `true` or `false`.
    pub fn boolean(&mut self, key: &'static str, field: &str) -> Result<Option<bool>> {
        Ok(self
            .choice(key, field, &["true", "false"])?
            .map(|w| w == "true"))
    }

    /// A required value: `v`, or an error saying the block lacks `key` (`expected` shows its
    /// values, e.g. "<name>").
    pub fn require<T>(&self, v: Option<T>, key: &str, expected: &str) -> Result<T> {
        v.ok_or_else(|| {
            at_line(
                self.path,
                self.context_line,
                format!(
                    "{} has no key `{key}`; expected a line `{key} {expected}`{}",
                    self.context,
                    self.unread_hint(key)
                ),
            )
        })
    }

    /// The keys not read so far that look like `key` misspelt, for a missing-key message.
    fn unread_hint(&self, key: &str) -> String {
        let unread: Vec<String> = (self.entries.iter().zip(&self.used))
            .filter(|(e, used)| !**used && edit_distance(&e.key, key) <= 2 + key.len() / 6)
            .map(|(e, _)| format!("`{}` (line {})", e.key, e.line))
            .collect();
        match unread.len() {
            0 => String::new(),
            _ => format!(" (a misspelling? this block has {})", unread.join(", ")),
        }
    }

    /// An error about the block as a whole.
    pub fn block_error(&self, what: impl std::fmt::Display) -> anyhow::Error {
        at_line(
            self.path,
            self.context_line,
            format!("{} {what}", self.context),
        )
    }

    /// Record that the block itself sets `field` (a derived name, a default).
    pub fn note(&mut self, field: &str, what: impl Into<String>) {
        let path = self.field(field);
        self.map.add(path, Some(self.context_line), what);
    }

    /// Refuse any key no one asked for.
    pub fn finish(self) -> Result<()> {
        match self.used.iter().position(|u| !u) {
            None => Ok(()),
            Some(i) => {
                let e = &self.entries[i];
                let mut known = self.known.clone();
                known.sort_unstable();
                Err(at_line(
                    self.path,
                    e.line,
                    format!(
                        "unknown key `{}` in {}; expected one of: {}",
                        e.key,
                        self.context,
                        known.join(", ")
                    ),
                ))
            }
        }
    }
}

/// ` (`a b c`)` for a non-empty list of values.
/// Levenshtein distance between two keys (insertions, deletions, substitutions).
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let above = row[j + 1];
            row[j + 1] = (diagonal + usize::from(ca != cb))
                .min(above + 1)
                .min(row[j] + 1);
            diagonal = above;
        }
    }
    row[b.len()]
}

fn shown(values: &[String]) -> String {
    if values.is_empty() {
        String::new()
    } else {
        format!(": `{}`", values.join(" "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entries(text: &str) -> Vec<Entry> {
        super::super::lines(text, Path::new("t"))
            .unwrap()
            .iter()
            .map(Entry::of)
            .collect()
    }

    fn err(r: Result<impl std::fmt::Debug>) -> String {
        format!("{:#}", r.unwrap_err())
    }

    #[test]
    fn typed_values_and_their_errors() {
        let mut map = SourceMap::default();
        let list = entries("fov 50\nlocation 0 O 420\nup 0 1\nflag yes\nsize -3\nx inf\n");
        let path = Path::new("c.scene");
        let mut e = Entries::new(
            path,
            "block `camera`".into(),
            1,
            "camera",
            list,
            &[],
            &mut map,
        )
        .unwrap();
        assert_eq!(e.f32("fov", "fov").unwrap(), Some(50.0));
        assert_eq!(
            err(e.vec3("location", "location")),
            "c.scene:2: key `location` expects a number; `O` is not one"
        );
        assert_eq!(
            err(e.vec3("up", "up")),
            "c.scene:3: key `up` expects 3 numbers (x y z), found 2 value(s): `0 1`"
        );
        assert_eq!(
            err(e.boolean("flag", "flag")),
            "c.scene:4: key `flag` expects one of true, false; found `yes`"
        );
        assert_eq!(
            err(e.integer::<u32>("size", "size")),
            "c.scene:5: key `size` expects a whole number >= 0; `-3` is not one"
        );
        assert_eq!(
            err(e.f32("x", "x")),
            "c.scene:6: key `x` expects finite numbers; `inf` is not"
        );
        assert_eq!(e.f32("absent", "absent").unwrap(), None);
        assert_eq!(
            err(e.require(None::<f32>, "lookat", "<x> <y> <z>")),
            "c.scene:1: block `camera` has no key `lookat`; expected a line `lookat <x> <y> <z>`"
        );
        e.finish().unwrap();
        assert_eq!(map.locate("camera.fov").unwrap().line, Some(1));
    }

    #[test]
    fn repeated_and_unknown_keys_are_refused() {
        let mut map = SourceMap::default();
        let path = Path::new("j.job");
        let twice = entries("seed 1\nwidth 3\nseed 2\n");
        let e = Entries::new(path, "the job".into(), 1, "", twice, &[], &mut map);
        assert_eq!(
            err(e.map(|_| ())),
            "j.job:3: key `seed` is given twice in the job (first on line 1); expected it once"
        );
        let list = entries("scene a\nscene b\ncolour 1 1 1\n");
        let mut e =
            Entries::new(path, "the job".into(), 1, "", list, &["scene"], &mut map).unwrap();
        let scenes = e.take_all("scene", |k| format!("scenes[{k}]"));
        assert_eq!(scenes.len(), 2);
        e.f32("seed", "seed").unwrap();
        assert_eq!(
            err(e.finish()),
            "j.job:3: unknown key `colour` in the job; expected one of: scene, seed"
        );
        assert_eq!(map.locate("scenes[1]").unwrap().line, Some(2));
    }
}
