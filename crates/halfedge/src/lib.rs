//! # halfedge
//!
//! A half-edge kernel for triangle meshes on `slotmap` handles, the foundation of the
//! `multires` workspace (multiresolution editing after Kobbelt-style hierarchies, Lee
//! 1999, Bendels & Klein 2003 and Feng, Ma & Peng).
//!
//! - [`Mesh`]: connectivity, positions ([`glam::DVec3`]), typed [attributes](attributes),
//!   navigation and [circulators](iter) with pmp / OpenMesh names, [`Mesh::check`].
//! - [Building](build) from indexed polygons with OpenMesh's importer policy, and
//!   [`io`] for OBJ (`tobj`) and PLY (`ply-rs-bw`).
//! - [`generators`]: grid, icosphere, 1-to-4 subdivision.
//!
//! ```
//! use halfedge::generators;
//! let mesh = generators::icosphere(2);
//! mesh.check().unwrap();
//! assert_eq!((mesh.n_vertices(), mesh.n_faces()), (162, 320));
//! let v = mesh.vertices().next().unwrap();
//! assert_eq!(mesh.adjacent_vertices(v).count(), mesh.valence(v));
//! ```

mod add_face;
pub mod attributes;
pub mod build;
mod check;
mod compact_build;
mod error;
pub mod generators;
mod geometry;
mod handle;
pub mod io;
pub mod iter;
mod mesh;
mod paths;
mod topology;

pub use attributes::{Attribute, AttributeValue, Element};
pub use build::{AddFaceError, BuildReport};
pub use error::{Error, Invariant, Result};
pub use handle::{FaceId, HalfedgeId, VertexId};
pub use mesh::Mesh;
pub use topology::TopologyReport;

pub use glam::DVec3;

/// Placeholder until collapse lands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CollapseVeto {
    /// The edge was removed.
    EdgeDeleted,
}
impl std::fmt::Display for CollapseVeto {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{self:?}")
    }
}
