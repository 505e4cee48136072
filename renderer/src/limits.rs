//! The suite's limits on sizes, counts and magnitudes, in one place.
//!
//! Every input that can carry one of these quantities (command line, scene, job, design,
//! observer, session log) checks it against the same constant here where it enters, so that
//! no file or flag can make a command allocate without bound or hand the tracer a number that
//! floats cannot represent. `docs/limits.md` lists them and what each kind of bad input gets.
//! Add a limit here rather than beside the reader that first needs it.

/// Largest image side in pixels (a typo guard: 16384² pixels is 3 GB of film).
pub const MAX_IMAGE_SIDE: u32 = 16384;

/// Most samples per pixel of one render (the point sets' largest set).
pub const MAX_SPP: u32 = crate::sampling::pointset::MAX_POINTS as u32;
