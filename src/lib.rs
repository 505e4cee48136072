//! The root package of blurlab: the umbrella command line (`src/main.rs`) and the `demo`
//! pipeline, which runs the three crates end to end on built-in defaults.

pub mod demo;
#[cfg(feature = "web")]
pub mod serve;
pub mod summary;
