//! Subject sessions for the two-pair method of constant stimuli (thesis Chapter IV): the design
//! file, per-subject trial lists, the append-only session log, resume, preflight checks of the
//! stimuli, simulated observers and (feature `gui`) the egui/eframe presentation app.
//!
//! The library part has no GUI dependency: the analysis and the simulator use it headless. It
//! knows no command line: `blurlab run` and `blurlab simulate` (the root package's `src/cli/`)
//! map their flags onto it.

#[cfg(feature = "gui")]
pub mod app;
pub mod design;
mod design_load;
pub mod display;
#[cfg(any(test, feature = "test-support"))]
pub mod fixture;
pub mod log;
pub mod observer;
pub mod paths;
pub mod playback;
pub mod predicted;
pub mod preflight;
pub mod procedure;
pub mod psychometric;
pub mod screening;
pub mod session;
pub mod simulate;
pub mod trials;
#[cfg(feature = "web")]
pub mod web;

#[cfg(feature = "gui")]
pub use app::LaunchOptions;
pub use design::Design;
pub use observer::Observer;
pub use session::{Phase, Session};
