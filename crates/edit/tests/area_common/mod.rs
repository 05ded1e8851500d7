//! Shared helpers of the area-editing integration tests.
#![allow(dead_code)]

use std::path::PathBuf;

use glam::DVec3;
use halfedge::{Mesh, VertexId};

/// The shared test meshes: `$MULTIRES_MESHES`, or the first ancestor of this crate that
/// holds `shared/meshes`. Only the real-mesh tier (`#[ignore]`d tests) reads them.
pub fn meshes_dir() -> PathBuf {
    if let Ok(dir) = std::env::var("MULTIRES_MESHES") {
        return PathBuf::from(dir);
    }
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .map(|a| a.join("shared/meshes"))
        .find(|d| d.is_dir())
        .expect(
            "the real-mesh tier needs the shared test meshes: a `shared/meshes` folder above \
             the workspace, or MULTIRES_MESHES=DIR",
        )
}

/// Loads a shared mesh by file name (real-mesh tier).
pub fn load(name: &str) -> Mesh {
    halfedge::io::read(meshes_dir().join(name))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .0
}

/// Loads a mesh of the workspace's `data/` folder.
pub fn data(name: &str) -> Mesh {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../data")
        .join(name);
    halfedge::io::read(&path)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .0
}

/// The default tier's stand-in for a shared mesh: `spot` (closed, a snout along +z) →
/// `data/creature.obj` (a snout as pointed as Spot's, and separate eyes); `cow` →
/// `data/torus.obj` (just another mesh); `stanford-bunny` (holes) → `data/cup.obj`.
pub fn stand_in(name: &str) -> Mesh {
    data(match name {
        "spot.obj" => "creature.obj",
        "cow.obj" => "torus.obj",
        "stanford-bunny.obj" => "cup.obj",
        other => panic!("no stand-in for {other}"),
    })
}

/// The snout tip: the vertex with the largest z (Spot and the creature look along +z;
/// on Spot it is vertex 1855).
pub fn nose(mesh: &Mesh) -> VertexId {
    mesh.extreme_vertex(DVec3::Z).unwrap().unwrap()
}

/// Vertex `i` of the file.
pub fn vertex(mesh: &Mesh, i: usize) -> VertexId {
    mesh.vertex_at(i).unwrap()
}
