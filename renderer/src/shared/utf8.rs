//! Reading text files with errors that locate a bad byte: `std::fs::read_to_string` says only
//! "stream did not contain valid UTF-8", which leaves a user searching a long file.

use anyhow::{Context, Result, bail};
use std::path::Path;

/// The contents of `path`, a `what` (e.g. "scene file"), as UTF-8 text. A byte that is not
/// UTF-8 is an error naming the file, line and column.
pub fn read(path: &Path, what: &str) -> Result<String> {
    let bytes =
        std::fs::read(path).with_context(|| format!("cannot read {what} {}", path.display()))?;
    decode(path, bytes, what)
}

/// `bytes` (the contents of `path`) as UTF-8 text, or an error locating the first bad byte. A
/// byte-order mark (some Windows editors write one) is skipped, in every text format alike.
pub fn decode(path: &Path, bytes: Vec<u8>, what: &str) -> Result<String> {
    String::from_utf8(without_bom(bytes)).or_else(|e| {
        let at = e.utf8_error().valid_up_to();
        let (line, column) = locate(e.as_bytes(), at);
        bail!(
            "{}:{line}: byte 0x{:02x} at column {column} is not UTF-8; expected {} {what} in \
             UTF-8 text (was the file saved in another encoding?)",
            path.display(),
            e.as_bytes()[at],
            article(what)
        )
    })
}

/// The UTF-8 byte-order mark EF BB BF.
pub const BOM: &[u8] = b"\xef\xbb\xbf";

/// `bytes` without a leading byte-order mark.
pub fn without_bom(mut bytes: Vec<u8>) -> Vec<u8> {
    if bytes.starts_with(BOM) {
        bytes.drain(..BOM.len());
    }
    bytes
}

/// "a" or "an", to go before `noun`.
pub fn article(noun: &str) -> &'static str {
    if noun.starts_with(['a', 'e', 'i', 'o', 'u']) {
        "an"
    } else {
        "a"
    }
}

/// Line and column (both from 1, the column in bytes) of byte `at` of `bytes`.
pub fn locate(bytes: &[u8], at: usize) -> (usize, usize) {
    let before = &bytes[..at];
    let line_start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1);
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    (line, at - line_start + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bad_byte_is_located() {
        let err = decode(
            Path::new("a.scene"),
            b"ok\nab\xffc\n".to_vec(),
            "scene file",
        );
        let err = err.unwrap_err().to_string();
        assert!(err.starts_with("a.scene:2: byte 0xff at column 3"), "{err}");
        assert_eq!(
            decode(Path::new("a"), b"fine".to_vec(), "x").unwrap(),
            "fine"
        );
    }

    #[test]
    fn a_byte_order_mark_is_skipped() {
        let text = decode(Path::new("a.scene"), b"\xef\xbb\xbfcamera\n".to_vec(), "x");
        assert_eq!(text.unwrap(), "camera\n");
        assert_eq!(without_bom(b"\xef\xbb".to_vec()), b"\xef\xbb");
    }

    #[test]
    fn locate_counts_from_one() {
        assert_eq!(locate(b"abc", 0), (1, 1));
        assert_eq!(locate(b"a\nbc", 3), (2, 2));
    }
}
