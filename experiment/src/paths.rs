//! Where the experiment's files go unless told otherwise: session logs under
//! `results/<design name>/sessions`.

use crate::design::Design;
use std::path::{Path, PathBuf};

/// `results/<design name>/sessions` unless given.
pub fn sessions_dir(out: Option<&Path>, design: &Design) -> PathBuf {
    out.map(Path::to_path_buf).unwrap_or_else(|| {
        PathBuf::from("results")
            .join(design.name())
            .join("sessions")
    })
}
