//! Handle, fixed and deformable parts of a polyline (Bendels & Klein, Sec. 2, Figs. 1
//! top and 2), by index spans or by picking.

use super::curve::{n_segments, segment, CurvePoint, Polyline};
use super::{closedness, CurveError, CurveResult};
use crate::bendels_klein::regions::{RegionKind, Role};

/// A run of consecutive points, `first..=last`. On a closed polygon a span with
/// `first > last` wraps around: `first..n` then `0..=last`.
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
    /// [`CurveError::NonFinitePoint`] for a non-finite pick (index 0 or 1).
    pub fn between<P: CurvePoint>(curve: &Polyline<P>, from: P, to: P) -> CurveResult<Self> {
        let a = curve.nearest(from)?;
        let b = curve
            .nearest(to)
            .map_err(|_| CurveError::NonFinitePoint { index: 1 })?;
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
    ) -> CurveResult<()> {
        if self.first >= n || self.last >= n {
            return Err(CurveError::OutOfRange {
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
            return Err(CurveError::SpanWrapsOpen {
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
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CurveRegions {
    roles: Vec<Role>,
    closed: bool,
}

impl CurveRegions {
    /// Regions from index spans: the handle is the union of `handle`, the fixed part
    /// the union of `fixed`, every other point deformable (the paper's Fig. 2: handle
    /// `4..=8`, fixed `0..=2` and `10..=13`).
    ///
    /// # Errors
    /// [`CurveError::OutOfRange`], [`CurveError::SpanWrapsOpen`] for a bad span,
    /// [`CurveError::Overlap`] for a point in both, and as [`CurveRegions::from_roles`].
    pub fn from_spans<P: CurvePoint>(
        curve: &Polyline<P>,
        handle: &[Span],
        fixed: &[Span],
    ) -> CurveResult<Self> {
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
            return Err(CurveError::Overlap { index });
        }
        Self::from_roles(curve, roles)
    }

    /// Regions from a role per point.
    ///
    /// # Errors
    /// [`CurveError::Mismatch`] for a role count other than the number of points,
    /// [`CurveError::EmptyRegion`] without handle or fixed point,
    /// [`CurveError::HandleTouchesFixed`] for a segment from a handle to a fixed point.
    pub fn from_roles<P: CurvePoint>(curve: &Polyline<P>, roles: Vec<Role>) -> CurveResult<Self> {
        let (n, closed) = (curve.len(), curve.is_closed());
        if roles.len() != n {
            return Err(CurveError::Mismatch {
                regions: roles.len(),
                regions_closed: closedness(closed),
                points: n,
                points_closed: closedness(closed),
            });
        }
        for kind in [RegionKind::Handle, RegionKind::Fixed] {
            let role = if kind == RegionKind::Handle {
                Role::Handle
            } else {
                Role::Fixed
            };
            if !roles.contains(&role) {
                return Err(CurveError::EmptyRegion(kind));
            }
        }
        for k in 0..n_segments(n, closed) {
            let (a, b) = segment(k, n);
            match (roles[a], roles[b]) {
                (Role::Handle, Role::Fixed) => {
                    return Err(CurveError::HandleTouchesFixed {
                        handle: a,
                        fixed: b,
                    })
                }
                (Role::Fixed, Role::Handle) => {
                    return Err(CurveError::HandleTouchesFixed {
                        handle: b,
                        fixed: a,
                    })
                }
                _ => {}
            }
        }
        Ok(Self { roles, closed })
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

    pub(super) fn check<P: CurvePoint>(&self, curve: &Polyline<P>) -> CurveResult<()> {
        if self.roles.len() != curve.len() || self.closed != curve.is_closed() {
            return Err(CurveError::Mismatch {
                regions: self.roles.len(),
                regions_closed: closedness(self.closed),
                points: curve.len(),
                points_closed: closedness(curve.is_closed()),
            });
        }
        Ok(())
    }
}
