//! Helpers shared by the kernel's integration tests.
#![allow(dead_code, missing_docs)]

use std::path::PathBuf;

use halfedge::{FaceId, HalfedgeId, Mesh, VertexId};

/// `shared/meshes` next to the repository (or `MULTIRES_MESHES`).
pub fn meshes_dir() -> PathBuf {
    if let Ok(dir) = std::env::var("MULTIRES_MESHES") {
        return PathBuf::from(dir);
    }
    let here = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    here.ancestors()
        .map(|a| a.join("shared/meshes"))
        .find(|p| p.is_dir())
        .expect("shared/meshes not found above the crate; set MULTIRES_MESHES")
}

/// Loads a shared mesh by file name.
pub fn load(name: &str) -> Mesh {
    halfedge::io::read(meshes_dir().join(name))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .0
}

/// Complete connectivity + positions snapshot, handle for handle.
#[derive(Debug, PartialEq, Clone)]
pub struct Snapshot {
    counts: (usize, usize, usize),
    vertices: Vec<(VertexId, Option<HalfedgeId>, [u64; 3])>,
    halfedges: Vec<(
        HalfedgeId,
        VertexId,
        HalfedgeId,
        HalfedgeId,
        HalfedgeId,
        Option<FaceId>,
    )>,
    faces: Vec<(FaceId, HalfedgeId)>,
}

/// Snapshot of everything `collapse` / `vertex_split` touch.
pub fn snapshot(mesh: &Mesh) -> Snapshot {
    Snapshot {
        counts: (mesh.n_vertices(), mesh.n_halfedges(), mesh.n_faces()),
        vertices: mesh
            .vertices()
            .map(|v| {
                (
                    v,
                    mesh.vertex_halfedge(v),
                    mesh.position(v).to_array().map(f64::to_bits),
                )
            })
            .collect(),
        halfedges: mesh
            .halfedges()
            .map(|h| {
                (
                    h,
                    mesh.to_vertex(h),
                    mesh.next(h),
                    mesh.prev(h),
                    mesh.opposite(h),
                    mesh.face(h),
                )
            })
            .collect(),
        faces: mesh.faces().map(|f| (f, mesh.face_halfedge(f))).collect(),
    }
}

/// `V − E + F`.
pub fn euler(mesh: &Mesh) -> i64 {
    mesh.n_vertices() as i64 - mesh.n_edges() as i64 + mesh.n_faces() as i64
}
