//! Bendels & Klein, *Image and 3D-object editing with precisely specified editing
//! regions*: a handle moved by an affine map, a fixed area that never moves, and a
//! deformable area between them that follows smoothly, on meshes, polylines and pictures.
//!
//! - **Regions** (Sec. 2): [`Regions`] of a mesh (handle, fixed, deformable, with their
//!   borders), from vertex sets, roles, edge loops or picked vertices. They keep the
//!   binding of their mesh.
//! - **Distances** (Sec. 4): Euclidean to the border polylines ([`BorderGrid`], a uniform
//!   grid) or geodesic on the surface ([`FastMarching`], Kimmel & Sethian 1998), and
//!   [`geodesic_ball`] to select vertices around seeds.
//! - **Shape functions** (Sec. 5): `α = f(d_fixed / (d_fixed + d_handle))`
//!   ([`blend_ratio`]) with [`ShapeFunction`] presets or a user-edited [`ShapeCurve`].
//! - **Affine blend** (Sec. 3, after Alexa 2002): every deformable vertex moves by
//!   `α ⊙ A = exp(α log A)` ([`affine_power`]); one core, shared by the three sessions
//!   below, keeps the roles, distances, weights, shape function and transform and computes
//!   the blended points.
//! - **Sessions**: [`BlendSession`] on a mesh, with adaptive refinement (Sec. 6) and
//!   [`HierarchyEdit`](crate::HierarchyEdit) marks for a coarse level;
//!   [`polyline::PolylineSession`] on a curve (Figs. 1–3);
//!   [`image::ImageSession`] on a picture through a grid mesh (Sec. 7, Fig. 6).
//!
//! Everything the family can refuse is a [`BendelsKleinError`]; where it happened is a
//! [`Site`] (a vertex, a point of a polyline, a pixel).

pub mod affine_power;
mod blend;
mod distance;
pub(crate) mod error;
pub mod image;
mod mesh;
pub mod polyline;
mod regions;
mod shape;

pub use blend::{blend_ratio, BlendPoint, RefineOptions, RefineReport, MAX_NEW_VERTICES};
pub use distance::ball::geodesic_ball;
pub use distance::euclidean::{point_segment_distance, BorderGrid, QueryPoints, MAX_TRACED_PIECES};
pub use distance::geodesic::{sphere_distance, FastMarching, FastMarchingUpdate, MarchSource};
pub use error::{
    BendelsKleinError, ControlPointProblem, NoLogReason, RegionKind, Site, TransformOverflow,
};
pub use mesh::{virtual_origin_distance, BlendOptions, BlendSession, DistanceKind};
pub use regions::{Border, Regions, Role};
pub use shape::{CurveOptions, ShapeCurve, ShapeFunction};
