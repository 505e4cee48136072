//! The root package of blurlab: the `demo` pipeline, which runs the three crates end to end on
//! built-in defaults, and the study summary it writes. The command line is the `blurlab`
//! binary's own (`src/main.rs`, `src/cli/`).

pub mod demo;
pub mod summary;
