//! STL output, binary (the default) or ASCII.
//!
//! Every face is written as a triangle starting at its [`Mesh::triangle`] corner, in
//! [`Mesh::faces`] order, with its unit normal computed from the positions (zero for a
//! degenerate face). Coordinates and normals are `f32`, as the format is: positions are
//! rounded to the nearest `f32` (reading the file back gives them as `f32`). Binary
//! files have an 80-byte header that does not begin with `solid` (so that no reader
//! takes them for ASCII), the triangle count, and 50 bytes per triangle (attribute bytes
//! 0). ASCII files write every number with the shortest decimal that parses back to the
//! same `f32`, in one solid named `multires`.
//!
//! STL has no shared vertices: [`read_stl`](super::stl::read_stl) welds corners at the
//! same position back together, so a closed mesh written and read again is the same
//! closed mesh (vertices in order of first appearance in the faces).

use std::io::Write;
use std::path::Path;

use crate::error::{Error, Result};
use crate::mesh::Mesh;

/// The STL encodings the writer produces.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum StlFormat {
    /// Binary, little endian (the common STL; 50 bytes per triangle).
    #[default]
    Binary,
    /// Text (`solid` … `endsolid`).
    Ascii,
}

/// Writes a mesh as STL in the given encoding (see the [module docs](self)).
pub fn write_stl(path: impl AsRef<Path>, mesh: &Mesh, format: StlFormat) -> Result<()> {
    let path = path.as_ref();
    super::write_file(path, |out| write_stl_to(out, mesh, format))
}

/// Writes a mesh as STL into any writer (see the [module docs](self)). Returns an
/// [`Error::InvalidArgument`] when a position does not fit `f32` (a coordinate beyond
/// ±3.4e38) or a binary file would have more than `u32::MAX` triangles, and
/// [`Error::Io`] (with an empty path) if writing fails.
pub fn write_stl_to(out: &mut impl Write, mesh: &Mesh, format: StlFormat) -> Result<()> {
    let io = |source: std::io::Error| Error::Io {
        path: Default::default(),
        source,
    };
    for v in mesh.vertices() {
        let p = mesh.position(v);
        if !p.as_vec3().is_finite() {
            return Err(Error::InvalidArgument(format!(
                "vertex {} at {p} does not fit STL's f32 coordinates",
                mesh.vertex_index(v)
            )));
        }
    }
    let triangles = mesh.faces().map(|f| {
        let n = mesh.face_normal(f).as_vec3().to_array();
        let corners = mesh
            .triangle(f)
            .map(|v| mesh.position(v).as_vec3().to_array());
        (n, corners)
    });
    match format {
        StlFormat::Binary => {
            let count = u32::try_from(mesh.n_faces()).map_err(|_| {
                Error::InvalidArgument(format!(
                    "{} faces do not fit a binary STL's 32-bit triangle count",
                    mesh.n_faces()
                ))
            })?;
            let mut header = [b' '; 80];
            let text = b"binary STL written by multires (halfedge crate)";
            header[..text.len()].copy_from_slice(text);
            out.write_all(&header).map_err(io)?;
            out.write_all(&count.to_le_bytes()).map_err(io)?;
            let mut record = [0u8; 50];
            for (n, corners) in triangles {
                let values = n.iter().chain(corners.iter().flatten());
                for (k, x) in values.enumerate() {
                    record[4 * k..4 * k + 4].copy_from_slice(&x.to_le_bytes());
                }
                out.write_all(&record).map_err(io)?;
            }
        }
        StlFormat::Ascii => {
            writeln!(out, "solid multires").map_err(io)?;
            for (n, corners) in triangles {
                writeln!(out, "  facet normal {} {} {}", n[0], n[1], n[2]).map_err(io)?;
                writeln!(out, "    outer loop").map_err(io)?;
                for c in corners {
                    writeln!(out, "      vertex {} {} {}", c[0], c[1], c[2]).map_err(io)?;
                }
                writeln!(out, "    endloop\n  endfacet").map_err(io)?;
            }
            writeln!(out, "endsolid multires").map_err(io)?;
        }
    }
    out.flush().map_err(io)
}
