//! # edit
//!
//! Editing methods on the `halfedge` kernel, one module per method:
//!
//! - [`area`] and [`mba`]: Lee 1999, *Interactive multiresolution editing of arbitrary
//!   meshes*: an editing area embedded onto a rectangle by a harmonic map, edits spread by
//!   multilevel B-spline approximation with a continuous scale parameter.
//! - [`regions`], [`distance`], [`shape`], [`matrix`], [`blend`]: Bendels & Klein,
//!   *Image and 3D-object editing with precisely specified editing regions*: handle, fixed
//!   and deformable regions, distance fields, shape functions and affine blending
//!   `exp(α log A)` (Alexa 2002); the same edit on curves ([`polyline`]) and pictures
//!   ([`image_edit`]).
//! - [`submesh`], [`barr`], [`smoothing`]: *Interactive editing of multiresolution
//!   meshes* (sub-mesh edits with propagation levels), Barr's taper / twist / bend, Taubin
//!   λ|μ smoothing; [`selection`]: the vertex sets they act on and exact undo snapshots.
//! - [`ffd`]: Feng, Ma & Peng, *A new free-form deformation through the control of
//!   parametric surfaces* (shape surface + height surface).
//!
//! Start with the [`guide`]: one page per method with its paper, parameters, errors and
//! a runnable example, and the simplify → edit → refine [workflow](guide::workflow).

mod error;
pub mod guide;
pub mod laplace;
pub mod selection;

pub mod area;
pub mod mba;

pub mod blend;
pub mod distance;
pub mod image_edit;
pub mod marks;
pub mod matrix;
pub mod polyline;
pub mod regions;
pub mod shape;

pub mod barr;
pub mod ffd;
pub mod smoothing;
pub mod submesh;

pub use error::{EditError, Result};
