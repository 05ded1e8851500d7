//! # multires
//!
//! Multiresolution editing of triangle meshes: the facade of the workspace, re-exporting
//! the [`halfedge`] kernel and the [`edit`] methods.

pub use edit;
pub use halfedge;

/// The items most programs need.
pub mod prelude {
    pub use glam::DVec3;
    pub use halfedge::{FaceId, HalfedgeId, Mesh, VertexId};
}
