//! Handle, fixed and deformable parts of a polyline (Bendels & Klein, Sec. 2, Figs. 1
//! top and 2), by index spans or by picking.

use halfedge::Binding;

use crate::bendels_klein::blend::BlendPoint;
use crate::bendels_klein::error::{BendelsKleinError, RegionKind, Result, Site};
use crate::bendels_klein::polyline::curve::{n_segments, segment, Polyline};
use crate::bendels_klein::regions::Role;

/// A run of consecutive points, `first..=last`. On a closed polygon a span with
/// `first > last` wraps around: `first..n` then `0..=last`.
///
/// Paper: Bendels & Klein 2003, *Image and 3D-object editing with precisely specified
/// editing regions*, Sec. 2 and Fig. 2.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Span {
    /// The first point.
    pub first: usize,
    /// The last point (inclusive).
    pub last: usize,
}

impl Span {
    /// The span `first..=last`.
    #[must_use]
    pub fn new(first: usize, last: usize) -> Self {
        Self { first, last }
    }

    /// A single point.
    #[must_use]
    pub fn single(index: usize) -> Self {
        Self {
            first: index,
            last: index,
        }
    }

    /// The span between the points nearest to two picked positions (the paper's
    /// picking with a cursor): on an open polyline from the lower to the higher index,
    /// on a closed polygon from the first pick forward to the second (possibly wrapping
    /// around index 0).
    ///
    /// # Errors
    /// [`BendelsKleinError::NonFinitePoint`] for a non-finite pick (index 0 or 1).
    pub fn between<P: BlendPoint>(curve: &Polyline<P>, from: P, to: P) -> Result<Self> {
        let a = curve.nearest(from)?;
        let b = curve
            .nearest(to)
            .map_err(|_| BendelsKleinError::NonFinitePoint { index: 1 })?;
        Ok(if curve.is_closed() {
            Self::new(a, b)
        } else {
            Self::new(a.min(b), a.max(b))
        })
    }

    /// Marks the span's points with `role`, checking it against `n` points.
    fn mark(
        &self,
        region: RegionKind,
        n: usize,
        closed: bool,
        mut visit: impl FnMut(usize),
    ) -> Result<()> {
        if self.first >= n || self.last >= n {
            return Err(BendelsKleinError::OutOfRange {
                region,
                first: self.first,
                last: self.last,
                len: n,
            });
        }
        if self.first <= self.last {
            (self.first..=self.last).for_each(&mut visit);
        } else if closed {
            (self.first..n).chain(0..=self.last).for_each(&mut visit);
        } else {
            return Err(BendelsKleinError::SpanWrapsOpen {
                region,
                first: self.first,
                last: self.last,
            });
        }
        Ok(())
    }
}

/// The role of every point of a polyline: handle, fixed or deformable (Bendels & Klein,
/// Sec. 2). The handle and the fixed part are non-empty, disjoint and never neighbours.
/// The regions keep the [`Binding`] of the polyline they were made for: a
/// [`PolylineSession`](super::PolylineSession) refuses them on any other polyline (even
/// one of the same length) with [`BendelsKleinError::Stale`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CurveRegions {
    roles: Vec<Role>,
    closed: bool,
    binding: Binding,
}

impl CurveRegions {
    /// Regions from index spans: the handle is the union of `handle`, the fixed part
    /// the union of `fixed`, every other point deformable (the paper's Fig. 2: handle
    /// `4..=8`, fixed `0..=2` and `10..=13`).
    ///
    /// # Errors
    /// [`BendelsKleinError::OutOfRange`], [`BendelsKleinError::SpanWrapsOpen`] for a bad span,
    /// [`BendelsKleinError::Overlap`] for a point in both, and as [`CurveRegions::from_roles`].
    pub fn from_spans<P: BlendPoint>(
        curve: &Polyline<P>,
        handle: &[Span],
        fixed: &[Span],
    ) -> Result<Self> {
        let (n, closed) = (curve.len(), curve.is_closed());
        let mut roles = vec![Role::Deformable; n];
        for span in handle {
            span.mark(RegionKind::Handle, n, closed, |i| roles[i] = Role::Handle)?;
        }
        let mut overlap = None;
        for span in fixed {
            span.mark(RegionKind::Fixed, n, closed, |i| {
                if roles[i] == Role::Handle {
                    overlap.get_or_insert(i);
                }
                roles[i] = Role::Fixed;
            })?;
        }
        if let Some(index) = overlap {
            return Err(BendelsKleinError::Overlap {
                site: Site::Point(index),
            });
        }
        Self::from_roles(curve, roles)
    }

    /// Regions from a role per point.
    ///
    /// # Errors
    /// [`BendelsKleinError::RoleCount`] for a role count other than the number of points,
    /// [`BendelsKleinError::EmptyRegion`] without handle or fixed point,
    /// [`BendelsKleinError::HandleTouchesFixed`] for a segment from a handle to a fixed point.
    pub fn from_roles<P: BlendPoint>(curve: &Polyline<P>, roles: Vec<Role>) -> Result<Self> {
        let (n, closed) = (curve.len(), curve.is_closed());
        if roles.len() != n {
            return Err(BendelsKleinError::RoleCount {
                roles: roles.len(),
                points: n,
            });
        }
        for kind in [RegionKind::Handle, RegionKind::Fixed] {
            let role = if kind == RegionKind::Handle {
                Role::Handle
            } else {
                Role::Fixed
            };
            if !roles.contains(&role) {
                return Err(BendelsKleinError::EmptyRegion(kind));
            }
        }
        for k in 0..n_segments(n, closed) {
            let (a, b) = segment(k, n);
            match (roles[a], roles[b]) {
                (Role::Handle, Role::Fixed) => {
                    return Err(BendelsKleinError::HandleTouchesFixed {
                        handle: Site::Point(a),
                        fixed: Site::Point(b),
                    })
                }
                (Role::Fixed, Role::Handle) => {
                    return Err(BendelsKleinError::HandleTouchesFixed {
                        handle: Site::Point(b),
                        fixed: Site::Point(a),
                    })
                }
                _ => {}
            }
        }
        Ok(Self {
            roles,
            closed,
            binding: curve.binding(),
        })
    }

    /// The role of every point.
    #[must_use]
    pub fn roles(&self) -> &[Role] {
        &self.roles
    }
    /// Number of points the regions cover.
    #[must_use]
    pub fn len(&self) -> usize {
        self.roles.len()
    }
    /// Always false (the regions have a handle and a fixed point).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.roles.is_empty()
    }
    /// True when made for a closed polygon.
    #[must_use]
    pub fn is_closed(&self) -> bool {
        self.closed
    }
    /// Number of points with `role`.
    #[must_use]
    pub fn count(&self, role: Role) -> usize {
        self.roles.iter().filter(|&&r| r == role).count()
    }

    /// The polyline the regions were made for (see [`halfedge::Binding`]).
    #[must_use]
    pub fn binding(&self) -> Binding {
        self.binding
    }

    /// `Ok` when the regions were made for `curve` as it is (the same points, none
    /// inserted since).
    ///
    /// # Errors
    /// [`BendelsKleinError::Stale`] otherwise.
    pub(super) fn check<P: BlendPoint>(&self, curve: &Polyline<P>) -> Result<()> {
        self.binding.check(curve, "the curve regions")?;
        Ok(())
    }
}
