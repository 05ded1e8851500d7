//! STL input (ASCII and binary), read by hand.
//!
//! **Which encoding.** A file is binary when its size is exactly `84 + 50·n` bytes, `n`
//! being the triangle count at bytes 80–83 (binary files may begin with `solid` too, as
//! many exporters write them); else it is ASCII when its first word is `solid` and the
//! word after that line is `facet` or `endsolid`, or when it begins with `solid` and is
//! shorter than a binary header (84 bytes); else it is binary (and refused when it is
//! shorter than its count says).
//!
//! **What is read.** The three corners of every triangle, as `f32` (the format's type,
//! converted to `f64` exactly). Normals, the binary header and attribute bytes, and solid
//! names are ignored. Binary files: bytes after the last announced triangle are ignored.
//! ASCII files: keywords in any case, any white space layout, several `solid … endsolid`
//! in a row; names may hold any bytes (UTF-8 or not).
//!
//! **Welding.** An STL file is a triangle soup: every triangle has its own three
//! corners, and there are no file vertices (vertex `i` of the mesh read is **not**
//! anything numbered in the file). [`read_stl`] welds the soup by the rule of the
//! examples' `--weld auto`, that is [`Mesh::welded_seams`]: corners at exactly the same
//! position (`-0.0` and `0.0` alike) become one vertex, kept in order of first
//! appearance, when that leaves fewer boundary loops than the soup (one per triangle)
//! has; the number of corners merged is [`BuildReport::merged_vertices`], and triangles
//! that welding gives a repeated vertex (two corners at one place) are counted in
//! [`BuildReport::dropped_faces`]. Faces that would make the welded mesh non-manifold go
//! onto copies of their vertices, as for every format ([`crate::BuildReport`]). When welding
//! closes nothing (or nothing is at one place), the soup itself is returned:
//! vertex `3k + j` is corner `j` of triangle `k`. [`read_stl_soup_from_bytes`] never
//! welds.
//!
//! **Errors** are [`Error::Format`] naming the file and the place: the triangle and its
//! byte offset in a binary file, the line and the facet in an ASCII file. An empty file,
//! a binary file shorter than its triangle count says (checked before anything is
//! allocated: a header claiming 4 billion triangles in a 200-byte file allocates
//! nothing), a file without triangles, a non-finite coordinate, a malformed number, a
//! missing or unexpected keyword, a facet without exactly three vertices, an ASCII file
//! without `endsolid`. Reading never panics.

use std::path::Path;

use glam::DVec3;

use super::tokens::{Token, Tokens};
use crate::build::{BuildReport, PolygonBlock};
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::weld::weld_by_key;

/// Reads an STL file (ASCII or binary) and welds its triangle soup (see the
/// [module docs](self)).
pub fn read_stl(path: impl AsRef<Path>) -> Result<(Mesh, BuildReport)> {
    let path = path.as_ref();
    let bytes = super::read_bytes(path)?;
    read_stl_from_bytes(&bytes, path)
}

/// Reads STL data from memory and welds it (see the [module docs](self)); `path` is only
/// used in error messages.
pub fn read_stl_from_bytes(bytes: &[u8], path: &Path) -> Result<(Mesh, BuildReport)> {
    let corners = read_corners(bytes, path)?;
    build_welded(corners)
}

/// Reads STL data from memory without welding: triangle `k` is face `k`, on the vertices
/// `3k`, `3k + 1` and `3k + 2`; `path` is only used in error messages.
pub fn read_stl_soup_from_bytes(bytes: &[u8], path: &Path) -> Result<(Mesh, BuildReport)> {
    let corners = read_corners(bytes, path)?;
    build_soup(corners)
}

/// True when `bytes` are a binary STL by the rule of the [module docs](self) (an empty
/// file counts as neither and gives `false`).
pub fn is_binary_stl(bytes: &[u8]) -> bool {
    !bytes.is_empty() && !is_ascii(bytes)
}

/// The triangle count of a binary header and the file size it means.
fn binary_size(bytes: &[u8]) -> Option<(u32, u64)> {
    let count: [u8; 4] = bytes.get(80..84)?.try_into().ok()?;
    let n = u32::from_le_bytes(count);
    Some((n, 84 + 50 * u64::from(n)))
}

fn is_ascii(bytes: &[u8]) -> bool {
    if let Some((_, size)) = binary_size(bytes) {
        if size == bytes.len() as u64 {
            return false;
        }
    }
    let mut tokens = Tokens::new(bytes, false);
    if !tokens.next_token().is_some_and(|t| t.is("solid")) {
        return false;
    }
    tokens.skip_line();
    let followed = tokens
        .next_token()
        .is_some_and(|t| t.is("facet") || t.is("endsolid"));
    // A file that starts with `solid` and is too short for a binary header is read as
    // ASCII, so that its error says where the text goes wrong.
    followed || bytes.len() < 84
}

