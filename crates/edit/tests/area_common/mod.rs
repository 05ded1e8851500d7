//! Shared helpers of the area-editing integration tests.
#![allow(dead_code)]

use std::path::PathBuf;

use halfedge::{Mesh, VertexId};

/// The shared test meshes: `$MULTIRES_MESHES`, or the first ancestor of this crate that
/// holds `shared/meshes`.
pub fn meshes_dir() -> PathBuf {
    if let Ok(dir) = std::env::var("MULTIRES_MESHES") {
        return PathBuf::from(dir);
    }
    let mut dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    loop {
        let candidate = dir.join("shared/meshes");
        if candidate.is_dir() {
            return candidate;
        }
        assert!(
            dir.pop(),
            "no shared/meshes above {}",
            env!("CARGO_MANIFEST_DIR")
        );
    }
}

/// Loads a shared mesh by file name.
pub fn load(name: &str) -> Mesh {
    halfedge::io::read(meshes_dir().join(name))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .0
}

/// Spot's snout tip (the vertex with the largest z; Spot looks along +z).
pub const SPOT_NOSE: usize = 1855;

/// Vertex `i` of the file.
pub fn vertex(mesh: &Mesh, i: usize) -> VertexId {
    mesh.vertex_at(i).unwrap()
}
