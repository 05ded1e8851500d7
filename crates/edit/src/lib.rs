//! # edit
//!
//! Editing methods on the `halfedge` kernel, one module per method family:
//!
//! - [`lee`]: Lee 1999, *Interactive multiresolution editing of arbitrary meshes*: an
//!   editing area embedded onto a rectangle by a harmonic map, edits spread by multilevel
//!   B-spline approximation ([`lee::mba`], Lee, Wolberg & Shin 1997) with a continuous
//!   scale parameter. Errors: [`lee::LeeError`].
//! - [`bendels_klein`]: Bendels & Klein, *Image and 3D-object editing with precisely
//!   specified editing regions*: handle, fixed and deformable regions, distance fields,
//!   shape functions and affine blending `exp(α log A)` (Alexa 2002), on meshes, on
//!   curves ([`bendels_klein::polyline`]) and on pictures ([`bendels_klein::image`]).
//!   Errors: [`bendels_klein::BendelsKleinError`].
//! - [`deform`]: *Interactive editing of multiresolution meshes* (sub-mesh edits with
//!   propagation levels), Barr's taper / twist / bend, Taubin λ|μ smoothing, and Feng,
//!   Ma & Peng's shape/height-surface free-form deformation. Errors:
//!   [`deform::DeformError`].
//!
//! Shared by the families: [`Vertices`] (the vertex sets the deformers act on) and
//! [`Snapshot`] (exact undo), [`laplace`] (cotangent weights), and [`HierarchyEdit`]:
//! the one trait of an edit made at a coarse level of a hierarchy that tells the
//! hierarchy what it did ([`HierarchyMarks`]), so that refinement brings it back at full
//! resolution. [`Error`] gathers the three family errors for programs that handle any of
//! them.
//!
//! Start with the guides (`multires::guide` in the `multires` crate, `docs/guide/*.md` in
//! the repository): one page per method with its paper, parameters, errors and a runnable
//! example, and the simplify → edit → refine workflow.

mod error;
pub mod laplace;

mod hierarchy_edit;
mod vertices;

pub mod bendels_klein;
pub mod deform;
pub mod lee;

pub use error::{Error, Result};
pub use hierarchy_edit::{HierarchyEdit, HierarchyMarks};
pub use vertices::{Snapshot, Vertices};
