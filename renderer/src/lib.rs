//! The renderer: motion-blurred distribution ray tracing of stimulus videos
//! (thesis Chapter III), the sampling machinery the study compares, and stimulus jobs.

pub mod accel;
pub mod atomic;
pub mod cli;
pub mod convergence;
pub mod export;
pub mod geometry;
pub mod hash;
pub mod job;
pub mod manifest;
pub mod metrics;
pub mod motion;
pub mod procedural;
pub mod sampling;
