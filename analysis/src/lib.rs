//! From session logs to psychometric fits, JNDs with bootstrap intervals, t-tests and figures
//! (thesis Chapter V).

pub mod data;
pub mod jnd;
pub mod optimizer;
pub mod psychometric;
pub mod sigmoid;
pub mod student_t;
