//! The renderer: motion-blurred distribution ray tracing of stimulus videos
//! (thesis Chapter III), the sampling machinery the study compares, and stimulus jobs.
//!
//! Two layers, chosen by cargo features (docs/ARCHITECTURE.md): the light core (`shared/`: stimulus
//! ids, hashing, SHA-256 digests, atomic writes, the JSON and UTF-8 readers, limits, the stimulus manifest,
//! the progress trait, the typed conditions) is always built, because the experiment and the analysis need it;
//! feature `plot` adds the figures' font, and feature `tracer` (default) everything that
//! renders. The experiment and the analysis turn `tracer` off, so they do not compile the ray
//! tracer. The library knows no command line: `blurlab render` (the root package's
//! `src/cli/render/`) parses the flags and calls it.

// Fused multiply-adds round once where a product and a sum round twice, and glam fuses its
// cross products and quaternion products whenever FMA is on at compile time (`-C
// target-cpu=native` turns it on): frames would then differ in their last bits from the
// default build's, and shards of one job rendered by the two builds would not be the same
// bytes (README.md, "On a cluster"). An AVX2 build without FMA keeps every bit, and gains
// little: the packet code takes AVX2 lanes at run time anyway (BENCHMARKS.md, "Lanes chosen at
// run time").
#[cfg(all(target_arch = "x86_64", target_feature = "fma"))]
compile_error!(
    "blurlab must be built without fused multiply-adds, or its pictures change: add \
     `-C target-feature=-fma` to RUSTFLAGS (BENCHMARKS.md, \"Lanes chosen at run time\")"
);

// The light core: the vocabulary every crate shares, in one folder (`shared/`) that imports
// nothing of the tracer. Re-exported here, so its modules keep their short paths
// (`renderer::manifest`, `renderer::limits`, ...).
pub mod shared;
pub use shared::{
    assets, atomic, condition, digest, hash, ids, json, limits, manifest, named, paths, progress,
    quote, utf8,
};

#[cfg(feature = "plot")]
pub mod plot_font;

// The tracer and what is built on it.
#[cfg(feature = "tracer")]
pub mod accel;
#[cfg(feature = "tracer")]
pub mod bvh;
#[cfg(feature = "tracer")]
pub mod camera;
#[cfg(feature = "tracer")]
pub mod contact_sheet;
#[cfg(feature = "tracer")]
pub mod convergence;
#[cfg(feature = "tracer")]
pub mod convert;
#[cfg(feature = "tracer")]
pub mod display_convergence;
#[cfg(feature = "tracer")]
pub mod environment;
#[cfg(feature = "tracer")]
pub mod export;
#[cfg(feature = "tracer")]
pub mod film;
#[cfg(feature = "tracer")]
pub mod frame_io;
#[cfg(feature = "tracer")]
pub mod geometry;
#[cfg(feature = "tracer")]
pub mod job;
#[cfg(feature = "tracer")]
pub mod light;
#[cfg(feature = "tracer")]
pub mod material;
#[cfg(feature = "tracer")]
pub mod math;
#[cfg(feature = "tracer")]
pub mod metrics;
#[cfg(feature = "tracer")]
pub mod motion;
#[cfg(feature = "tracer")]
pub mod pointset_figure;
#[cfg(feature = "tracer")]
pub mod procedural;
#[cfg(feature = "tracer")]
pub mod render;
#[cfg(feature = "tracer")]
pub mod sampling;
#[cfg(feature = "tracer")]
pub mod scene;
#[cfg(feature = "tracer")]
pub mod shading;
#[cfg(feature = "tracer")]
pub mod simd;
#[cfg(feature = "tracer")]
pub mod text;
#[cfg(feature = "tracer")]
pub mod workload;
