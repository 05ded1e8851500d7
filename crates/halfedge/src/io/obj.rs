//! OBJ input through `tobj` (plain files, most of them, in one pass by a reader of
//! their own, with the same result).
//!
//! `tobj` keeps only the positions that faces refer to and renumbers them per object in
//! order of first use. To keep every `v` line in file order, the file is handed to `tobj`
//! as one object (`o`, `g`, `usemtl` and `mtllib` lines are left out) preceded by one
//! synthetic polygon `f 1 2 … n` that names every vertex once in file order: `tobj`'s
//! numbering is then the file's, and the synthetic polygon is skipped afterwards.
//!
//! As in OpenMesh's OBJ reader, a face that names a vertex more than once keeps the
//! first mention of each vertex (`f 1 2 4 2 3` is read as `f 1 2 4 3`) and is dropped
//! when fewer than three vertices remain; polylines (`l`) are ignored. A line ending in
//! `\` continues on the next one, as the OBJ format says (OpenMesh 1.2.1 reads only the
//! first part of such a face). Every error names the line.
//!
//! The text need not be UTF-8: `tobj` reads UTF-8 lines, so bytes that are not UTF-8
//! (a Latin-1 `usemtl Terraindæk`, a comment in another encoding) are replaced by U+FFFD
//! first. Names and comments are not read, so such files read like their UTF-8
//! equivalents; in a number such bytes are a malformed number, an error naming the line.

use std::borrow::Cow;
use std::path::Path;

use glam::DVec3;

use crate::build::BuildReport;

use crate::error::{Error, Result};

use crate::mesh::Mesh;

/// Reads an OBJ file (positions and faces; normals, texture coordinates and materials are
/// ignored). Polygons are fan-triangulated by the builder.
pub fn read_obj(path: impl AsRef<Path>) -> Result<(Mesh, BuildReport)> {
    let path = path.as_ref();
    let bytes = super::read_bytes(path)?;
    read_obj_from_bytes(&bytes, path)
}

/// Reads OBJ text from memory; `path` is only used in error messages.
///
/// Errors name the file and the line. Bytes that are not UTF-8 are read as U+FFFD: they
/// do no harm in names and comments, and make a malformed number (an error naming its
/// line) in a `v` or `f` line.
pub fn read_obj_from_bytes(bytes: &[u8], path: &Path) -> Result<(Mesh, BuildReport)> {
    let format = |message: String| Error::Format {
        path: path.to_owned(),
        message,
    };
    if bytes.is_empty() {
        return Err(format("line 1: empty file".into()));
    }
    // Plain files in one pass; everything else (and every error) through tobj.
    if let Some(read) = super::obj_fast::read_plain_obj(bytes) {
        return Ok(read);
    }
    read_obj_through_tobj(bytes, path)
}