/// The corners of every triangle, three per triangle, in file order.
fn read_corners(bytes: &[u8], path: &Path) -> Result<Vec<[f32; 3]>> {
    let format = |message: String| Error::Format {
        path: path.to_owned(),
        message,
    };
    if bytes.is_empty() {
        return Err(format("line 1: empty file".into()));
    }
    let corners = if is_ascii(bytes) {
        read_ascii(bytes, &format)?
    } else {
        read_binary(bytes, &format)?
    };
    Ok(corners)
}

fn read_binary(bytes: &[u8], format: &dyn Fn(String) -> Error) -> Result<Vec<[f32; 3]>> {
    let Some((n, size)) = binary_size(bytes) else {
        return Err(format(format!(
            "byte {}: truncated file: a binary STL starts with an 80-byte header and a \
             4-byte triangle count, the file has {} bytes (and is not ASCII STL: no 'solid' \
             followed by 'facet' or 'endsolid')",
            bytes.len(),
            bytes.len()
        )));
    };
    if size > bytes.len() as u64 {
        let whole = (bytes.len() - 84) / 50;
        return Err(format(format!(
            "byte {}: truncated file: the header announces {n} triangles ({size} bytes), the \
             file has {} bytes (triangle {whole} is the first one missing or cut)",
            bytes.len(),
            bytes.len()
        )));
    }
    if n == 0 {
        return Err(format(
            "byte 80: no triangles (the triangle count is 0), so no vertices".into(),
        ));
    }
    let n = n as usize;
    let mut corners = Vec::with_capacity(3 * n);
    for (k, triangle) in bytes[84..84 + 50 * n].chunks_exact(50).enumerate() {
        for j in 0..3 {
            let at = 12 + 12 * j;
            let c: [f32; 3] = std::array::from_fn(|axis| {
                let b = at + 4 * axis;
                f32::from_le_bytes([
                    triangle[b],
                    triangle[b + 1],
                    triangle[b + 2],
                    triangle[b + 3],
                ])
            });
            if let Some(bad) = c.iter().find(|x| !x.is_finite()) {
                return Err(format(format!(
                    "triangle {k} (byte {}): corner {j} has a non-finite coordinate ({bad})",
                    84 + 50 * k + at
                )));
            }
            corners.push(c);
        }
    }
    Ok(corners)
}

fn read_ascii(bytes: &[u8], format: &dyn Fn(String) -> Error) -> Result<Vec<[f32; 3]>> {
    let mut tokens = Tokens::new(bytes, false);
    let mut corners = Vec::new();
    // `solid name`: the name is the rest of the line.
    tokens.next_token();
    tokens.skip_line();
    let mut facet = 0usize;
    let end = |tokens: &Tokens<'_>, expected: &str, facet: usize| {
        format(format!(
            "line {} (end of file): truncated file: expected {expected} (facet {facet})",
            tokens.line()
        ))
    };
    let unexpected = |t: Token<'_>, expected: &str, facet: usize| {
        format(format!(
            "line {}, facet {facet}: expected {expected}, found '{}'",
            t.line,
            t.shown()
        ))
    };
    loop {
        let Some(t) = tokens.next_token() else {
            return Err(end(&tokens, "'facet' or 'endsolid'", facet));
        };
        if t.is("endsolid") {
            tokens.skip_line();
            match tokens.next_token() {
                None => break,
                // Another solid.
                Some(t) if t.is("solid") => {
                    tokens.skip_line();
                    continue;
                }
                Some(t) => return Err(unexpected(t, "'solid' or the end of the file", facet)),
            }
        }
        if !t.is("facet") {
            return Err(unexpected(t, "'facet' or 'endsolid'", facet));
        }
        // `normal nx ny nz`: not used, not parsed.
        for expected in [
            "'normal'",
            "the normal's x",
            "the normal's y",
            "the normal's z",
        ] {
            match tokens.next_token() {
                None => return Err(end(&tokens, expected, facet)),
                Some(t) if expected == "'normal'" && !t.is("normal") => {
                    return Err(unexpected(t, expected, facet))
                }
                Some(_) => {}
            }
        }
        for word in ["outer", "loop"] {
            match tokens.next_token() {
                None => return Err(end(&tokens, &format!("'{word}'"), facet)),
                Some(t) if !t.is(word) => return Err(unexpected(t, &format!("'{word}'"), facet)),
                Some(_) => {}
            }
        }
        for corner in 0..3 {
            match tokens.next_token() {
                None => return Err(end(&tokens, "'vertex'", facet)),
                Some(t) if t.is("endloop") => {
                    return Err(format(format!(
                        "line {}, facet {facet}: the loop has {corner} vertices, an STL facet \
                         has three",
                        t.line
                    )))
                }
                Some(t) if !t.is("vertex") => return Err(unexpected(t, "'vertex'", facet)),
                Some(_) => {}
            }
            let mut p = [0.0f32; 3];
            for (axis, c) in p.iter_mut().enumerate() {
                let Some(t) = tokens.next_token() else {
                    return Err(end(&tokens, "a coordinate", facet));
                };
                let value: f32 = std::str::from_utf8(t.text)
                    .ok()
                    .and_then(|s| s.parse().ok())
                    .ok_or_else(|| {
                        format(format!(
                            "line {}, facet {facet}: malformed coordinate '{}'",
                            t.line,
                            t.shown()
                        ))
                    })?;
                if !value.is_finite() {
                    return Err(format(format!(
                        "line {}, facet {facet}: corner {corner} has a non-finite coordinate \
                         ('{}' is {value} as f32, axis {axis})",
                        t.line,
                        t.shown()
                    )));
                }
                *c = value;
            }
            corners.push(p);
        }
        match tokens.next_token() {
            None => return Err(end(&tokens, "'endloop'", facet)),
            Some(t) if t.is("vertex") => {
                return Err(format(format!(
                    "line {}, facet {facet}: the loop has more than three vertices, an STL \
                     facet has three",
                    t.line
                )))
            }
            Some(t) if !t.is("endloop") => return Err(unexpected(t, "'endloop'", facet)),
            Some(_) => {}
        }
        match tokens.next_token() {
            None => return Err(end(&tokens, "'endfacet'", facet)),
            Some(t) if !t.is("endfacet") => return Err(unexpected(t, "'endfacet'", facet)),
            Some(_) => {}
        }
        facet += 1;
    }
    if corners.is_empty() {
        return Err(format(format!(
            "line {}: no triangles (no facets between 'solid' and 'endsolid'), so no vertices",
            tokens.line()
        )));
    }
    Ok(corners)
}

