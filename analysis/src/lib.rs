//! From session logs to psychometric fits, JNDs with bootstrap intervals, t-tests and figures
//! (thesis Chapter V).
