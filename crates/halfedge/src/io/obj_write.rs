//! OBJ output: `v x y z` and `f a b c` lines, nothing else.
//!
//! Coordinates are written with Rust's shortest round-trip formatting of `f64` (`{}`), so
//! reading the file back gives the very same bits. Live vertices are written compacted,
//! in [`Mesh::vertices`] order (see [`file_vertex_indices`](super::file_vertex_indices));
//! face indices are 1-based as OBJ wants.

use std::io::Write;
use std::path::Path;

use crate::error::{Error, Result};

use crate::mesh::Mesh;

/// Writes a mesh as OBJ (see the [module docs](self)).
pub fn write_obj(path: impl AsRef<Path>, mesh: &Mesh) -> Result<()> {
    let path = path.as_ref();
    super::write_file(path, |out| write_obj_to(out, mesh))
}

/// Writes a mesh as OBJ into any writer; errors are [`Error::Io`] with an empty path.
pub fn write_obj_to(out: &mut impl Write, mesh: &Mesh) -> Result<()> {
    let io = |source: std::io::Error| Error::Io {
        path: Default::default(),
        source,
    };
    writeln!(
        out,
        "# written by multires (halfedge crate): {} vertices, {} faces",
        mesh.n_vertices(),
        mesh.n_faces()
    )
    .map_err(io)?;
    for v in mesh.vertices() {
        let p = mesh.position(v);
        writeln!(out, "v {} {} {}", p.x, p.y, p.z).map_err(io)?;
    }
    let index = super::file_vertex_indices(mesh);
    for f in mesh.faces() {
        let [a, b, c] = mesh
            .triangle(f)
            .map(|v| u64::from(index[mesh.vertex_index(v)]) + 1);
        writeln!(out, "f {a} {b} {c}").map_err(io)?;
    }
    out.flush().map_err(io)
}
