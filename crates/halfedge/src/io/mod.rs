//! Mesh files: OBJ (read with `tobj`) and PLY (read and written with `ply-rs-bw`).
//!
//! Reading keeps every vertex of the file in file order (vertex `i` of the file has
//! [`Mesh::vertex_index`](crate::Mesh::vertex_index) `i`, unreferenced vertices become
//! isolated vertices) and builds faces with the policy of [`crate::build`].

mod obj;

use std::path::Path;

use crate::{BuildReport, Error, Mesh, Result};

pub use obj::{read_obj, read_obj_from_bytes};

/// Reads a mesh file, choosing the format by extension (`.obj`, `.ply`).
pub fn read(path: impl AsRef<Path>) -> Result<(Mesh, BuildReport)> {
    let path = path.as_ref();
    match extension(path).as_deref() {
        Some("obj") => read_obj(path),
        _ => Err(Error::UnknownFormat(path.to_owned())),
    }
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
