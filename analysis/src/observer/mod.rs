//! The image-based observer: how visible a test video's difference from its reference is,
//! computed from the display frames as a subject sees them, and the proportion correct that
//! follows. Two layers, each importing only downward (`analysis/tests/observer_layers.rs`):
//!
//! - [`model`]: the model itself, from display frames to d' and proportion correct; it imports
//!   nothing of the analysis outside itself;
//! - [`datasets`]: the published data sets the model is fitted and validated on (ModelFest,
//!   Meese et al. 2007) and their fits; they import the model and each other.
//!
//! Runs over stimulus sets and the bridge to sessions are above both, in [`crate::predict`].
//! `docs/predict.md` describes the model, its choices and what it cannot know.

pub mod datasets;
pub mod model;
