//! From session logs to psychometric fits, JNDs with bootstrap intervals, t-tests and figures
//! (thesis Chapter V).

pub mod adaptive;
pub mod analyze;
pub mod bootstrap;
pub mod comparisons;
mod continued_fraction;
pub mod data;
pub mod exclusions;
pub mod figures;
pub mod jnd;
pub mod multilevel;
pub mod observer;
pub mod optimizer;
pub mod output;
pub mod plan;
pub mod predict;
pub mod psychometric;
pub mod report;
pub mod sigmoid;
#[cfg(any(test, feature = "test-support"))]
pub mod simulate;
pub mod student_t;
pub mod summary;
pub mod threshold;
pub mod ttest;
pub mod validate;
