//! The user's own copies of files a scene names (`--asset CedarCity.hdr=PATH`): a scene's
//! environment map whose file name matches an asset's name is read from the asset's path
//! instead of the scene's folder. The thesis's sky (`CedarCity.hdr`, the OptiX SDK's sample
//! map) cannot ship with the suite; a user who has it renders the thesis scenes with it
//! without copying it into the project. Each asset is checked when it is named (a Radiance
//! RGBE lat-long map for a `.hdr` name) and recorded, with its SHA-256, in the manifest of what
//! it rendered, so stimuli made with and without it are never confused.

use crate::digest::sha256_hex;
use anyhow::{Context, Result, bail};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// One asset as recorded in a manifest.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct AssetRecord {
    /// The file name the scenes use, e.g. `CedarCity.hdr`.
    pub name: String,
    /// SHA-256 of the file's bytes, lowercase hex.
    pub sha256: String,
}

/// One substitution: scenes' files named `name` are read from `path`.
#[derive(Clone, Debug, PartialEq)]
pub struct Asset {
    pub name: String,
    pub path: PathBuf,
    /// SHA-256 of the file, hashed when the asset was checked.
    pub sha256: String,
}

/// The assets of a run (none by default: every file from its scene's folder).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Assets(Vec<Asset>);

impl Assets {
    /// Assets from `NAME=PATH` values of the flag `flag`, each checked.
    pub fn from_flags(values: &[String], flag: &str) -> Result<Self> {
        let mut assets = Self::default();
        for v in values {
            let Some((name, path)) = v.split_once('=') else {
                bail!("{flag} {v:?}: expected NAME=PATH, e.g. CedarCity.hdr=/data/CedarCity.hdr");
            };
            assets.add(name, Path::new(path))?;
        }
        Ok(assets)
    }

    /// Add `name` read from `path`, after checking it.
    pub fn add(&mut self, name: &str, path: &Path) -> Result<()> {
        if name.is_empty() || name.contains(['/', '\\']) {
            bail!("asset name {name:?}: expected a bare file name such as CedarCity.hdr");
        }
        if self.0.iter().any(|a| a.name == name) {
            bail!("asset {name:?} is named twice; expected one path per name");
        }
        let bytes = std::fs::read(path)
            .with_context(|| format!("asset {name}: cannot read {}", path.display()))?;
        if name.to_ascii_lowercase().ends_with(".hdr") {
            check_radiance_latlong(&bytes)
                .with_context(|| format!("asset {name}: {}", path.display()))?;
        }
        self.0.push(Asset {
            name: name.to_string(),
            path: path.to_path_buf(),
            sha256: sha256_hex(&bytes),
        });
        Ok(())
    }

    /// Where to read the file a scene names as `file` (relative to `dir`, the scene's folder):
    /// the asset of that file name, or the scene's own file.
    pub fn resolve(&self, dir: &Path, file: &Path) -> PathBuf {
        self.find(file)
            .map(|a| a.path.clone())
            .unwrap_or_else(|| dir.join(file))
    }

    /// The asset that replaces `file`, if any.
    pub fn find(&self, file: &Path) -> Option<&Asset> {
        let name = file.file_name()?.to_str()?;
        self.0.iter().find(|a| a.name == name)
    }

