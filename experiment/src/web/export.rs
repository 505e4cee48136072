//! Encoded videos for a static server (issue 48 item 5): every video the design shows, copied
//! under its study-wide opaque name (`video_ids::export_name`) into one folder that a stock
//! nginx, Caddy or object store serves. Subjects then fetch videos there (`--video-base-url`)
//! while their answers still go to `blurlab serve`. The folder holds the videos only: nothing in
//! it names a stimulus.

use super::Config;
use super::packs::PACK_EXT;
use super::tokens::Tokens;
use anyhow::{Context, Result};
use std::path::Path;

/// What an export wrote.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Exported {
    pub videos: usize,
    pub bytes: u64,
    /// Files already there with the right size, left as they were.
    pub kept: usize,
}

/// Export the videos of `config`'s design to `dir`, named with the study's key (made and saved
/// in `OUT/web/tokens.json` if new, so that the server started later names them the same).
pub fn export(
    config: &Config,
    dir: &Path,
    progress: &mut dyn FnMut(usize, usize, &str),
) -> Result<Exported> {
    let (study, _) = super::load_study(config, progress)?;
    let mut tokens = Tokens::load_or_new(&config.out)?;
    let key = tokens.video_key()?;
    tokens.save(&config.out)?;
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let mut done = Exported {
        videos: 0,
        bytes: 0,
        kept: 0,
    };
    for (_, served) in study.videos() {
        let name = super::video_ids::export_name(&key, &served.pack.sha256);
        let target = dir.join(format!("{name}.{PACK_EXT}"));
        done.videos += 1;
        done.bytes += served.pack.bytes;
        // The name is keyed by the content: a file of that name and size is this video.
        if std::fs::metadata(&target).is_ok_and(|m| m.len() == served.pack.bytes) {
            done.kept += 1;
            continue;
        }
        let bytes = std::fs::read(&served.path)
            .with_context(|| format!("cannot read {}", served.path.display()))?;
        renderer::atomic::write_atomic(&target, &bytes)?;
    }
    Ok(done)
}
