//! Bendels & Klein on polylines and polygons (*Image and 3D-object editing with
//! precisely specified editing regions*, Sec. 2, Figs. 1 top, 2 and 3): the same
//! handle / fixed / deformable parts, distance ratio, shape function and affine blend
//! `exp(α log A)` as on meshes ([`BlendSession`](super::BlendSession)), on a curve.
//!
//! - [`Polyline`]: an open polyline or a closed polygon of 2-D ([`glam::DVec2`]) or 3-D
//!   ([`glam::DVec3`]) points ([`BlendPoint`](super::BlendPoint));
//!   [`Polyline::nearest`] picks a point. A polyline keeps a
//!   [`Provenance`](halfedge::Provenance), as a mesh does.
//! - [`CurveRegions`]: the role of every point, from index [`Span`]s (a closed polygon's
//!   span may wrap around index 0) or from picked positions ([`Span::between`]). The
//!   handle and the fixed part must not overlap nor be neighbours (Sec. 2, footnote 1).
//!   Regions keep the [`Binding`](halfedge::Binding) of the polyline they were made for:
//!   a session refuses them on any other polyline (even one of the same length) with
//!   [`BendelsKleinError::Stale`](super::BendelsKleinError::Stale).
//! - [`PolylineSession`]: distances, weights and the edit. Distances along the curve
//!   ([`CurveDistance::ArcLength`], the geodesic distance of a curve: α grows
//!   monotonically from the fixed part to the handle, Fig. 3 b) or Euclidean distances
//!   to the handle and fixed parts (eq. 1–2, through
//!   [`BorderGrid`](super::BorderGrid); α need not be monotone along the curve, Fig. 3
//!   a). Each deformable point moves by `α ⊙ A` with `α = f(d_fixed / (d_fixed +
//!   d_handle))` ([`ShapeFunction`](super::ShapeFunction)), computed by
//!   [`AffinePower`](super::affine_power::AffinePower) (`log A` once per edit). In 2-D
//!   `A` is a 3×3 homogeneous matrix, in 3-D a 4×4 one. The fixed part is never written
//!   (bit for bit), the handle is `A p` exactly.
//! - [`PolylineSession::refine`]: Sec. 6 on a curve: where the edit stretched a
//!   segment of the deformable part beyond a length, the original midpoint is inserted
//!   and placed by the blend, until no segment is longer.

mod curve;
mod regions;
mod session;

pub use curve::Polyline;
pub use regions::{CurveRegions, Span};
pub use session::{CurveDistance, PolylineOptions, PolylineSession};

#[cfg(test)]
mod tests;