    /// The assets, in the order they were named.
    pub fn list(&self) -> &[Asset] {
        &self.0
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The manifest's records of these assets, by name.
    pub fn records(&self) -> Vec<AssetRecord> {
        let mut r: Vec<AssetRecord> = self
            .0
            .iter()
            .map(|a| AssetRecord {
                name: a.name.clone(),
                sha256: a.sha256.clone(),
            })
            .collect();
        r.sort_by(|a, b| a.name.cmp(&b.name));
        r
    }
}

/// A Radiance RGBE file (`#?RADIANCE` or `#?RGBE`, `FORMAT=32-bit_rle_rgbe` if a format is
/// given) whose resolution line `-Y h +X w` describes a lat-long map, `w = 2 h`: what the
/// renderer's environment reads as a sphere of directions. A light probe (angular map) or a
/// cube cross has another shape and would be drawn wrongly without an error.
fn check_radiance_latlong(bytes: &[u8]) -> Result<()> {
    let head = &bytes[..bytes.len().min(4096)];
    let text = String::from_utf8_lossy(head);
    let mut lines = text.split('\n');
    let magic = lines.next().unwrap_or_default();
    if !(magic.starts_with("#?RADIANCE") || magic.starts_with("#?RGBE")) {
        bail!("not a Radiance RGBE map: expected a first line `#?RADIANCE`");
    }
    for line in lines.by_ref() {
        if line.trim().is_empty() {
            break;
        }
        if let Some(f) = line.strip_prefix("FORMAT=")
            && f.trim() != "32-bit_rle_rgbe"
        {
            bail!(
                "FORMAT={}: expected 32-bit_rle_rgbe (RGB, not XYZ)",
                f.trim()
            );
        }
    }
    let size = lines.next().unwrap_or_default().trim();
    let (h, w) = parse_resolution(size)
        .with_context(|| format!("resolution line {size:?}: expected `-Y height +X width`"))?;
    if w != 2 * h {
        bail!("{w} x {h} texels: expected a lat-long map twice as wide as high");
    }
    Ok(())
}

fn parse_resolution(line: &str) -> Option<(u32, u32)> {
    let t: Vec<&str> = line.split_whitespace().collect();
    match t.as_slice() {
        ["-Y", h, "+X", w] => Some((h.parse().ok()?, w.parse().ok()?)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hdr(w: u32, h: u32, format: &str) -> Vec<u8> {
        let mut b = format!("#?RADIANCE\nFORMAT={format}\n\n-Y {h} +X {w}\n").into_bytes();
        b.extend(std::iter::repeat_n([128u8, 128, 128, 129], (w * h) as usize).flatten());
        b
    }

    #[test]
    fn a_lat_long_rgbe_map_replaces_the_scene_s_file_of_its_name() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("mine.hdr");
        std::fs::write(&path, hdr(8, 4, "32-bit_rle_rgbe")).unwrap();
        let flag = format!("CedarCity.hdr={}", path.display());
        let a = Assets::from_flags(&[flag], "--asset").unwrap();
        let scene_dir = Path::new("scenes/thesis");
        assert_eq!(a.resolve(scene_dir, Path::new("data/CedarCity.hdr")), path);
        assert_eq!(
            a.resolve(scene_dir, Path::new("data/other.hdr")),
            scene_dir.join("data/other.hdr")
        );
        let r = a.records();
        assert_eq!(r[0].name, "CedarCity.hdr");
        assert_eq!(r[0].sha256, sha256_hex(&std::fs::read(&path).unwrap()));
    }

    #[test]
    fn other_files_are_refused_with_what_was_expected() {
        let dir = tempfile::tempdir().unwrap();
        let err = |bytes: &[u8]| {
            let p = dir.path().join("x.hdr");
            std::fs::write(&p, bytes).unwrap();
            let mut a = Assets::default();
            format!("{:#}", a.add("CedarCity.hdr", &p).unwrap_err())
        };
        assert!(err(b"\x89PNG\r\n").contains("#?RADIANCE"));
        assert!(err(&hdr(8, 8, "32-bit_rle_rgbe")).contains("twice as wide"));
        assert!(err(&hdr(8, 4, "32-bit_rle_xyze")).contains("32-bit_rle_rgbe"));
        assert!(err(b"#?RADIANCE\n\n+Y 4 -X 8\n").contains("-Y height +X width"));
        let missing = Assets::from_flags(&["CedarCity.hdr=/no/such/file".into()], "--asset");
        assert!(format!("{:#}", missing.unwrap_err()).contains("/no/such/file"));
        let bare = Assets::from_flags(&["CedarCity.hdr".into()], "--asset");
        assert!(format!("{:#}", bare.unwrap_err()).contains("NAME=PATH"));
    }
}
