//! `predict`'s check of its frames against the manifest, made before any prediction by the
//! code `blurlab run`'s preflight uses ([`experiment::preflight::stimulus_problems`]): every
//! stimulus's `frames` agrees with its frame list, every frame exists with the manifest's size,
//! and the frames' content hash is the manifest's. A test frame swapped for another file of the
//! same size, a zeroed `content_hash`, or a `frames` that disagrees with the list used to give
//! a prediction without a word (issue 29).

use anyhow::{Result, bail};
use experiment::preflight::{PreflightOptions, stimulus_problems};
use rayon::prelude::*;
use renderer::manifest::{Manifest, manifest_file};
use renderer::progress::NoProgress;
use std::path::Path;

/// Every problem of the stimuli `ids` of `manifest` (read from `manifest_path`, the file or
/// its folder), listed; an error when there is any.
pub fn check(manifest: &Manifest, manifest_path: &Path, ids: &[&str]) -> Result<()> {
    let file = manifest_file(manifest_path);
    let folder = file.parent().unwrap_or(Path::new(""));
    let opts = PreflightOptions { check_hashes: true };
    let problems: Vec<String> = ids
        .par_iter()
        .flat_map_iter(|&id| match manifest.get(id) {
            None => vec![format!("{id}: not in the manifest")],
            Some(s) => {
                let (found, _, _) = stimulus_problems(s, folder, opts, &NoProgress);
                found.into_iter().map(|m| format!("{id}: {m}")).collect()
            }
        })
        .collect();
    if !problems.is_empty() {
        bail!(
            "{}: {} problem(s) with the stimuli, checked as `blurlab run`'s preflight checks \
             them; nothing was predicted:\n  - {}",
            file.display(),
            problems.len(),
            problems.join("\n  - ")
        );
    }
    Ok(())
}
