//! Shared by the root package's integration tests.

pub mod paired_t;
pub mod thesis_study;
