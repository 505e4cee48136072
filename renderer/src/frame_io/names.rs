//! The file names of a rendered frame in its folder (`frame_NNNN.png`, `.exr`), shared by
//! `render scene` and the job runner.

use std::path::{Path, PathBuf};

/// `dir/frame_NNNN.png`.
pub fn png_path(dir: &Path, frame: u32) -> PathBuf {
    dir.join(png_name(frame))
}

/// `frame_NNNN.png`: the display frame's file name.
pub fn png_name(frame: u32) -> String {
    format!("frame_{frame:04}.png")
}

/// `dir/frame_NNNN.exr`.
pub fn exr_path(dir: &Path, frame: u32) -> PathBuf {
    dir.join(exr_name(frame))
}

/// `frame_NNNN.exr`: the linear frame's file name.
pub fn exr_name(frame: u32) -> String {
    format!("frame_{frame:04}.exr")
}
