//! Assets made by the project's own code: the stand-ins for the thesis's airliner model and
//! environment map (Figure 13's `models/B-727-200.obj` and `data/CedarCity.hdr`, at those paths
//! beside the thesis scenes). `render assets` writes them into `scenes/`; a test checks that
//! the committed files equal what this code produces.

pub mod airliner;
pub mod sky;

use anyhow::Result;
use std::path::{Path, PathBuf};

/// One generated file: its path relative to the scenes folder and its bytes.
pub struct Asset {
    pub path: &'static str,
    pub bytes: Vec<u8>,
}

/// Every generated asset.
pub fn assets() -> Result<Vec<Asset>> {
    Ok(vec![
        Asset {
            path: "thesis/models/B-727-200.obj",
            bytes: airliner::b727_obj().into_bytes(),
        },
        Asset {
            path: "thesis/data/CedarCity.hdr",
            bytes: sky::hdr_bytes(&sky::SkyParams::cedar_city())?,
        },
    ])
}

/// Write every asset under `scenes_dir` (atomically); returns the written paths.
pub fn write_assets(scenes_dir: &Path) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    for a in assets()? {
        let path = scenes_dir.join(a.path);
        crate::atomic::write_atomic(&path, &a.bytes)?;
        written.push(path);
    }
    Ok(written)
}
