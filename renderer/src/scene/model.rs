//! Wavefront OBJ models through tobj: every group and object of the file merged into one
//! triangle mesh (polygons triangulated), with per-vertex normals when every part has them.
//! Materials and texture coordinates of the file are ignored: the scene file assigns materials.

use crate::geometry::TriangleMesh;
use anyhow::{Context, Result, bail};
use glam::Vec3A;
use std::path::Path;

/// Load `path` as one mesh. Errors name the file; a file without triangles is an error.
pub fn load_obj(path: &Path) -> Result<TriangleMesh> {
    // tobj's options grow with its cargo features; the update keeps this compiling under any.
    #[allow(clippy::needless_update)]
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    // The material library (if any) is not needed; its absence is not an error.
    let (models, _materials) = tobj::load_obj(path, &options)
        .with_context(|| format!("cannot read OBJ model {}", path.display()))?;
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut indices = Vec::new();
    let mut every_part_has_normals = true;
    for m in &models {
        let mesh = &m.mesh;
        let base = positions.len();
        let count = mesh.positions.len() / 3;
        positions.extend(
            mesh.positions
                .chunks_exact(3)
                .map(|p| Vec3A::new(p[0], p[1], p[2])),
        );
        if mesh.normals.len() == mesh.positions.len() {
            normals.extend(
                mesh.normals
                    .chunks_exact(3)
                    .map(|n| Vec3A::new(n[0], n[1], n[2])),
            );
        } else {
            every_part_has_normals = false;
        }
        for tri in mesh.indices.chunks_exact(3) {
            if tri.iter().any(|&i| i as usize >= count) {
                bail!(
                    "{}: part `{}` has a face with a vertex index out of range",
                    path.display(),
                    m.name
                );
            }
            indices.push([0, 1, 2].map(|k| (base + tri[k] as usize) as u32));
        }
    }
    if indices.is_empty() {
        bail!("{}: the model holds no triangles", path.display());
    }
    if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
        bail!(
            "{}: vertex {} has a coordinate that is not a finite number",
            path.display(),
            i + 1
        );
    }
    let normals = every_part_has_normals.then_some(normals);
    Ok(TriangleMesh::new(positions, normals, indices))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn quads_are_triangulated_and_parts_merged() {
        let dir = tempfile::tempdir().unwrap();
        let p = write(
            dir.path(),
            "m.obj",
            "o a\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n\
             o b\nv 0 0 1\nv 1 0 1\nv 1 1 1\nf 5 6 7\n",
        );
        let m = load_obj(&p).unwrap();
        assert_eq!(m.triangle_count(), 3);
        assert_eq!(m.positions.len(), 7);
        assert!(m.normals.is_none());
        assert!(m.indices.iter().flatten().all(|&i| i < 7));
        assert!(
            m.indices[2].contains(&4),
            "second part's vertices are offset"
        );
    }

    #[test]
    fn normals_are_kept_when_present() {
        let dir = tempfile::tempdir().unwrap();
        let p = write(
            dir.path(),
            "n.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n",
        );
        let m = load_obj(&p).unwrap();
        assert_eq!(m.normals.as_ref().unwrap()[1], Vec3A::Z);
    }

    #[test]
    fn bad_files_are_refused_with_their_name() {
        let dir = tempfile::tempdir().unwrap();
        let empty = write(dir.path(), "empty.obj", "v 0 0 0\n");
        let e = load_obj(&empty).unwrap_err().to_string();
        assert!(e.contains("empty.obj") && e.contains("no triangles"), "{e}");
        let missing = dir.path().join("missing.obj");
        let e = format!("{:#}", load_obj(&missing).unwrap_err());
        assert!(e.contains("missing.obj"), "{e}");
    }
}
