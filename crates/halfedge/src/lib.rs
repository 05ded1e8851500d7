//! # halfedge
//!
//! A half-edge kernel for triangle meshes on `slotmap` handles, the foundation of the
//! `multires` workspace (multiresolution editing after Kobbelt-style hierarchies, Lee
//! 1999, Bendels & Klein 2003 and Feng, Ma & Peng).
//!
//! - [`Mesh`]: connectivity, positions ([`glam::DVec3`]), typed [`Attribute`]s,
//!   navigation and [circulators](iter) with pmp / OpenMesh names, [`Mesh::check`].
//! - Building from indexed polygons with OpenMesh's importer policy
//!   ([`Mesh::from_polygons`], [`BuildReport`]), and [`io`] for OBJ, PLY, OFF and STL
//!   (gzip-compressed too).
//! - [`generators`]: grid, icosphere, torus, 1-to-4 subdivision.
//! - Collapse and vertex split ([`Mesh::collapse`], [`CollapseRecord`]), the progressive
//!   [`hierarchy::Hierarchy`] with local-frame detail coefficients (rounds or QEM), and
//!   sub-mesh [`labels`] that hold across its levels.
//! - [`selection`] (nearest and extreme vertices, Euclidean and edge-path balls,
//!   components, grow / shrink / select linked) and [`bvh`] (picking along a ray, the
//!   nearest point of the surface).
//! - [`surface_distance`]: how far apart two surfaces are (mean, root mean square and
//!   Hausdorff distances over sample points, as Metro measures a simplification).
//! - Plain arrays in and out: [`Mesh::from_arrays`] / [`Mesh::to_arrays`]; welding
//!   vertices at the same place (triangle soups, seams) with [`Mesh::welded`]
//!   ([`WeldReport`]).
//! - One way to know data fits its mesh: [`Binding`], checked on every use, refusing with
//!   [`Stale`].
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
mod arrays;
mod attribute_store;
mod attributes;
mod binding;
mod build;
pub mod bvh;
mod check;
mod collapse;
mod compact_build;
mod error;
pub mod generators;
mod geometry;
mod handle;
pub mod hierarchy;
#[cfg(test)]
mod hostile_tests;
pub mod io;
pub mod iter;
pub mod labels;
mod mesh;
mod paths;
mod prefetch;
pub mod selection;
mod split;
pub mod surface_distance;
mod topology;
mod vertex_data;
mod weld;

pub use attributes::{Attribute, AttributeValue, Element};
pub use binding::{Binding, Bound, Provenance, Stale};
pub use build::{AddFaceError, BuildReport};
pub use collapse::{CollapseRecord, CollapseVeto};
pub use error::{Error, Invariant, Result};
pub use handle::{FaceId, HalfedgeId, VertexId};
pub use mesh::Mesh;
pub use topology::TopologyReport;
pub use vertex_data::VertexData;
pub use weld::WeldReport;

/// The crate README's code, compiled and run as a doctest so that it stays true.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
