//! Points and polylines (Bendels & Klein, Sec. 2, Fig. 1 top).

use halfedge::{Binding, Bound, Provenance};

use crate::bendels_klein::blend::BlendPoint;
use crate::bendels_klein::error::{BendelsKleinError, Result};

/// An open polyline or a closed polygon (the last point joined to the first), the
/// curve of Bendels & Klein's Figs. 1 (top) and 2. Never empty; every point finite.
///
/// Like a mesh, a polyline keeps a [`Provenance`]: what is derived from it
/// ([`CurveRegions`](super::CurveRegions)) keeps its [`Binding`] and is refused on any
/// other polyline, or on this one after a point was inserted. A clone is another
/// instance. Two polylines are equal when their points and closedness are.
#[derive(Clone, Debug)]
pub struct Polyline<P> {
    points: Vec<P>,
    closed: bool,
    provenance: Provenance,
}

impl<P: PartialEq> PartialEq for Polyline<P> {
    fn eq(&self, other: &Self) -> bool {
        self.closed == other.closed && self.points == other.points
    }
}

impl<P> Bound for Polyline<P> {
    fn provenance(&self) -> &Provenance {
        &self.provenance
    }
}

impl<P: BlendPoint> Polyline<P> {
    /// A polyline through `points`, closed into a polygon when `closed`.
    ///
    /// # Errors
    /// [`BendelsKleinError::EmptyPolyline`] without points,
    /// [`BendelsKleinError::TooFewPoints`] for a closed polygon of fewer than 3,
    /// [`BendelsKleinError::NonFinitePoint`] for NaN or infinite coordinates.
    pub fn new(points: Vec<P>, closed: bool) -> Result<Self> {
        if points.is_empty() {
            return Err(BendelsKleinError::EmptyPolyline);
        }
        if closed && points.len() < 3 {
            return Err(BendelsKleinError::TooFewPoints {
                points: points.len(),
            });
        }
        if let Some(index) = points.iter().position(|p| !p.finite()) {
            return Err(BendelsKleinError::NonFinitePoint { index });
        }
        Ok(Self::from_parts(points, closed))
    }

    /// An open polyline (see [`Polyline::new`]).
    ///
    /// # Errors
    /// As [`Polyline::new`].
    pub fn open(points: Vec<P>) -> Result<Self> {
        Self::new(points, false)
    }

    /// A closed polygon (see [`Polyline::new`]).
    ///
    /// # Errors
    /// As [`Polyline::new`].
    pub fn closed(points: Vec<P>) -> Result<Self> {
        Self::new(points, true)
    }

    /// The points.
    #[must_use]
    pub fn points(&self) -> &[P] {
        &self.points
    }
    /// The points, by value.
    #[must_use]
    pub fn into_points(self) -> Vec<P> {
        self.points
    }
    /// Number of points (at least 1).
    #[must_use]
    pub fn len(&self) -> usize {
        self.points.len()
    }
    /// Always false: a polyline has a point.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }
    /// True for a closed polygon.
    #[must_use]
    pub fn is_closed(&self) -> bool {
        self.closed
    }
    /// Number of segments: `len − 1` open, `len` closed.
    #[must_use]
    pub fn n_segments(&self) -> usize {
        n_segments(self.points.len(), self.closed)
    }
    /// Total length (0 for a single point).
    #[must_use]
    pub fn length(&self) -> f64 {
        (0..self.n_segments())
            .map(|k| {
                let (a, b) = segment(k, self.points.len());
                self.points[a]
                    .to_space()
                    .distance(self.points[b].to_space())
            })
            .sum()
    }

    /// The index of the point nearest to `q` (the first of equally near ones): picking
    /// on the curve.
    ///
    /// # Errors
    /// [`BendelsKleinError::NonFinitePoint`] (index 0) for a non-finite `q`.
    pub fn nearest(&self, q: P) -> Result<usize> {
        if !q.finite() {
            return Err(BendelsKleinError::NonFinitePoint { index: 0 });
        }
        let q = q.to_space();
        let mut best = (f64::INFINITY, 0);
        for (i, p) in self.points.iter().enumerate() {
            let d = p.to_space().distance_squared(q);
            if d < best.0 {
                best = (d, i);
            }
        }
        Ok(best.1)
    }

    /// Moves point `index` to `p` (the polyline's positions changed; what was derived
    /// from it still fits, see [`Binding::fits`]).
    ///
    /// # Errors
    /// [`BendelsKleinError::NonFinitePoint`] for a non-finite `p`,
    /// [`BendelsKleinError::InvalidParameter`] for an index out of range; nothing changes
    /// then.
    pub fn set_point(&mut self, index: usize, p: P) -> Result<()> {
        if !p.finite() {
            return Err(BendelsKleinError::NonFinitePoint { index });
        }
        let len = self.points.len();
        let slot =
            self.points
                .get_mut(index)
                .ok_or_else(|| BendelsKleinError::InvalidParameter {
                    name: "index",
                    reason: format!("point {index} of a polyline of {len} points"),
                })?;
        *slot = p;
        self.provenance.positions_changed();
        Ok(())
    }

    /// Inserts `p` before point `index` (at the end for `index == len`): a change of the
    /// polyline's connectivity, after which regions made for it are stale.
    ///
    /// # Errors
    /// [`BendelsKleinError::NonFinitePoint`] for a non-finite `p`,
    /// [`BendelsKleinError::InvalidParameter`] for an index beyond the end; nothing
    /// changes then.
    pub fn insert_point(&mut self, index: usize, p: P) -> Result<()> {
        if !p.finite() {
            return Err(BendelsKleinError::NonFinitePoint { index });
        }
        if index > self.points.len() {
            return Err(BendelsKleinError::InvalidParameter {
                name: "index",
                reason: format!(
                    "insertion at {index} in a polyline of {} points",
                    self.points.len()
                ),
            });
        }
        self.points.insert(index, p);
        self.provenance.connectivity_changed();
        Ok(())
    }

    /// The binding of what is derived from the polyline now (see [`Binding`]).
    #[must_use]
    pub fn binding(&self) -> Binding {
        self.provenance.binding()
    }

    pub(super) fn from_parts(points: Vec<P>, closed: bool) -> Self {
        Self {
            points,
            closed,
            provenance: Provenance::new(),
        }
    }
}

/// Segments of a polyline with `n` points.
#[inline]
pub(super) fn n_segments(n: usize, closed: bool) -> usize {
    if closed {
        n
    } else {
        n.saturating_sub(1)
    }
}

/// The ends of segment `k` of a polyline with `n` points: `(k, k + 1)`, the last of a
/// closed polygon `(n − 1, 0)`.
#[inline]
pub(super) fn segment(k: usize, n: usize) -> (usize, usize) {
    (k, if k + 1 == n { 0 } else { k + 1 })
}
