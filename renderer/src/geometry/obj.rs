//! Wavefront OBJ models as one [`TriangleMesh`] (through tobj), with errors that name the file.

use super::TriangleMesh;
use glam::Vec3A;
use std::io::BufReader;
use std::path::{Path, PathBuf};

#[derive(Debug, thiserror::Error)]
pub enum ObjError {
    #[error("cannot read OBJ model {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("OBJ model {path} is not valid: {source}")]
    Parse {
        path: PathBuf,
        source: tobj::LoadError,
    },
    #[error("OBJ model {path}: {what}")]
    Content { path: PathBuf, what: String },
}

impl TriangleMesh {
    /// Every object and group of an OBJ file merged into one mesh; polygons are triangulated,
    /// materials and texture coordinates ignored. Vertex normals are kept when every part of the
    /// file has them. Errors (unreadable file, parse error, non-finite coordinates, no triangle)
    /// name the file.
    pub fn from_obj(path: &Path) -> Result<TriangleMesh, ObjError> {
        let content = |what: String| ObjError::Content {
            path: path.to_owned(),
            what,
        };
        if path.is_dir() {
            return Err(content("is a folder; expected an OBJ file".into()));
        }
        let file = std::fs::File::open(path).map_err(|source| ObjError::Io {
            path: path.to_owned(),
            source,
        })?;
        let options = tobj::LoadOptions {
            triangulate: true,
            single_index: true,
            ignore_points: true,
            ignore_lines: true,
        };
        // Materials are the scene's business: never open the model's .mtl files.
        let (models, _) = tobj::load_obj_buf(&mut BufReader::new(file), &options, |_| {
            Err(tobj::LoadError::OpenFileFailed)
        })
        .map_err(|source| ObjError::Parse {
            path: path.to_owned(),
            source,
        })?;
        let with_normals = models
            .iter()
            .all(|m| !m.mesh.normals.is_empty() && m.mesh.normals.len() == m.mesh.positions.len());
        let (mut positions, mut normals, mut indices) = (Vec::new(), Vec::new(), Vec::new());
        for m in &models {
            let base = positions.len() as u32;
            positions.extend(m.mesh.positions.chunks_exact(3).map(Vec3A::from_slice));
            if with_normals {
                normals.extend(m.mesh.normals.chunks_exact(3).map(Vec3A::from_slice));
            }
            indices.extend(
                m.mesh
                    .indices
                    .chunks_exact(3)
                    .map(|t| [base + t[0], base + t[1], base + t[2]]),
            );
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(content(format!(
                "vertex {} has a non-finite coordinate",
                i + 1
            )));
        }
        if indices.is_empty() {
            return Err(content(
                "has no faces (expected at least one triangle)".into(),
            ));
        }
        let n = positions.len() as u32;
        if indices.iter().flatten().any(|&i| i >= n) {
            return Err(content(
                "a face refers to a vertex that does not exist".into(),
            ));
        }
        let normals = (with_normals && normals.iter().all(|n| n.is_finite())).then_some(normals);
        Ok(TriangleMesh::new(positions, normals, indices))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn write(text: &str) -> tempfile::NamedTempFile {
        let mut f = tempfile::Builder::new().suffix(".obj").tempfile().unwrap();
        f.write_all(text.as_bytes()).unwrap();
        f
    }

    #[test]
    fn loads_quads_as_triangles_with_normals() {
        let f = write(
            "mtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nusemtl x\nf 1//1 2//1 3//1 4//1\n",
        );
        let m = TriangleMesh::from_obj(f.path()).unwrap();
        assert_eq!(m.triangle_count(), 2);
        assert!(
            m.normals
                .as_ref()
                .is_some_and(|n| n.iter().all(|&n| n == Vec3A::Z))
        );
    }

    #[test]
    fn errors_name_the_file() {
        let missing = Path::new("/nonexistent/plane.obj");
        let e = TriangleMesh::from_obj(missing).unwrap_err().to_string();
        assert!(e.contains("/nonexistent/plane.obj"), "{e}");
        let bad = write("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
        let e = TriangleMesh::from_obj(bad.path()).unwrap_err().to_string();
        assert!(e.contains(&bad.path().display().to_string()), "{e}");
        let empty = write("v 0 0 0\n");
        let e = TriangleMesh::from_obj(empty.path())
            .unwrap_err()
            .to_string();
        assert!(e.contains("no faces"), "{e}");
        let dir = tempfile::tempdir().unwrap();
        let e = TriangleMesh::from_obj(dir.path()).unwrap_err().to_string();
        assert!(e.contains("is a folder; expected an OBJ file"), "{e}");
    }
}
