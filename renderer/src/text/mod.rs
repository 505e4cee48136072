//! What the readers and writers of the thesis's own text formats share: Figure 12's seven-line
//! job (`crate::job::line_format`) and Figure 13's block scene (`crate::scene::block_format`).
//!
//! - [`words`]: a file as numbered lines of whitespace-separated words, `#` comments, quoted
//!   words for values with spaces;
//! - [`entries`]: `key value ...` lines taken by key, with typed values, repeated and unknown
//!   keys refused, every error naming the file, the line and the key;
//! - [`source_map`]: which line set which field of the model, so that a check made later on the
//!   model (a material that is not defined) still names the line;
//! - [`names`]: the thesis's spellings of point set and time filter names;
//! - [`sampling`]: the sampling options both formats share;
//! - [`out`]: writing lines back, deterministically.
//!
//! The syntax is documented in `docs/thesis-formats.md`.

pub mod entries;
pub mod names;
pub mod out;
pub mod sampling;
pub mod source_map;
pub mod words;

pub use entries::{Entries, Entry};
pub use out::Out;
pub use source_map::SourceMap;
pub use words::{Line, lines, quote};

use std::path::Path;

/// An error at a line of a text file: `plane.scene:14: what` (a long quoted word shortened by
/// [`crate::quote::clip_quoted`]).
pub fn at_line(path: &Path, line: usize, what: impl std::fmt::Display) -> anyhow::Error {
    let what = crate::quote::clip_quoted(&what.to_string());
    anyhow::anyhow!("{}:{line}: {what}", path.display())
}
