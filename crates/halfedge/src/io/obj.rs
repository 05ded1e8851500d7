//! OBJ input through `tobj`.
//!
//! `tobj` keeps only the positions that faces refer to and renumbers them per object in
//! order of first use. To keep every `v` line in file order, the file is handed to `tobj`
//! as one object (`o`, `g`, `usemtl` and `mtllib` lines are left out) preceded by one
//! synthetic polygon `f 1 2 … n` that names every vertex once in file order: `tobj`'s
//! numbering is then the file's, and the synthetic polygon is skipped afterwards.

use std::path::Path;

use glam::DVec3;

use crate::{BuildReport, Error, Mesh, Result};

/// Reads an OBJ file (positions and faces; normals, texture coordinates and materials are
/// ignored). Polygons are fan-triangulated by the builder.
pub fn read_obj(path: impl AsRef<Path>) -> Result<(Mesh, BuildReport)> {
    let path = path.as_ref();
    let bytes = super::read_bytes(path)?;
    read_obj_from_bytes(&bytes, path)
}

/// Reads OBJ text from memory; `path` is only used in error messages.
pub fn read_obj_from_bytes(bytes: &[u8], path: &Path) -> Result<(Mesh, BuildReport)> {
    let format = |message: String| Error::Format {
        path: path.to_owned(),
        message,
    };
    if bytes.is_empty() {
        return Err(format("empty file".into()));
    }
    let text = std::str::from_utf8(bytes).map_err(|e| format(format!("not UTF-8 text: {e}")))?;

    // Count vertices, check face indices (so that errors can name the line) and keep the
    // lines tobj needs, as one object.
    let mut n_vertices = 0usize;
    // The largest positive face index and its line.
    let mut largest = (0u64, 0usize);
    let mut body = String::with_capacity(text.len() + 16);
    for (number, line) in text.lines().enumerate() {
        let mut tokens = line.split_whitespace();
        match tokens.next().unwrap_or("") {
            "o" | "g" | "usemtl" | "mtllib" => continue,
            "v" => n_vertices += 1,
            "f" => {
                for token in tokens {
                    let index = face_index(token, n_vertices)
                        .map_err(|message| format(format!("line {}: {message}", number + 1)))?;
                    if index > largest.0 {
                        largest = (index, number + 1);
                    }
                }
            }
            _ => {}
        }
        body.push_str(line);
        body.push('\n');
    }
    if n_vertices == 0 {
        return Err(format("no vertices (no 'v' lines)".into()));
    }
    if largest.0 > n_vertices as u64 {
        return Err(format(format!(
            "line {}: face refers to vertex {}, but the file has {n_vertices} vertices",
            largest.1, largest.0
        )));
    }
    let mut prefix = String::with_capacity(8 * n_vertices);
    prefix.push('f');
    for i in 1..=n_vertices {
        prefix.push(' ');
        prefix.push_str(itoa(i).as_str());
    }
    prefix.push('\n');
    let source = prefix + &body;

    let options = tobj::LoadOptions {
        single_index: false,
        triangulate: false,
        ..Default::default()
    };
    let (models, _) = tobj::load_obj_buf(&mut source.as_bytes(), &options, |_| {
        Err(tobj::LoadError::GenericFailure)
    })
    .map_err(|e| format(format!("OBJ parse error: {e}")))?;
    let model = models
        .into_iter()
        .next()
        .ok_or_else(|| format("no geometry".into()))?;
    let mesh = model.mesh;
    if mesh.positions.len() != 3 * n_vertices {
        return Err(format(format!(
            "expected {n_vertices} vertices, tobj returned {}",
            mesh.positions.len() / 3
        )));
    }
    let positions: Vec<DVec3> = mesh
        .positions
        .chunks_exact(3)
        .map(|c| DVec3::new(c[0], c[1], c[2]))
        .collect();

    // Faces: skip the synthetic first polygon.
    let arities: Vec<u32> = if mesh.face_arities.is_empty() {
        vec![3; mesh.indices.len() / 3]
    } else {
        mesh.face_arities.clone()
    };
    let mut offsets = Vec::with_capacity(arities.len());
    let mut start = 0usize;
    for &a in &arities {
        offsets.push((start, start + a as usize));
        start += a as usize;
    }
    if start != mesh.indices.len() {
        return Err(format(
            "face index count does not match the face arities".into(),
        ));
    }
    let faces = offsets[1..].iter().map(|&(a, b)| &mesh.indices[a..b]);
    Mesh::from_polygons(&positions, faces).map_err(|e| match e {
        Error::IndexOutOfRange {
            face,
            index,
            vertex_count,
        } => format(format!(
            "face {face} refers to vertex {} but the file has {vertex_count} vertices",
            index + 1
        )),
        Error::NonFiniteCoordinate { vertex, value } => format(format!(
            "vertex {} has a non-finite coordinate ({value})",
            vertex + 1
        )),
        other => other,
    })
}

/// The 1-based vertex index of a face token (`v`, `v/vt`, `v//vn`, `v/vt/vn`); negative
/// indices count back from the last vertex read so far.
fn face_index(token: &str, vertices_so_far: usize) -> std::result::Result<u64, String> {
    let text = token.split('/').next().unwrap_or("");
    let index: i64 = text
        .parse()
        .map_err(|_| format!("malformed face index '{token}'"))?;
    match index {
        0 => Err("face index 0 (OBJ indices start at 1)".into()),
        i if i > 0 => Ok(i as u64),
        i => {
            let resolved = vertices_so_far as i64 + i + 1;
            if resolved < 1 {
                Err(format!(
                    "relative face index {i} points before the first vertex ({vertices_so_far} vertices so far)"
                ))
            } else {
                Ok(resolved as u64)
            }
        }
    }
}

fn itoa(i: usize) -> String {
    i.to_string()
}
