//! # multires
//!
//! Multiresolution editing of triangle meshes: the facade of the workspace, re-exporting
//! the [`halfedge`] kernel and the [`edit`] methods.
//!
//! Start with the guides in [`edit::guide`]: one per method (its paper, parameters,
//! errors and a runnable example) and the simplify → edit → refine
//! [workflow](edit::guide::workflow).
//!
//! Besides the two crates, the facade re-exports [`glam`] (the math types of every API)
//! and, with the `render` feature (default), offers [`render`]: PNG pictures of meshes
//! side by side from a software renderer.

pub use edit;
/// The vector and matrix types of every API here (`DVec3` positions, `DMat4` affine
/// transforms for Bendels & Klein), re-exported so that users need not match the version.
pub use glam;
pub use halfedge;

#[cfg(feature = "render")]
pub mod render;

/// The items most programs need.
pub mod prelude {
    pub use glam::{self, DMat3, DMat4, DQuat, DVec2, DVec3};
    pub use halfedge::bvh::{Bvh, Ray};
    pub use halfedge::{
        FaceId, HalfedgeId, Hierarchy, HierarchyOptions, Mesh, Selection, VertexId,
    };
}

/// The README's code, compiled and run as a doctest so that the tour stays true.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
