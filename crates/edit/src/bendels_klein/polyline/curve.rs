//! Points and polylines (Bendels & Klein, Sec. 2, Fig. 1 top).

use glam::{DMat3, DMat4, DVec2, DVec3};

use super::{CurveError, CurveResult};
use crate::bendels_klein::affine_power::{embed_affine2, AffinePower};

/// A point of a polyline: [`DVec2`] (transforms are 3×3 homogeneous [`DMat3`]) or
/// [`DVec3`] (4×4 [`DMat4`]). The blend works in space; 2-D points live in `z = 0` and
/// their transforms act on `x, y` only ([`embed_affine2`]).
pub trait CurvePoint: Copy + PartialEq + std::fmt::Debug + Send + Sync + 'static {
    /// The homogeneous affine transform of such points.
    type Affine: Copy + PartialEq + std::fmt::Debug + Send + Sync;
    /// The point in space (`z = 0` in 2-D).
    fn to_space(self) -> DVec3;
    /// The point back from space (`z` dropped in 2-D).
    fn from_space(p: DVec3) -> Self;
    /// True when every coordinate is finite.
    fn finite(self) -> bool;
    /// The midpoint of `self` and `other`.
    fn midpoint(self, other: Self) -> Self;
    /// The transform as a 4×4 affine map of space.
    fn embed(a: Self::Affine) -> DMat4;
    /// The identity transform.
    fn identity() -> Self::Affine;
    /// `A p`, with the arithmetic of glam's `transform_point2` / `transform_point3`.
    fn apply(a: &Self::Affine, p: Self) -> Self;
    /// `(α ⊙ A) p` from a prepared power of `embed(A)`.
    fn blend(power: &AffinePower, alpha: f64, p: Self) -> Self;
}

impl CurvePoint for DVec2 {
    type Affine = DMat3;
    #[inline]
    fn to_space(self) -> DVec3 {
        self.extend(0.0)
    }
    #[inline]
    fn from_space(p: DVec3) -> Self {
        p.truncate()
    }
    #[inline]
    fn finite(self) -> bool {
        self.is_finite()
    }
    #[inline]
    fn midpoint(self, other: Self) -> Self {
        // Halves first: finite points give a finite midpoint even near f64::MAX.
        0.5 * self + 0.5 * other
    }
    fn embed(a: DMat3) -> DMat4 {
        embed_affine2(a)
    }
    fn identity() -> DMat3 {
        DMat3::IDENTITY
    }
    #[inline]
    fn apply(a: &DMat3, p: Self) -> Self {
        a.transform_point2(p)
    }
    #[inline]
    fn blend(power: &AffinePower, alpha: f64, p: Self) -> Self {
        power.transform_point2(alpha, p)
    }
}

impl CurvePoint for DVec3 {
    type Affine = DMat4;
    #[inline]
    fn to_space(self) -> DVec3 {
        self
    }
    #[inline]
    fn from_space(p: DVec3) -> Self {
        p
    }
    #[inline]
    fn finite(self) -> bool {
        self.is_finite()
    }
    #[inline]
    fn midpoint(self, other: Self) -> Self {
        // Halves first: finite points give a finite midpoint even near f64::MAX.
        0.5 * self + 0.5 * other
    }
    fn embed(a: DMat4) -> DMat4 {
        a
    }
    fn identity() -> DMat4 {
        DMat4::IDENTITY
    }
    #[inline]
    fn apply(a: &DMat4, p: Self) -> Self {
        a.transform_point3(p)
    }
    #[inline]
    fn blend(power: &AffinePower, alpha: f64, p: Self) -> Self {
        power.transform_point(alpha, p)
    }
}

/// An open polyline or a closed polygon (the last point joined to the first), the
/// curve of Bendels & Klein's Figs. 1 (top) and 2. Never empty; every point finite.
#[derive(Clone, Debug, PartialEq)]
pub struct Polyline<P> {
    points: Vec<P>,
    closed: bool,
}

impl<P: CurvePoint> Polyline<P> {
    /// A polyline through `points`, closed into a polygon when `closed`.
    ///
    /// # Errors
    /// [`CurveError::Empty`] without points, [`CurveError::TooFewPoints`] for a closed
    /// polygon of fewer than 3, [`CurveError::NonFinitePoint`] for NaN or infinite
    /// coordinates.
    pub fn new(points: Vec<P>, closed: bool) -> CurveResult<Self> {
        if points.is_empty() {
            return Err(CurveError::Empty);
        }
        if closed && points.len() < 3 {
            return Err(CurveError::TooFewPoints(points.len()));
        }
        if let Some(index) = points.iter().position(|p| !p.finite()) {
            return Err(CurveError::NonFinitePoint { index });
        }
        Ok(Self { points, closed })
    }

    /// An open polyline (see [`Polyline::new`]).
    ///
    /// # Errors
    /// As [`Polyline::new`].
    pub fn open(points: Vec<P>) -> CurveResult<Self> {
        Self::new(points, false)
    }

    /// A closed polygon (see [`Polyline::new`]).
    ///
    /// # Errors
    /// As [`Polyline::new`].
    pub fn closed(points: Vec<P>) -> CurveResult<Self> {
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
    /// [`CurveError::NonFinitePoint`] (index 0) for a non-finite `q`.
    pub fn nearest(&self, q: P) -> CurveResult<usize> {
        if !q.finite() {
            return Err(CurveError::NonFinitePoint { index: 0 });
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

    pub(super) fn from_parts(points: Vec<P>, closed: bool) -> Self {
        Self { points, closed }
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
