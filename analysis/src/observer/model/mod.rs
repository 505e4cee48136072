//! The observer model, one idea per file, in the order a frame passes through it:
//!
//! | file | idea |
//! |---|---|
//! | `display` | sRGB frames -> luminance (cd/m^2); pixels per degree |
//! | `csf` | stelaCSF, the spatio-temporal contrast sensitivity function (cited there) |
//! | `shape` | the CSF's shape and oblique effect as ModelFest's observers have them |
//! | `temporal` | sustained and transient channels as filters over looped frames |
//! | `bands` | 2D FFT, octave bands, CSF weighting |
//! | `video/` | the model on one test/reference pair, frame by frame (its files: `video/mod.rs`) |
//! | `decision_stage` | `DecisionStage`: how test and reference are compared; `SideBySide` |
//! | `masking` | the difference stage's threshold elevation by the reference's contrast |
//! | `local` | sum-preserving Gaussian local means (the side-by-side stage's neighbourhood) |
//! | `orientation` | the side-by-side stage's orientation channels, cross-orientation weight |
//! | `transducer` | the side-by-side stage's discrimination of suprathreshold contrast |
//! | `pooling` | Minkowski pooling over channels, space and time, the aperture (fitted) |
//! | `proportion_correct` | d' = k Q; proportion correct of the two-pair task and 2IFC |
//!
//! It imports nothing of the analysis outside this folder (`analysis/tests/observer_layers.rs`).

pub mod bands;
pub mod csf;
pub mod decision_stage;
pub mod display;
pub mod local;
pub mod masking;
pub mod orientation;
pub mod pooling;
pub mod proportion_correct;
pub mod shape;
pub mod temporal;
pub mod transducer;
pub mod video;
