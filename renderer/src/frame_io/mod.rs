//! Frames as files: PNG display frames, EXR linear frames and their names. The lowest layer
//! of the renderer's output: `render/` (one scene's sequence) and `job/` (stimulus sets) both
//! write through it, and the environment map reads EXR through it; it imports neither.

pub mod exr;
pub mod names;
pub mod png;
