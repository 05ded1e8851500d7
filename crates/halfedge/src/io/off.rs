//! OFF input (Geomview's Object File Format, ASCII), read by hand.
//!
//! **What is read.** The header keyword `OFF`, or `COFF` (a colour after each vertex's
//! coordinates), `NOFF` (a normal), `STOFF` (texture coordinates) and their combinations
//! in the format's order (`STCNOFF`, `CNOFF`, …); the keyword may be left out, as the
//! format allows. Then the counts `V F E` (on the keyword's line or after it; `E` is
//! read and ignored), `V` vertices (`x y z`, then `nx ny nz` for `N`), and `F` faces
//! `n i0 … in-1` with 0-based indices. Colours, normals and texture coordinates are
//! ignored. Polygons are fan-triangulated by the builder ([`crate::BuildReport`]), and vertex
//! `i` of the file is [`Mesh::vertex_at`]`(i)`, as for OBJ and PLY.
//!
//! **Layout.** Values are separated by any white space (`\n`, `\r\n` or `\r` line ends);
//! `#` starts a comment anywhere, up to the end of its line; a UTF-8 byte order mark is
//! skipped, and bytes that are not UTF-8 are fine in comments. The keyword and the counts
//! may share a line or not. As OpenMesh reads OFF (and as every OFF writer writes it),
//! each vertex and each face ends its line: its values may go on over several lines, and
//! what follows its last value on that line is skipped — a vertex's colour and texture
//! coordinates (at most those its keyword announces plus 4, so that the colours some
//! writers put after plain `OFF` vertices are skipped too), a face's colour (at most 4
//! values). More values there are an error (several faces on one line, a face count
//! that does not match its indices). Anything after the last face (edges some writers
//! add) is ignored.
//!
//! **Refused, with a clear error:** binary OFF (`OFF BINARY`), `4OFF` and `nOFF`
//! (4-dimensional and n-dimensional vertices).
//!
//! **Errors** are [`Error::Format`] naming the file, the line and what is wrong: an
//! empty file, a missing or unknown keyword, malformed or missing counts, no vertices,
//! counts larger than the file can hold (checked before anything is allocated: a header
//! announcing 10¹² vertices in a 100-byte file allocates nothing), a file that ends
//! before its last face, a malformed or non-finite coordinate, a negative or
//! out-of-range index, too many values after a vertex or a face on its line. Reading
//! never panics.

use std::path::Path;

use glam::DVec3;

use super::tokens::Tokens;
use crate::build::{BuildReport, PolygonBlock};
use crate::error::{Error, Result};
use crate::mesh::Mesh;

/// Reads an OFF file (see the [module docs](self)).
pub fn read_off(path: impl AsRef<Path>) -> Result<(Mesh, BuildReport)> {
    let path = path.as_ref();
    let bytes = super::read_bytes(path)?;
    read_off_from_bytes(&bytes, path)
}

/// What the header keyword announces.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Keyword {
    texture: bool,
    colours: bool,
    normals: bool,
    four: bool,
    n_dim: bool,
}

impl Keyword {
    /// `[ST][C][N][4][n]OFF`, or `None` for any other token.
    fn parse(text: &[u8]) -> Option<Keyword> {
        let mut rest = text.strip_suffix(b"OFF")?;
        let mut k = Keyword::default();
        let mut flag = |prefix: &[u8], set: &mut bool| {
            if let Some(r) = rest.strip_prefix(prefix) {
                rest = r;
                *set = true;
            }
        };
        flag(b"ST", &mut k.texture);
        flag(b"C", &mut k.colours);
        flag(b"N", &mut k.normals);
        flag(b"4", &mut k.four);
        flag(b"n", &mut k.n_dim);
        rest.is_empty().then_some(k)
    }

    /// Values read per vertex: coordinates, and the normal for `N`.
    fn fields(self) -> usize {
        if self.normals {
            6
        } else {
            3
        }
    }

