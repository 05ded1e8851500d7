//! Mesh files: OBJ (read with `tobj`, written by hand) and PLY (read and written with
//! `ply-rs-bw`, plus a fast route for common binary layouts), OFF ([`off`], by hand),
//! STL ([`stl`], ASCII and binary, by hand; a triangle soup, welded on reading), and any
//! of them gzip-compressed ([`gz`]: `.obj.gz`, `.ply.gz`, `.off.gz`, `.stl.gz`).
//!
//! **Reading** keeps every vertex of the file in file order (vertex `i` of the file has
//! [`Mesh::vertex_index`](crate::Mesh::vertex_index) `i`, unreferenced vertices become
//! isolated vertices; vertices duplicated by the builder come after the file's) and builds
//! faces with the policy of [`crate::BuildReport`]. Bad files give [`Error::Format`] (naming the
//! file and what is wrong where) or [`Error::Io`]; reading never panics.
//!
//! **Writing** writes the live vertices compacted, in [`Mesh::vertices`] order: vertex `k`
//! of the written file is the `k`-th live vertex, [`file_vertex_indices`] gives the map.
//! For a mesh without removed vertices (for instance one just read) this is the identity
//! on [`Mesh::vertex_index`](crate::Mesh::vertex_index), so read → write → read keeps
//! vertex numbers. Faces are written as triangles in [`Mesh::faces`] order, each starting
//! at its [`Mesh::triangle`] corner, so a written mesh reads back with the same faces.

pub mod gz;
pub mod obj;
mod obj_fast;
pub mod obj_write;
pub mod off;
pub mod off_write;
pub mod ply;
mod ply_fast;
pub(crate) mod ply_layout;
pub mod ply_write;
pub mod stl;
pub mod stl_write;
mod tokens;

use std::io::{BufWriter, Write};
use std::path::Path;

use crate::build::BuildReport;

use crate::error::{Error, Result};

use crate::mesh::Mesh;

pub use gz::{read_gz, read_gz_from_bytes, write_gz};
pub use obj::{read_obj, read_obj_from_bytes};
pub use obj_write::{write_obj, write_obj_to};
pub use off::{read_off, read_off_from_bytes};
pub use off_write::{write_off, write_off_to};
pub use ply::{read_ply, read_ply_from_bytes};
pub use ply_write::{write_ply, write_ply_to, PlyFormat};
pub use stl::{read_stl, read_stl_from_bytes};
pub use stl_write::{write_stl, write_stl_to, StlFormat};

/// Reads a mesh file, choosing the format by extension (`.obj`, `.ply`, `.off`, `.stl`,
/// each also gzip-compressed as `.obj.gz` and so on; any case). STL files are welded
/// (see [`stl`]): their vertex `i` is no file vertex.
pub fn read(path: impl AsRef<Path>) -> Result<(Mesh, BuildReport)> {
    let path = path.as_ref();
    match extension(path).as_deref() {
        Some("obj") => read_obj(path),
        Some("ply") => read_ply(path),
        Some("off") => read_off(path),
        Some("stl") => read_stl(path),
        Some("gz") => read_gz(path),
        _ => Err(Error::UnknownFormat(path.to_owned())),
    }
}

/// Writes a mesh file, choosing the format by extension: `.obj`, `.ply` (binary little
/// endian; use [`write_ply`] for ASCII), `.off`, `.stl` (binary; use [`write_stl`] for
/// ASCII), or one of them gzip-compressed (`.obj.gz` and so on, see [`gz`]).
pub fn write(path: impl AsRef<Path>, mesh: &Mesh) -> Result<()> {
    let path = path.as_ref();
    match extension(path).as_deref() {
        Some("obj") => write_obj(path, mesh),
        Some("ply") => write_ply(path, mesh, PlyFormat::BinaryLittleEndian),
        Some("off") => write_off(path, mesh),
        Some("stl") => write_stl(path, mesh, StlFormat::Binary),
        Some("gz") => write_gz(path, mesh),
        _ => Err(Error::UnknownFormat(path.to_owned())),
    }
}

/// The number each vertex gets in a written file, indexed by
/// [`Mesh::vertex_index`](crate::Mesh::vertex_index) (0-based; `u32::MAX` for slots of
/// removed vertices): live vertices are numbered in [`Mesh::vertices`] order.
pub fn file_vertex_indices(mesh: &Mesh) -> Vec<u32> {
    let mut index = vec![u32::MAX; mesh.vertex_slots()];
    for (k, v) in mesh.vertices().enumerate() {
        index[mesh.vertex_index(v)] = k as u32;
    }
    index
}

pub(crate) fn extension(path: &Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
}

pub(crate) fn read_bytes(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).map_err(|source| Error::Io {
        path: path.to_owned(),
        source,
    })
}

/// Creates `path` and runs `write` on a buffered writer into it; I/O errors name the file.
pub(crate) fn write_file(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<std::fs::File>) -> Result<()>,
) -> Result<()> {
    let file = std::fs::File::create(path).map_err(|source| Error::Io {
        path: path.to_owned(),
        source,
    })?;
    let mut out = BufWriter::with_capacity(1 << 20, file);
    write(&mut out).map_err(|e| match e {
        Error::Io { source, .. } => Error::Io {
            path: path.to_owned(),
            source,
        },
        other => other,
    })?;
    out.flush().map_err(|source| Error::Io {
        path: path.to_owned(),
        source,
    })
}
