//! Quoting a file's text in a message: at most [`QUOTE_CHARS`] characters of it, so that a
//! 10 MB line (a file that is not what it claims, a runaway write) gives a message a terminal
//! can show. Every reader's error passes through [`clip_quoted`] where it is built
//! (`crate::text::at_line`, `crate::json::from_str`, the session-log reader).

/// Most characters of a file's text that a message quotes: a 10 MB line used to be echoed
/// whole into the message.
pub const QUOTE_CHARS: usize = 80;

/// `s` when it is short, else its first [`QUOTE_CHARS`] characters, `...` and its length.
pub fn short(s: &str) -> std::borrow::Cow<'_, str> {
    match s.char_indices().nth(QUOTE_CHARS) {
        None => s.into(),
        Some((end, _)) => format!("{}... ({} characters)", &s[..end], s.chars().count()).into(),
    }
}

/// `message` with every `backtick-quoted` (then "double-quoted") span shortened by [`short`]:
/// the suite's readers quote the words they refuse in backticks, serde in either.
pub fn clip_quoted(message: &str) -> String {
    clip_between(&clip_between(message, '`'), '"')
}

fn clip_between(message: &str, mark: char) -> String {
    let mut out = String::with_capacity(message.len().min(4096));
    for (i, part) in message.split(mark).enumerate() {
        if i > 0 {
            out.push(mark);
        }
        // Odd parts lie between marks (an unpaired last one is quoted text too).
        out.push_str(&if i % 2 == 1 { short(part) } else { part.into() });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_quoted_text_is_shortened() {
        let long = "x".repeat(1_000_000);
        let e = clip_quoted(&format!("a.scene:1: `{long}` outside a block"));
        assert!(e.len() < 200, "{} bytes", e.len());
        assert!(
            e.contains("... (1000000 characters)` outside a block"),
            "{e}"
        );
        assert_eq!(clip_quoted("key `fov` is `x`"), "key `fov` is `x`");
        let e = clip_quoted(&format!("unknown variant \"{long}\", expected `a`"));
        assert!(
            e.len() < 200 && e.ends_with("characters)\", expected `a`"),
            "{e}"
        );
        let wide = "\u{e9}".repeat(100);
        assert!(short(&wide).starts_with(&"\u{e9}".repeat(80)));
    }
}
