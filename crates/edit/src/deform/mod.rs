//! Sub-mesh edits and deformers.
//!
//! - **Sub-mesh edits** (*Interactive editing of multiresolution meshes* §4): a [`SubMesh`]
//!   (a vertex set with its frontier) is pulled, scaled, rotated, tapered or twisted
//!   ([`SubmeshEdit`]), the edit fading over `n` propagation levels ([`Propagation`]);
//!   [`SubMesh::apply_with_marks`] keeps what the edit means for a hierarchy
//!   ([`AppliedSubmeshEdit`], a [`HierarchyEdit`](crate::HierarchyEdit)).
//! - **Barr's deformations** (Barr 1984, *Global and local deformations of solid
//!   primitives*): [`Taper`], [`Twist`] and [`Bend`] along an axis ([`Profile`]), applied
//!   by [`apply_deformer`].
//! - **Taubin smoothing** (Taubin 1995, *A signal processing approach to fair surface
//!   design*): [`Smoother`] and [`taubin`], on a sub-mesh and its collar or the whole mesh.
//! - **Shape/height-surface FFD** (Feng, Ma & Peng, *A new free-form deformation through
//!   the control of parametric surfaces*): [`Ffd`] attached to a mesh, driven by two
//!   [`BSplineSurface`]s placed in a [`LatticeFrame`].
//!
//! The deformers act on [`Vertices`](crate::Vertices) of a mesh and every edit can be
//! undone exactly with a [`Snapshot`](crate::Snapshot). Everything the family can refuse
//! is a [`DeformError`].

mod barr;
mod checks;
pub(crate) mod error;
mod ffd;
mod smoothing;
mod submesh;

pub use barr::{apply_deformer, Bend, Deformer, Profile, Taper, Twist};
pub use error::{DeformError, SurfaceProblem};
pub use ffd::{AttachOptions, BSplineSurface, Ffd, FfdReach, LatticeFrame, MAX_ATTACH_ITERATIONS};
pub use smoothing::{taubin, Smoother, SmoothingWeights, TaubinOptions};
pub use submesh::{
    AppliedSubmeshEdit, Axis, Falloff, Plane, Propagation, SubMesh, SubmeshEdit, Variation,
};