/// A corner as a `DVec3` (exactly: every `f32` is an `f64`).
fn position(c: [f32; 3]) -> DVec3 {
    DVec3::new(c[0].into(), c[1].into(), c[2].into())
}

/// The soup: triangle `k` on the corners `3k`, `3k + 1`, `3k + 2`.
fn build_soup(corners: Vec<[f32; 3]>) -> Result<(Mesh, BuildReport)> {
    let n = corners.len() as u32;
    let block = PolygonBlock {
        indices: (0..n).collect(),
        offsets: None,
    };
    let positions = corners.into_iter().map(position).collect();
    Mesh::from_polygon_blocks(positions, vec![block])
}

/// The soup welded by the rule of [`Mesh::welded_seams`] (see the [module docs](self)),
/// without building the soup first: the soup has one boundary loop per triangle.
fn build_welded(corners: Vec<[f32; 3]>) -> Result<(Mesh, BuildReport)> {
    let (kept, map) = weld_corners(&corners);
    if kept.len() < corners.len() {
        let positions: Vec<DVec3> = kept
            .iter()
            .map(|&i| position(corners[i as usize]))
            .collect();
        // Corner `3k + j` of the soup is vertex `map[3k + j]` of the welded mesh: the map
        // is the welded triangles' index list.
        let block = PolygonBlock {
            indices: map,
            offsets: None,
        };
        let (mesh, mut report) = Mesh::from_polygon_blocks(positions, vec![block])?;
        if mesh.boundary_loops().len() < corners.len() / 3 {
            report.merged_vertices = corners.len() - kept.len();
            return Ok((mesh, report));
        }
    }
    build_soup(corners)
}

/// Corners at the same position (`-0.0` and `0.0` alike) merged by the crate's one exact
/// weld ([`crate::weld::weld_exact`]'s, on the `f32` bits: the same result as on the
/// corners as `f64`): the kept corners (the first at each position, in order) and every
/// corner's kept corner's number. A closed soup has about six corners per vertex.
fn weld_corners(corners: &[[f32; 3]]) -> (Vec<u32>, Vec<u32>) {
    // `+ 0.0` turns -0.0 into 0.0 and leaves every other value as it is.
    weld_by_key(corners.len(), corners.len() / 6, |i| {
        corners[i].map(|x| (x + 0.0).to_bits())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The hash map weld gives what the sort of `crate::weld::weld_exact` gives, on
    /// corners with repeats, signed zeros, near values and a coarse grid.
    #[test]
    fn weld_corners_is_weld_exact() {
        let mut corners: Vec<[f32; 3]> = Vec::new();
        for i in 0..3000u32 {
            let k = (i.wrapping_mul(2_654_435_761) >> 20) % 500;
            corners.push([(k % 10) as f32 * 0.25, (k / 10) as f32, 0.0]);
            corners.push([-0.0, (k % 7) as f32, f32::from_bits(0x3f80_0000 + k % 3)]);
        }
        let (kept, map) = weld_corners(&corners);
        let points: Vec<DVec3> = corners.iter().map(|&c| position(c)).collect();
        assert_eq!((kept, map), crate::weld::weld_exact(&points));
    }
}
