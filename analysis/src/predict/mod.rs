//! Predicting before subjects: how visible each stimulus's difference from its reference is,
//! computed from the display frames as a subject sees them, and the proportion correct of the
//! two-pair task that follows. One idea per file:
//!
//! | file | idea |
//! |---|---|
//! | `display` | sRGB frames -> luminance (cd/m^2); pixels per degree |
//! | `csf` | stelaCSF, the spatio-temporal contrast sensitivity function (cited there) |
//! | `temporal` | sustained and transient channels as filters over looped frames |
//! | `bands` | 2D FFT, octave bands, CSF weighting |
//! | `local` | sum-preserving Gaussian local means on a coarse grid (the side-by-side stage's neighbourhood) |
//! | `masking` | threshold elevation by the reference's contrast |
//! | `orientation` | orientation channels for the side-by-side stage's masking, the cross-orientation weight |
//! | `transducer` | the side-by-side stage's discrimination of suprathreshold contrast (Weber-like) |
//! | `pooling` | Minkowski pooling over channels, space and time, the aperture (fitted) |
//! | `shape` | the CSF's shape and oblique effect as ModelFest's observers have them (fitted) |
//! | `video` | the model on one test/reference pair, frame by frame |
//! | `explain` | where the aperture lands in a pair's frames and what is there (a diagnostic) |
//! | `stage` | which decision stage a design's layout calls for, and why |
//! | `decision` | proportion correct from d': the two-pair task and 2IFC (with simulations) |
//! | `stimuli` | a whole stimulus set: rows of `predicted.csv`, JNDs per condition |
//! | `frames` | a video's JNDs from predictions of single frames spread over it |
//! | `output` | `predicted.csv`, `predicted_jnd.csv`, `predict.md`, a figure per scene |
//! | `calibrate` | the sensitivity constant fitted to real sessions, leave-one-condition-out |
//! | `modelfest` | the ModelFest data set loaded and run through the pipeline |
//! | `masking_validation` | the decision stages against Meese's masking data, errors in dB |
//! | `meese` | Meese et al. 2007 cross-orientation masking: the data and the model's thresholds |
//! | `validate` | k, the pooling and the CSF's shape fitted to ModelFest, errors, leave-one-out |
//! | `options` | what `blurlab predict` and its subcommands are asked to do, run end to end |
//!
//! `docs/predict.md` describes the model, its choices and what it cannot know.

pub mod bands;
pub mod calibrate;
pub mod compare;
pub mod csf;
pub mod decision;
pub mod display;
pub mod explain;
pub mod frames;
pub mod local;
pub mod masking;
pub mod masking_validation;
pub mod meese;
pub mod modelfest;
pub mod options;
pub mod orientation;
pub mod output;
pub mod pooling;
pub mod preflight;
pub mod shape;
pub mod stage;
pub mod stimuli;
pub mod temporal;
pub mod transducer;
pub mod validate;
pub mod video;
pub mod viewer;
