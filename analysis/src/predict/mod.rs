//! `blurlab predict`: the observer model ([`crate::observer`]) run over stimulus sets, and its
//! bridge to sessions. One idea per file:
//!
//! | file | idea |
//! |---|---|
//! | `stimuli` | a whole stimulus set: rows of `predicted.csv`, JNDs per condition |
//! | `preflight` | the set's frames checked against its manifest first (`run`'s checks) |
//! | `stage_choice` | which decision stage a design's layout calls for, and why |
//! | `frames` | a video's JNDs from predictions of single frames spread over it |
//! | `explain` | where the aperture lands in a pair's frames and what is there (a diagnostic) |
//! | `output` | `predicted.csv`, `predicted_jnd.csv`, `predict.md`, a figure per scene |
//! | `viewer` | a browser session's display: the subject's own pixels per degree |
//! | `calibrate` | the sensitivity constant fitted to real sessions, leave-one-condition-out |
//! | `compare` | the predicted JNDs beside a study's measured ones |
//! | `run` | what `blurlab predict` and its subcommands are asked to do, run end to end |
//!
//! `docs/predict.md` describes the model, its choices and what it cannot know.

pub mod calibrate;
pub mod compare;
pub mod explain;
pub mod frames;
pub mod output;
pub mod preflight;
pub mod run;
pub mod stage_choice;
pub mod stimuli;
pub mod viewer;
