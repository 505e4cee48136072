//! The published data sets the observer model is fitted and validated on, each with the
//! model run on its stimuli and the fit (`blurlab predict validate modelfest|meese2007`):
//!
//! - `modelfest/`: ModelFest's 43 detection stimuli and thresholds (`mod`: loading, the
//!   model's response); `fit`: k, the pooling and the CSF's shape, errors, leave-one-out;
//! - `meese/`: Meese et al. 2007's cross-orientation masking (`mod`: loading, the model's
//!   thresholds); `fit`: each decision stage's errors in dB, the cross-orientation weight.
//!
//! They import the model and each other (Meese's absolute thresholds are at ModelFest's
//! presentation), nothing else of the analysis (`analysis/tests/observer_layers.rs`).

pub mod meese;
pub mod modelfest;
