//! The vocabulary every crate shares: stimulus ids and typed conditions, hashing and SHA-256
//! digests, the stimulus manifest, limits and number parsers, the JSON and UTF-8 readers,
//! atomic writes, paths, quoting, the progress trait and the enum-naming macro. Always built
//! (the experiment and the analysis need it without the tracer); nothing here imports the
//! tracer (`renderer/tests/layers.rs` checks it).

pub mod assets;
pub mod atomic;
pub mod condition;
pub mod digest;
pub mod hash;
pub mod ids;
pub mod json;
pub mod limits;
pub mod manifest;
pub mod named;
pub mod paths;
pub mod progress;
pub mod quote;
pub mod utf8;
