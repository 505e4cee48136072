//! A text file as numbered lines of words. Words are separated by whitespace; `#` starts a
//! comment that runs to the end of the line; blank and comment-only lines are skipped. A word
//! holding whitespace, `#` or `"` (a file name with a space, a description) is written in double
//! quotes, with `\"`, `\\`, `\n`, `\r` and `\t` as escapes; a bare word is taken literally
//! (so `data\CedarCity.hdr` keeps its backslash).

use anyhow::Result;
use std::borrow::Cow;
use std::path::Path;

/// One line that holds at least one word.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Line {
    /// 1-based line number in the file.
    pub number: usize,
    pub words: Vec<String>,
}

/// The lines of `text` that hold words, numbered as in the file.
pub fn lines(text: &str, path: &Path) -> Result<Vec<Line>> {
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let words = split(raw).map_err(|e| super::at_line(path, i + 1, e))?;
        if !words.is_empty() {
            out.push(Line {
                number: i + 1,
                words,
            });
        }
    }
    Ok(out)
}

/// The words of one line.
fn split(line: &str) -> std::result::Result<Vec<String>, String> {
    let mut words = Vec::new();
    let mut chars = line.chars().peekable();
    loop {
        while chars.next_if(|c| c.is_whitespace()).is_some() {}
        match chars.peek() {
            None | Some('#') => return Ok(words),
            Some('"') => {
                chars.next();
                words.push(quoted(&mut chars)?);
                if chars
                    .peek()
                    .is_some_and(|c| !c.is_whitespace() && *c != '#')
                {
                    return Err("a quoted word must be followed by a space".into());
                }
            }
            Some(_) => {
                let mut w = String::new();
                while let Some(c) = chars.next_if(|c| !c.is_whitespace() && *c != '#') {
                    if c == '"' {
                        return Err(format!(
                            "`{w}\"`: a `\"` may only start a quoted word (\"like this\")"
                        ));
                    }
                    w.push(c);
                }
                words.push(w);
            }
        }
    }
}

/// The rest of a quoted word after its opening quote.
fn quoted(chars: &mut impl Iterator<Item = char>) -> std::result::Result<String, String> {
    let mut w = String::new();
    while let Some(c) = chars.next() {
        match c {
            '"' => return Ok(w),
            '\\' => match chars.next() {
                Some('"') => w.push('"'),
                Some('\\') => w.push('\\'),
                Some('n') => w.push('\n'),
                Some('r') => w.push('\r'),
                Some('t') => w.push('\t'),
                other => {
                    return Err(format!(
                        "unknown escape `\\{}` in a quoted word; expected \\\" \\\\ \\n \\r or \\t",
                        other.map(String::from).unwrap_or_default()
                    ));
                }
            },
            c => w.push(c),
        }
    }
    Err(format!("quoted word \"{w} is not closed by `\"`"))
}

/// `word` as the writers write it: bare when it reads back as itself, else quoted.
pub fn quote(word: &str) -> Cow<'_, str> {
    let bare = !word.is_empty()
        && word
            .chars()
            .all(|c| !c.is_whitespace() && !c.is_control() && c != '#' && c != '"');
    if bare {
        return Cow::Borrowed(word);
    }
    let mut q = String::with_capacity(word.len() + 2);
    q.push('"');
    for c in word.chars() {
        match c {
            '"' => q.push_str("\\\""),
            '\\' => q.push_str("\\\\"),
            '\n' => q.push_str("\\n"),
            '\r' => q.push_str("\\r"),
            '\t' => q.push_str("\\t"),
            c => q.push(c),
        }
    }
    q.push('"');
    Cow::Owned(q)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn words(line: &str) -> Vec<String> {
        split(line).unwrap()
    }

    #[test]
    fn words_comments_and_quotes() {
        assert_eq!(words("  location 0 0 420  "), ["location", "0", "0", "420"]);
        assert_eq!(words("fov 50 # degrees"), ["fov", "50"]);
        assert_eq!(words("fov 50#degrees"), ["fov", "50"]);
        assert_eq!(words("# only a comment"), Vec::<String>::new());
        assert_eq!(
            words(r#"modelfilename "my models/B-727.obj" x"#),
            ["modelfilename", "my models/B-727.obj", "x"]
        );
        assert_eq!(words(r#"d "a \"b\" \\ c\n""#), ["d", "a \"b\" \\ c\n"]);
        assert_eq!(words(r#"e "" "#), ["e", ""]);
        assert_eq!(
            words(r"envmap data\CedarCity.hdr"),
            ["envmap", r"data\CedarCity.hdr"]
        );
        assert_eq!(words(r##"d "a # b""##), ["d", "a # b"]);
    }

    #[test]
    fn bad_quotes_are_explained() {
        assert!(split(r#"d "open"#).unwrap_err().contains("not closed"));
        assert!(
            split(r#"d "a"b"#)
                .unwrap_err()
                .contains("followed by a space")
        );
        assert!(split(r#"d ab"c"#).unwrap_err().contains("may only start"));
        assert!(split(r#"d "\q""#).unwrap_err().contains("unknown escape"));
        let e = lines("ok 1\n\nd \"x", Path::new("f.scene")).unwrap_err();
        assert_eq!(
            e.to_string().split(':').take(2).collect::<Vec<_>>(),
            ["f.scene", "3"]
        );
    }

    #[test]
    fn lines_keep_file_numbers() {
        let l = lines("# c\r\na 1\r\n\r\n  b\n", Path::new("x")).unwrap();
        assert_eq!(l.len(), 2);
        assert_eq!((l[0].number, l[1].number), (2, 4));
        assert_eq!(l[1].words, ["b"]);
    }

    proptest! {
        #[test]
        fn any_word_reads_back_as_itself(w in any::<String>(), v in "[a-z]{1,4}") {
            let line = format!("{v} {} {v}", quote(&w));
            prop_assert_eq!(split(&line).unwrap(), vec![v.clone(), w, v]);
        }
    }
}
