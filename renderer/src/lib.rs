//! The renderer: motion-blurred distribution ray tracing of stimulus videos
//! (thesis Chapter III), the sampling machinery the study compares, and stimulus jobs.

pub mod accel;
pub mod atomic;
pub mod bvh;
pub mod camera;
pub mod cli;
pub mod condition;
pub mod contact_sheet;
pub mod convergence;
pub mod convert;
pub mod display_convergence;
pub mod environment;
pub mod export;
pub mod film;
pub mod frame_io;
pub mod geometry;
pub mod hash;
pub mod job;
pub mod json;
pub mod light;
pub mod limits;
pub mod manifest;
pub mod material;
pub mod metrics;
pub mod motion;
pub mod paths;
pub mod plot_font;
pub mod procedural;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod shading;
pub mod text;
pub mod utf8;
pub mod workload;