/// [`read_obj_from_bytes`] through tobj, for any file (see the module docs).
pub(super) fn read_obj_through_tobj(bytes: &[u8], path: &Path) -> Result<(Mesh, BuildReport)> {
    let format = |message: String| Error::Format {
        path: path.to_owned(),
        message,
    };
    // Bytes that are not UTF-8 (a Latin-1 material, group or object name, or comment)
    // become U+FFFD: those lines are not read anyway. In a `v` or `f` line they make a
    // malformed number, reported with its line. Valid UTF-8 is used as it is.
    let text = String::from_utf8_lossy(bytes);
    let text: &str = &text;

    // Count vertices, check face indices (so that errors can name the line) and keep the
    // lines tobj needs, as one object.
    let mut n_vertices = 0usize;
    // The largest positive face index and its line.
    let mut largest = (0u64, 0usize);
    let mut body = String::with_capacity(text.len() + 16);
    for (number, line) in kept_lines(text) {
        let mut tokens = line.split_whitespace();
        match tokens.next().unwrap_or("") {
            "v" => n_vertices += 1,
            "f" => {
                for token in tokens {
                    let index = face_index(token, n_vertices)
                        .map_err(|message| format(format!("line {number}: {message}")))?;
                    if index > largest.0 {
                        largest = (index, number);
                    }
                }
            }
            _ => {}
        }
        body.push_str(&line);
        body.push('\n');
    }
    if n_vertices == 0 {
        return Err(format(format!(
            "line {} (end of file): no vertices (no 'v' lines)",
            text.lines().count().max(1)
        )));
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

    let model = match load_tobj(&source) {
        Ok(model) => model,
        // Vertex colours on some `v` lines only: tobj refuses them, colours are not read
        // anyway.
        Err(tobj::LoadError::FaceColorOutOfBounds) => {
            load_tobj(&without_colours(&source)).map_err(|e| tobj_error(text, e, &format))?
        }
        Err(e) => return Err(tobj_error(text, e, &format)),
    };
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
    // OpenMesh's OBJ reader drops the repeated indices of a face (keeping the first of
    // each) and keeps the face when three or more vertices remain.
    let faces = offsets[1..]
        .iter()
        .map(|&(a, b)| without_repeats(&mesh.indices[a..b]));
    Mesh::from_polygons(&positions, faces).map_err(|e| match e {
        Error::IndexOutOfRange {
            face,
            index,
            vertex_count,
        } => format(format!(
            "line {}: face refers to vertex {} but the file has {vertex_count} vertices",
            nth_line_of(text, "f", face),
            index + 1
        )),
        Error::NonFiniteCoordinate { vertex, value } => format(format!(
            "line {}: vertex {} has a non-finite coordinate ({value})",
            nth_line_of(text, "v", vertex),
            vertex + 1
        )),
        other => format(other.to_string()),
    })
}

/// The lines tobj is given, numbered from 1 as in the file: all but `o`, `g`, `usemtl`
/// and `mtllib` (the file is read as one object) and `l` (polylines, which OpenMesh
/// ignores and tobj would read as faces). A line ending in `\` goes on on the next line
/// (the OBJ format's continuation, which exporters write for long faces); the joined
/// line has the number of its first.
fn kept_lines(text: &str) -> impl Iterator<Item = (usize, Cow<'_, str>)> {
    logical_lines(text).filter(|(_, line)| {
        !matches!(
            line.split_whitespace().next().unwrap_or(""),
            "o" | "g" | "usemtl" | "mtllib" | "l"
        )
    })
}

/// The lines of `text` numbered from 1, each joined with the lines after it while it
/// ends in `\` (before trailing white space), the `\` replaced by a space; borrowed
/// when nothing is joined.
fn logical_lines(text: &str) -> impl Iterator<Item = (usize, Cow<'_, str>)> {
    let mut lines = text.lines().enumerate();
    std::iter::from_fn(move || {
        let (i, first) = lines.next()?;
        let Some(head) = first.trim_end().strip_suffix('\\') else {
            return Some((i + 1, Cow::Borrowed(first)));
        };
        let mut joined = String::from(head);
        for (_, next) in lines.by_ref() {
            joined.push(' ');
            match next.trim_end().strip_suffix('\\') {
                Some(more) => joined.push_str(more),
                None => {
                    joined.push_str(next);
                    break;
                }
            }
        }
        Some((i + 1, Cow::Owned(joined)))
    })
}

/// The file's line of the `k`-th (0-based) line starting with `keyword` among the kept
/// lines (0 when there is none, which the callers never ask for).
fn nth_line_of(text: &str, keyword: &str, k: usize) -> usize {
    kept_lines(text)
        .filter(|(_, l)| l.split_whitespace().next() == Some(keyword))
        .nth(k)
        .map_or(0, |(n, _)| n)
}

/// tobj's parse of `source` as one model (materials are not loaded).
fn load_tobj(source: &str) -> std::result::Result<tobj::Model, tobj::LoadError> {
    let options = tobj::LoadOptions {
        single_index: false,
        triangulate: false,
        ..Default::default()
    };
    let (models, _) = tobj::load_obj_buf(&mut source.as_bytes(), &options, |_| {
        Err(tobj::LoadError::GenericFailure)
    })?;
    models
        .into_iter()
        .next()
        .ok_or(tobj::LoadError::GenericFailure)
}

/// A tobj error as a format error naming its line. tobj does not say where it failed:
/// the line is the first one whose addition makes tobj fail on the kept lines up to it
/// (found by bisection, only on this error path).
fn tobj_error(text: &str, e: tobj::LoadError, format: &dyn Fn(String) -> Error) -> Error {
    let lines: Vec<(usize, Cow<'_, str>)> = kept_lines(text).collect();
    let fails = |k: usize| {
        let mut prefix = String::new();
        for (_, l) in &lines[..k] {
            prefix.push_str(l);
            prefix.push('\n');
        }
        load_tobj(&prefix).is_err()
    };
    let place = if fails(lines.len()) {
        // Smallest k with fails(k): lo never fails, hi fails.
        let (mut lo, mut hi) = (0, lines.len());
        if fails(0) {
            hi = 0;
        }
        while hi > lo + 1 {
            let mid = lo + (hi - lo) / 2;
            if fails(mid) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        format!("line {}", lines.get(hi.max(1) - 1).map_or(1, |l| l.0))
    } else {
        // Only the whole file as tobj is given it fails: the error is about all of it.
        format!("line {} (end of file)", text.lines().count().max(1))
    };
    format(format!("{place}: OBJ parse error: {e}"))
}

/// The `v` lines of `source` without vertex colours (`v x y z r g b` → `v x y z`).
fn without_colours(source: &str) -> String {
    let mut out = String::with_capacity(source.len());
    for line in source.lines() {
        let tokens: Vec<&str> = line.split_whitespace().collect();
        if tokens.first() == Some(&"v") && tokens.len() == 7 {
            out.push_str(&tokens[..4].join(" "));
        } else {
            out.push_str(line);
        }
        out.push('\n');
    }
    out
}

/// A face's indices without repeats, the first of each kept in order (OpenMesh's OBJ
/// reader: `f 1 2 4 2 3` is the polygon `1 2 4 3`); borrowed when nothing repeats.
pub(super) fn without_repeats(face: &[u32]) -> Cow<'_, [u32]> {
    let repeats = (1..face.len()).any(|i| face[..i].contains(&face[i]));
    if !repeats {
        return Cow::Borrowed(face);
    }
    let mut kept: Vec<u32> = Vec::with_capacity(face.len());
    for &i in face {
        if !kept.contains(&i) {
            kept.push(i);
        }
    }
    Cow::Owned(kept)
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
