//! Helpers shared by the workspace's integration tests that talk to OpenMesh.
#![allow(dead_code, missing_docs)]

use std::path::{Path, PathBuf};

/// The report keys OpenMesh and this kernel both compute.
pub const KEYS: [&str; 9] = [
    "vertices",
    "edges",
    "faces",
    "halfedges",
    "boundary_vertices",
    "boundary_loops",
    "components",
    "euler",
    "valence_histogram",
];

/// The workspace root.
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// `../shared/meshes` (the first ancestor of the workspace that has `shared/meshes`), or
/// `$MULTIRES_MESHES`.
pub fn shared_meshes() -> PathBuf {
    if let Some(dir) = std::env::var_os("MULTIRES_MESHES") {
        return PathBuf::from(dir);
    }
    root()
        .ancestors()
        .map(|a| a.join("shared/meshes"))
        .find(|d| d.is_dir())
        .expect("no shared/meshes directory above the workspace (set MULTIRES_MESHES)")
}
