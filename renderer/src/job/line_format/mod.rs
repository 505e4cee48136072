//! The thesis's job description (Figure 12), a `.job` file: seven lines — the job's name; the
//! number of sampling levels; the levels; the number of point sets; the point sets; the number
//! of time filters; the time filters — then optional `key value ...` extension lines for what
//! the thesis kept elsewhere (scenes, reference, seed, overrides). It reads into the same
//! [`JobFile`](super::JobFile) as the JSON format ([`read`]) and is written back from it
//! ([`write`]) without loss. Syntax and defaults: `docs/thesis-formats.md`.

mod read;
mod write;

pub use read::read;
pub use write::write;

/// The file extension of the format.
pub const EXTENSION: &str = "job";

/// Seed of a `.job` without a `seed` line (the thesis's year, as `scenes/thesis/job.json`).
pub const DEFAULT_SEED: u64 = 2013;

/// What each of the seven lines holds, for messages.
pub const LINES: [&str; 7] = [
    "name",
    "number of levels",
    "levels",
    "number of point sets",
    "point sets",
    "number of time filters",
    "time filters",
];

/// Whether `path` names a text job (by its extension).
pub fn is_line_job(path: &std::path::Path) -> bool {
    path.extension().is_some_and(|e| e == EXTENSION)
}

/// The scene a `.job` without `scene` lines renders: the file named after the job file, with
/// the extension `.scene`, beside it (`plane.job` renders `plane.scene`).
pub fn default_scene(job_path: &std::path::Path) -> String {
    let stem = job_path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    format!("{stem}.{}", crate::scene::block_format::EXTENSION)
}
