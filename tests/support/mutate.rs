//! Mutations of valid files for the parsers' property tests (issue 16): every reader of the
//! suite, given arbitrary bytes or a valid file with a few bytes, numbers or lines changed,
//! must end in `Ok` or an error that names the file and says where (a line, a field or a key)
//! — never a panic, an abort or a hang. Included by path from each crate's
//! `tests/parsers_never_panic.rs`, so the three crates mutate the same way.

use proptest::prelude::*;

/// Numbers that break readers: signs, zero, f32 and u32 overflow, exponents, non-numbers.
const NUMBERS: &[&str] = &[
    "-1",
    "0",
    "1e39",
    "1e308",
    "-1e308",
    "1e400",
    "4294967296",
    "99999999999999999999",
    "NaN",
    "inf",
    "1.5",
    "-0",
    "65537",
    "100000",
    "\"7\"",
    "null",
    "[]",
    "{}",
];

/// Cases per property: `default`, or `BLURLAB_FUZZ_CASES` for a longer local search
/// (`BLURLAB_FUZZ_CASES=20000 cargo test --test parsers_never_panic`).
pub fn cases(default: u32) -> u32 {
    std::env::var("BLURLAB_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// One edit of a file: (operation, position, length or index, byte).
pub type Edit = (u8, u16, u16, u8);

/// Up to `n` edits.
pub fn edits(n: usize) -> impl Strategy<Value = Vec<Edit>> {
    prop::collection::vec(any::<Edit>(), 1..=n)
}

/// `text` with `edits` applied, in order. Positions wrap around the current length.
pub fn apply(text: &[u8], edits: &[Edit]) -> Vec<u8> {
    let mut b = text.to_vec();
    for &(op, pos, len, byte) in edits {
        let at = if b.is_empty() {
            0
        } else {
            pos as usize % (b.len() + 1)
        };
        let end = (at + len as usize % 16).min(b.len());
        match op % 7 {
            0 => {
                if at < b.len() {
                    b[at] = byte;
                }
            }
            1 => {
                b.drain(at..end);
            }
            2 => b.insert(at, byte),
            3 => b.truncate(at),
            4 => replace_number(&mut b, at, NUMBERS[len as usize % NUMBERS.len()]),
            5 => duplicate_line(&mut b, at),
            _ => {
                // A structural byte where it hurts: quotes, brackets, separators.
                let s = b"\"{}[],:\n# -";
                b.insert(at, s[byte as usize % s.len()]);
            }
        }
    }
    b
}

/// Replace the number at or after `at` with `with`.
fn replace_number(b: &mut Vec<u8>, at: usize, with: &str) {
    let is_num = |c: u8| c.is_ascii_digit() || c == b'.' || c == b'-' || c == b'e';
    let Some(start) = (at..b.len()).find(|&i| b[i].is_ascii_digit()) else {
        return;
    };
    let start = (0..start)
        .rev()
        .take_while(|&i| is_num(b[i]))
        .last()
        .unwrap_or(start);
    let end = (start..b.len()).find(|&i| !is_num(b[i])).unwrap_or(b.len());
    b.splice(start..end, with.bytes());
}

/// Repeat the line holding `at`.
fn duplicate_line(b: &mut Vec<u8>, at: usize) {
    let start = b[..at]
        .iter()
        .rposition(|&c| c == b'\n')
        .map_or(0, |i| i + 1);
    let end = b[at..]
        .iter()
        .position(|&c| c == b'\n')
        .map_or(b.len(), |i| at + i + 1);
    let line = b[start..end].to_vec();
    b.splice(start..start, line);
}

/// An error message from reading `file` that a user can act on: it names the file (by its
/// file name) and a place in it or a field (`file:12:`, `line 3`, `field `x``, `key `y``), or
/// says what the file as a whole lacks or is not (for binary images: "cannot read ... as").
pub fn assert_located(message: &str, file: &str) {
    assert!(
        message.contains(file),
        "the message does not name {file}: {message}"
    );
    // A whole-file finding is located by the file: what it lacks ("no `camera` block",
    // "missing field"), that it is empty, or which texels or vertices are wrong.
    let located = [
        "line",
        "field",
        "key",
        "column",
        "cannot read",
        "byte",
        "no `",
        "missing",
        "empty",
        "texel",
        "vertex",
    ]
    .iter()
    .any(|w| message.contains(w))
        || message.split(file).skip(1).any(|rest| {
            rest.starts_with(':') && rest[1..].starts_with(|c: char| c.is_ascii_digit())
        });
    assert!(
        located,
        "the message names no line, field or key: {message}"
    );
}
