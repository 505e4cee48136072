//! Wavefront OBJ models as one [`TriangleMesh`] (through tobj), with errors that name the file.

use super::TriangleMesh;
use glam::Vec3A;
use std::path::{Path, PathBuf};

#[derive(Debug, thiserror::Error)]
pub enum ObjError {
    #[error("cannot read OBJ model {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    // `error`, not `source`: tobj's words are the message, not a cause to print again.
    #[error("OBJ model {path} is not valid: {error}")]
    Parse {
        path: PathBuf,
        error: tobj::LoadError,
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
        let bytes = std::fs::read(path).map_err(|source| ObjError::Io {
            path: path.to_owned(),
            source,
        })?;
        let text = std::str::from_utf8(&bytes).map_err(|e| {
            let at = e.valid_up_to();
            let (line, column) = crate::utf8::locate(&bytes, at);
            content(format!(
                "line {line}: byte 0x{:02x} at column {column} is not UTF-8; expected an OBJ \
                 model in UTF-8 text",
                bytes[at]
            ))
        })?;
        let options = tobj::LoadOptions {
            triangulate: true,
            single_index: true,
            ignore_points: true,
            ignore_lines: true,
        };
        // Materials are the scene's business: never open the model's .mtl files.
        let (models, _) = tobj::load_obj_buf(&mut text.as_bytes(), &options, |_| {
            Err(tobj::LoadError::OpenFileFailed)
        })
        .map_err(|source| match bad_line(text, &source) {
            // tobj names no line: find the first line of the kind it could not read.
            Some(line) => content(format!("line {line}: {source}")),
            None => ObjError::Parse {
                path: path.to_owned(),
                error: source,
            },
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
                "has no faces (no `f` lines); expected at least one triangle".into(),
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

/// The first line (from 1) of `text` of the kind tobj's `err` is about that does not read:
/// a vertex, normal or texture coordinate without three (two) numbers, or a face with an
/// index that is not a number or points outside the file's lists.
fn bad_line(text: &str, err: &tobj::LoadError) -> Option<usize> {
    use tobj::LoadError::*;
    let lines = || {
        text.lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.split_whitespace()))
    };
    let numbers = |key: &str, n: usize| {
        lines().find_map(|(no, mut w)| {
            (w.next() == Some(key)).then_some(())?;
            let ok = w.take(n).filter(|x| x.parse::<f32>().is_ok()).count() == n;
            (!ok).then_some(no)
        })
    };
    match err {
        // `v x y z [w]` or `v x y z r g b`: three, four or six numbers, w not 0.
        PositionParseError | ColorParseError | ScalingByZeroError => {
            lines().find_map(|(no, mut w)| {
                (w.next() == Some("v")).then_some(())?;
                let words: Vec<&str> = w.collect();
                let n: Vec<f32> = words.iter().filter_map(|x| x.parse().ok()).collect();
                let ok = n.len() == words.len()
                    && [3, 4, 6].contains(&n.len())
                    && (n.len() != 4 || n[3] != 0.0);
                (!ok).then_some(no)
            })
        }
        NormalParseError => numbers("vn", 3),
        TexcoordParseError => numbers("vt", 1),
        FaceParseError
        | FaceVertexOutOfBounds
        | FaceTexCoordOutOfBounds
        | FaceNormalOutOfBounds
        | InvalidPolygon => bad_face(text),
        _ => None,
    }
}

/// The first face (or line) element with too few corners, a corner of more than three
/// indices, or an index that is not a number or points outside the lists read before it.
fn bad_face(text: &str) -> Option<usize> {
    let mut seen = [0usize; 3];
    for (i, line) in text.lines().enumerate() {
        let mut w = line.split_whitespace();
        let min_corners = match w.next() {
            Some("v") => {
                seen[0] += 1;
                continue;
            }
            Some("vt") => {
                seen[1] += 1;
                continue;
            }
            Some("vn") => {
                seen[2] += 1;
                continue;
            }
            Some("f") => 3,
            Some("l") => 1,
            _ => continue,
        };
        let bad_index = |(k, idx): (usize, &str)| {
            if idx.is_empty() && k > 0 {
                return false;
            }
            match idx.parse::<i64>() {
                Ok(n) if n != 0 => n.unsigned_abs() as usize > seen[k],
                _ => true,
            }
        };
        let bad_corner =
            |c: &&str| c.split('/').count() > 3 || c.split('/').enumerate().any(bad_index);
        let corners: Vec<&str> = w.collect();
        if corners.len() < min_corners || corners.iter().any(bad_corner) {
            return Some(i + 1);
        }
    }
    None
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
        assert!(
            e.contains(": line 4: face vertex index out of bounds"),
            "{e}"
        );
        let bad = write("v 0 0 0\nv 1 0 x\nv 0 1 0\nf 1 2 3\n");
        let e = TriangleMesh::from_obj(bad.path()).unwrap_err().to_string();
        assert!(e.contains(": line 2: position parse error"), "{e}");
        let bad = write("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 -9 3\n");
        let e = TriangleMesh::from_obj(bad.path()).unwrap_err().to_string();
        assert!(e.contains(": line 4: "), "{e}");
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
