//! Empty on purpose: it exists so that Cargo resolves the `[build-dependencies]` in Cargo.toml,
//! which pin the host-side features of syn to those the test build needs (see the comment there).

fn main() {}