    /// Values allowed after the fields on a vertex's line: a colour (up to 4) for `C`,
    /// texture coordinates (2) for `ST`, and 4 more for a colour the keyword does not
    /// announce.
    fn extras(self) -> usize {
        4 * usize::from(self.colours) + 2 * usize::from(self.texture) + 4
    }
}

/// Polygons in blocks of about a megabyte (see [`PolygonBlock`]), which the builder frees
/// one by one.
struct Blocks {
    full: Vec<PolygonBlock>,
    block: PolygonBlock,
}

impl Blocks {
    const BLOCK: usize = 1 << 20;

    fn end_polygon(&mut self, start: usize) {
        self.block.end_polygon(start);
        if self.block.indices.len() >= Self::BLOCK {
            self.full.push(std::mem::take(&mut self.block));
        }
    }

    fn into_blocks(mut self) -> Vec<PolygonBlock> {
        self.full.push(self.block);
        self.full
    }
}

/// Reads OFF text from memory; `path` is only used in error messages.
pub fn read_off_from_bytes(bytes: &[u8], path: &Path) -> Result<(Mesh, BuildReport)> {
    let format = |message: String| Error::Format {
        path: path.to_owned(),
        message,
    };
    if bytes.is_empty() {
        return Err(format("line 1: empty file".into()));
    }
    let mut tokens = Tokens::new(bytes, true);
    let Some(first) = tokens.peek() else {
        tokens.next_token();
        return Err(format(format!(
            "line {} (end of file): no OFF header (the file has only comments or white space)",
            tokens.line()
        )));
    };
    let keyword = match Keyword::parse(first.text) {
        Some(k) => {
            tokens.next_token();
            k
        }
        // The keyword is optional: the file starts with the counts.
        None if first.u64().is_some() => Keyword::default(),
        None => {
            return Err(format(format!(
                "line {}: not an OFF file: expected the keyword OFF (or COFF, NOFF, CNOFF, \
                 STOFF) or the counts, found '{}'",
                first.line,
                first.shown()
            )))
        }
    };
    if keyword.four || keyword.n_dim {
        return Err(format(format!(
            "line {}: '{}' files (4-dimensional or n-dimensional vertices) are not supported",
            first.line,
            first.shown()
        )));
    }
    if let Some(next) = tokens.peek() {
        if next.line == first.line && next.is("BINARY") {
            return Err(format(format!(
                "line {}: binary OFF ('{} BINARY') is not supported: convert it to ASCII OFF",
                next.line,
                first.shown()
            )));
        }
    }

    // Counts.
    let mut count = |what: &str| -> Result<(u64, usize)> {
        match tokens.next_token() {
            None => Err(format(format!(
                "line {} (end of file): the header ends before the {what} count",
                tokens.line()
            ))),
            Some(t) => t.u64().map(|n| (n, t.line)).ok_or_else(|| {
                format(format!(
                    "line {}: expected the {what} count, found '{}'",
                    t.line,
                    t.shown()
                ))
            }),
        }
    };
    let (n_vertices, counts_line) = count("vertex")?;
    let (n_faces, _) = count("face")?;
    count("edge")?;
    if n_vertices == 0 {
        return Err(format(format!(
            "line {counts_line}: no vertices (the vertex count is 0)"
        )));
    }
    if n_vertices > u64::from(u32::MAX) {
        return Err(format(format!(
            "line {counts_line}: {n_vertices} vertices are more than 32-bit indices address"
        )));
    }
    // Each vertex takes at least two bytes per value (a digit and a separator), each face
    // two (its count and a line end): counts the rest of the file cannot hold are refused
    // before anything is allocated.
    let least = u128::from(n_vertices) * 2 * keyword.fields() as u128 + u128::from(n_faces) * 2;
    let remaining = tokens.remaining() as u128;
    if least > remaining + 1 {
        return Err(format(format!(
            "line {counts_line}: the header announces {n_vertices} vertices and {n_faces} \
             faces, more than the {remaining} bytes after it can hold (truncated file?)"
        )));
    }
    let n_vertices = n_vertices as usize;

    // Vertices.
    let mut positions: Vec<DVec3> = Vec::with_capacity(n_vertices);
    let end_of_file = |tokens: &Tokens<'_>, what: String| {
        format(format!(
            "line {} (end of file): truncated file: the file ends in {what}",
            tokens.line()
        ))
    };
    for i in 0..n_vertices {
        let mut p = [0.0f64; 3];
        for field in 0..keyword.fields() {
            let Some(t) = tokens.next_token() else {
                return Err(end_of_file(
                    &tokens,
                    format!("vertex {i} ({n_vertices} announced)"),
                ));
            };
            let value = t.f64().ok_or_else(|| {
                format(format!(
                    "line {}: vertex {i}: malformed number '{}'",
                    t.line,
                    t.shown()
                ))
            })?;
            if let Some(c) = p.get_mut(field) {
                if !value.is_finite() {
                    return Err(format(format!(
                        "line {}: vertex {i} has a non-finite coordinate ({})",
                        t.line,
                        t.shown()
                    )));
                }
                *c = value;
            }
        }
        positions.push(DVec3::from_array(p));
        let (extra, first) = tokens.skip_line();
        if extra > keyword.extras() {
            let line = first.map_or(0, |t| t.line);
            return Err(format(format!(
                "line {line}: vertex {i} is followed by {extra} values on its line, more than \
                 a colour and texture coordinates ({} at most): one vertex per line",
                keyword.extras()
            )));
        }
    }

    // Faces: the block of indices grows with what the file really has.
    let mut blocks = Blocks {
        full: Vec::new(),
        block: PolygonBlock::default(),
    };
    for face in 0..n_faces {
        let Some(t) = tokens.next_token() else {
            return Err(end_of_file(
                &tokens,
                format!("the faces: face {face} of {n_faces} is missing"),
            ));
        };
        let n = t.u64().ok_or_else(|| {
            format(format!(
                "line {}: face {face}: expected its number of vertices, found '{}'",
                t.line,
                t.shown()
            ))
        })?;
        let start = blocks.block.indices.len();
        for _ in 0..n {
            let Some(t) = tokens.next_token() else {
                return Err(end_of_file(
                    &tokens,
                    format!("face {face} ({n} vertices announced)"),
                ));
            };
            let index = t.i64().ok_or_else(|| {
                format(format!(
                    "line {}: face {face}: malformed vertex index '{}'",
                    t.line,
                    t.shown()
                ))
            })?;
            if index < 0 {
                return Err(format(format!(
                    "line {}: face {face} has a negative vertex index ({index})",
                    t.line
                )));
            }
            if index as u64 >= n_vertices as u64 {
                return Err(format(format!(
                    "line {}: face {face} refers to vertex {index}, but the file has \
                     {n_vertices} vertices",
                    t.line
                )));
            }
            blocks.block.indices.push(index as u32);
        }
        blocks.end_polygon(start);
        let (extra, first) = tokens.skip_line();
        if extra > 4 {
            let line = first.map_or(0, |t| t.line);
            return Err(format(format!(
                "line {line}: face {face} is followed by {extra} values on its line, more \
                 than a colour (4 at most): one face per line, with as many indices as its \
                 count says"
            )));
        }
    }
    Mesh::from_polygon_blocks(positions, blocks.into_blocks()).map_err(|e| match e {
        // Indices and coordinates were checked above, with their lines.
        Error::IndexOutOfRange { .. } | Error::NonFiniteCoordinate { .. } => format(e.to_string()),
        other => other,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keywords() {
        let k = |s: &str| Keyword::parse(s.as_bytes());
        assert_eq!(k("OFF"), Some(Keyword::default()));
        assert!(k("COFF").unwrap().colours);
        assert!(k("NOFF").unwrap().normals);
        let all = k("STCN4nOFF").unwrap();
        assert!(all.texture && all.colours && all.normals && all.four && all.n_dim);
        for bad in ["off", "NCOFF", "OFFF", "XOFF", "OF", "", "COFFx"] {
            assert_eq!(k(bad), None, "{bad}");
        }
        assert_eq!(k("CNOFF").unwrap().fields(), 6);
        assert_eq!(k("STCOFF").unwrap().extras(), 10);
    }
}
