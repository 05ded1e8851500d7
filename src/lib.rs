//! # multires
//!
//! Multiresolution editing of triangle meshes: the facade of the workspace, re-exporting
//! the [`halfedge`] kernel and the [`edit`] methods.
//!
//! Start with the guides in [`edit::guide`]: one per method (its paper, parameters,
//! errors and a runnable example) and the simplify → edit → refine
//! [workflow](edit::guide::workflow).

pub use edit;
pub use halfedge;

/// The items most programs need.
pub mod prelude {
    pub use glam::DVec3;
    pub use halfedge::{FaceId, HalfedgeId, Mesh, VertexId};
}

/// The README's code, compiled and run as a doctest so that the tour stays true.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
