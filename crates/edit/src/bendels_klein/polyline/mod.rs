//! Bendels & Klein on polylines and polygons (*Image and 3D-object editing with
//! precisely specified editing regions*, Sec. 2, Figs. 1 top, 2 and 3): the same
//! handle / fixed / deformable parts, distance ratio, shape function and affine blend
//! `exp(α log A)` as on meshes ([`crate::blend`]), on a curve.
//!
//! - [`Polyline`]: an open polyline or a closed polygon of 2-D ([`glam::DVec2`]) or 3-D
//!   ([`glam::DVec3`]) points ([`CurvePoint`]); [`Polyline::nearest`] picks a point.
//! - [`CurveRegions`]: the role of every point, from index [`Span`]s (a closed polygon's
//!   span may wrap around index 0) or from picked positions ([`Span::between`]). The
//!   handle and the fixed part must not overlap nor be neighbours (Sec. 2, footnote 1).
//! - [`PolylineSession`]: distances, weights and the edit. Distances along the curve
//!   ([`CurveDistance::ArcLength`], the geodesic distance of a curve: α grows
//!   monotonically from the fixed part to the handle, Fig. 3 b) or Euclidean distances
//!   to the handle and fixed parts (eq. 1–2, through [`crate::bendels_klein::distance::BorderGrid`];
//!   α need not be monotone along the curve, Fig. 3 a). Each deformable point moves by
//!   `α ⊙ A` with `α = f(d_fixed / (d_fixed + d_handle))` ([`crate::shape`]), computed
//!   by [`crate::bendels_klein::affine_power::AffinePower`] (`log A` once per edit). In 2-D `A` is a 3×3
//!   homogeneous matrix, in 3-D a 4×4 one. The fixed part is never written (bit for
//!   bit), the handle is `A p` exactly.
//! - [`PolylineSession::refine`]: Sec. 6 on a curve: where the edit stretched a
//!   segment of the deformable part beyond a length, the original midpoint is inserted
//!   and placed by the blend, until no segment is longer.

mod curve;
mod regions;
mod session;

pub use curve::{CurvePoint, Polyline};
pub use regions::{CurveRegions, Span};
pub use session::{CurveDistance, PolylineOptions, PolylineSession};

use crate::bendels_klein::regions::RegionKind;
use crate::EditError;

/// What can go wrong with a polyline edit (module [`crate::polyline`]).
#[derive(Debug, thiserror::Error)]
pub enum CurveError {
    /// The polyline has no point.
    #[error("the polyline has no point")]
    Empty,
    /// A closed polygon needs at least three points.
    #[error("a closed polygon needs at least 3 points, got {0}")]
    TooFewPoints(usize),
    /// A point (or a picked position) is NaN or infinite.
    #[error("point {index} is not finite")]
    NonFinitePoint {
        /// Its index (for a pick: the position of the pick in its list).
        index: usize,
    },
    /// A span names a point the polyline does not have.
    #[error("{region} span {first}..={last} is out of range: the polyline has {len} points")]
    OutOfRange {
        /// Whose span.
        region: RegionKind,
        /// First index of the span.
        first: usize,
        /// Last index of the span.
        last: usize,
        /// Number of points.
        len: usize,
    },
    /// A span runs backwards (`first > last`) on an open polyline, where it cannot wrap
    /// around.
    #[error("{region} span {first}..={last} runs backwards, but the polyline is open")]
    SpanWrapsOpen {
        /// Whose span.
        region: RegionKind,
        /// First index of the span.
        first: usize,
        /// Last index of the span.
        last: usize,
    },
    /// A point is both in the handle and in the fixed part.
    #[error("point {index} is in both the handle and the fixed part")]
    Overlap {
        /// The point.
        index: usize,
    },
    /// A handle point and a fixed point are joined by a segment: no deformable point lies
    /// between them (Sec. 2, footnote 1: the handle lies in the complement of the fixed
    /// area).
    #[error("handle point {handle} and fixed point {fixed} are neighbours on the polyline")]
    HandleTouchesFixed {
        /// The handle point.
        handle: usize,
        /// The fixed point.
        fixed: usize,
    },
    /// The handle or the fixed part has no point.
    #[error("the {0} part is empty")]
    EmptyRegion(RegionKind),
    /// Regions or roles made for another polyline (other length or closedness).
    #[error("regions for {regions} points ({regions_closed}), the polyline has {points} ({points_closed})")]
    Mismatch {
        /// Points the regions cover.
        regions: usize,
        /// "closed" or "open".
        regions_closed: &'static str,
        /// Points of the polyline.
        points: usize,
        /// "closed" or "open".
        points_closed: &'static str,
    },
    /// An error of the shared machinery: the transform (no real logarithm, not affine,
    /// not finite), a shape curve, a refinement parameter.
    #[error(transparent)]
    Edit(#[from] EditError),
}

/// `Result` with a [`CurveError`].
pub type CurveResult<T> = std::result::Result<T, CurveError>;

fn closedness(closed: bool) -> &'static str {
    if closed {
        "closed"
    } else {
        "open"
    }
}

#[cfg(test)]
mod tests;
