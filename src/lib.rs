//! # multires
//!
//! Multiresolution editing of triangle meshes: the facade of the workspace, re-exporting
//! the [`halfedge`] kernel and the [`edit`] methods.
//!
//! Start with the guides in [`guide`]: one per method (its paper, parameters,
//! errors and a runnable example) and the simplify → edit → refine
//! [workflow](guide::workflow).
//!
//! Besides the two crates, the facade re-exports [`glam`] (the math types of every API)
//! and, with the `render` feature (default), offers [`render`]: PNG pictures of meshes
//! side by side from a software renderer.

#[cfg(feature = "render")]
pub mod batch;
mod cut;
pub mod error;
pub mod guide;
pub mod load;
pub mod memory;
pub mod progress;
pub mod recipe;
#[cfg(feature = "render")]
pub mod workflow;

pub use edit;
pub use error::{Error, Result};
/// The vector and matrix types of every API here (`DVec3` positions, `DMat4` affine
/// transforms for Bendels & Klein), re-exported so that users need not match the version.
pub use glam;
pub use halfedge;

#[cfg(feature = "render")]
pub mod render;

/// The items most programs need: the kernel's mesh, handles and hierarchy, and the
/// editing methods of the three families (Lee 1999 area editing, Bendels & Klein regions,
/// the deformers) with the trait that marks a hierarchy after a coarse edit.
pub mod prelude {
    pub use glam::{self, DMat3, DMat4, DQuat, DVec2, DVec3};
    pub use halfedge::bvh::{Bvh, Ray};
    pub use halfedge::hierarchy::{Hierarchy, HierarchyOptions};
    pub use halfedge::selection::Selection;
    pub use halfedge::{FaceId, HalfedgeId, Mesh, VertexData, VertexId};

    pub use edit::bendels_klein::{
        BendelsKleinError, BlendOptions, BlendSession, DistanceKind, RefineOptions, Regions, Role,
        ShapeFunction,
    };
    pub use edit::deform::{
        apply_deformer, taubin, AttachOptions, Axis, Bend, DeformError, Ffd, LatticeFrame,
        Propagation, SubMesh, SubmeshEdit, Taper, TaubinOptions, Twist, Variation,
    };
    pub use edit::lee::{AreaSession, EditingArea, LeeError, SessionOptions};
    pub use edit::{HierarchyEdit, Snapshot, Vertices};
}

/// The README's code, compiled and run as a doctest so that the tour stays true.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
