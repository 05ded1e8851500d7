//! OFF output: the keyword `OFF`, the counts `V F E`, `x y z` lines and `3 a b c` lines,
//! nothing else.
//!
//! Coordinates are written with Rust's shortest round-trip formatting of `f64` (`{}`), so
//! reading the file back gives the very same bits. Live vertices are written compacted,
//! in [`Mesh::vertices`] order (see [`file_vertex_indices`](super::file_vertex_indices));
//! face indices are 0-based as OFF wants; `E` is the mesh's number of edges.

use std::io::Write;
use std::path::Path;

use crate::error::{Error, Result};
use crate::mesh::Mesh;

/// Writes a mesh as OFF (see the [module docs](self)).
pub fn write_off(path: impl AsRef<Path>, mesh: &Mesh) -> Result<()> {
    let path = path.as_ref();
    super::write_file(path, |out| write_off_to(out, mesh))
}

/// Writes a mesh as OFF into any writer; errors are [`Error::Io`] with an empty path.
pub fn write_off_to(out: &mut impl Write, mesh: &Mesh) -> Result<()> {
    let io = |source: std::io::Error| Error::Io {
        path: Default::default(),
        source,
    };
    writeln!(
        out,
        "OFF\n{} {} {}",
        mesh.n_vertices(),
        mesh.n_faces(),
        mesh.n_edges()
    )
    .map_err(io)?;
    for v in mesh.vertices() {
        let p = mesh.position(v);
        writeln!(out, "{} {} {}", p.x, p.y, p.z).map_err(io)?;
    }
    let index = super::file_vertex_indices(mesh);
    for f in mesh.faces() {
        let [a, b, c] = mesh.triangle(f).map(|v| index[mesh.vertex_index(v)]);
        writeln!(out, "3 {a} {b} {c}").map_err(io)?;
    }
    out.flush().map_err(io)
}
