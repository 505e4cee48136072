//! The thesis's scene description (Figure 13), a `.scene` file: blocks `material`, `object`,
//! `objectinstance`, `group`, `light`, `camera` and `settings`, each a keyword on its own line,
//! then `key value ...` lines, then `end`. There may be many of the first five and exactly one
//! camera and one settings block. It reads into the same [`SceneFile`](super::SceneFile) as the
//! JSON format ([`read`]) and is written back from it ([`write`]) without loss. The keys,
//! their JSON fields and defaults: `docs/thesis-formats.md`.

mod read;
mod write;

pub use read::read;
pub use write::write;

/// The block keywords, in the order the writer writes them.
pub const BLOCKS: [&str; 7] = [
    "material",
    "object",
    "objectinstance",
    "group",
    "light",
    "camera",
    "settings",
];

/// The file extension of the format.
pub const EXTENSION: &str = "scene";

/// Whether `path` names a text scene (by its extension).
pub fn is_block_scene(path: &std::path::Path) -> bool {
    path.extension().is_some_and(|e| e == EXTENSION)
}
