//! Shape functions (Bendels & Klein, Sec. 5).

use crate::bendels_klein::error::{BendelsKleinError, ControlPointProblem, Result};

/// Shape functions `f: [0, 1] → [0, 1]` with `f(0) = 0`, `f(1) = 1` (Bendels & Klein,
/// Sec. 5): the blend weight of a deformable vertex is `α = f(d_fixed / (d_fixed +
/// d_handle))`, so `f` sets the profile of the deformed area. The edit joins the fixed
/// area and the handle continuously when `f` is continuous, and without a crease
/// ("differentiably") when moreover `f'(0) = f'(1) = 0`.
///
/// - Presets: [`ShapeFunction::Linear`] (continuous only), [`ShapeFunction::Smoothstep`]
///   `3x² − 2x³` (C¹ joins), [`ShapeFunction::Smootherstep`] `6x⁵ − 15x⁴ + 10x³` (C²
///   joins).
/// - [`ShapeCurve`]: a user-editable piecewise cubic Hermite curve through control
///   points (the endpoints (0, 0) and (1, 1) are implied). With
///   [`CurveOptions::monotone`] the tangents follow Fritsch & Carlson (1980, *Monotone
///   piecewise cubic interpolation*): the curve is monotone whenever the points are,
///   and never leaves [0, 1]. Otherwise the tangents are central differences
///   (Catmull–Rom), smoother but free to overshoot, and the values are clamped to
///   [0, 1]. [`CurveOptions::flat_ends`] sets `f'(0) = f'(1) = 0`.
///
/// A shape function `f: [0, 1] → [0, 1]`, `f(0) = 0`, `f(1) = 1` (Bendels & Klein,
/// Sec. 5).
#[derive(Clone, Debug, PartialEq)]
pub enum ShapeFunction {
    /// `f(x) = x`: continuous, creased at both borders.
    Linear,
    /// `f(x) = 3x² − 2x³`: C¹, `f'(0) = f'(1) = 0`.
    Smoothstep,
    /// `f(x) = 6x⁵ − 15x⁴ + 10x³`: C², first and second derivatives vanish at the ends.
    Smootherstep,
    /// A curve through user control points.
    Curve(ShapeCurve),
}

impl Default for ShapeFunction {
    /// [`ShapeFunction::Smoothstep`]: the simplest shape with crease-free joins.
    fn default() -> Self {
        Self::Smoothstep
    }
}

impl ShapeFunction {
    /// `f(x)`, with `x` clamped to [0, 1] (NaN gives 0).
    #[inline]
    #[must_use]
    pub fn eval(&self, x: f64) -> f64 {
        let x = clamp01(x);
        match self {
            Self::Linear => x,
            Self::Smoothstep => x * x * (3.0 - 2.0 * x),
            Self::Smootherstep => x * x * x * (x * (6.0 * x - 15.0) + 10.0),
            Self::Curve(c) => c.eval(x),
        }
    }

    /// `f'(x)` for `x` in [0, 1] (one-sided at the ends).
    #[must_use]
    pub fn derivative(&self, x: f64) -> f64 {
        let x = clamp01(x);
        match self {
            Self::Linear => 1.0,
            Self::Smoothstep => 6.0 * x * (1.0 - x),
            Self::Smootherstep => 30.0 * x * x * (x - 1.0) * (x - 1.0),
            Self::Curve(c) => c.derivative(x),
        }
    }
}

#[inline]
fn clamp01(x: f64) -> f64 {
    if x >= 1.0 {
        1.0
    } else if x > 0.0 {
        x
    } else {
        0.0
    }
}

/// How [`ShapeCurve`] fits its control points.
///
/// Paper: Bendels & Klein 2003, *Image and 3D-object editing with precisely specified
/// editing regions*, Sec. 5 (Fritsch & Carlson 1980, *Monotone piecewise cubic
/// interpolation*).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct CurveOptions {
    /// Fritsch–Carlson tangents: monotone (and inside [0, 1]) through monotone points;
    /// control points that decrease are refused. Default `true`.
    pub monotone: bool,
    /// `f'(0) = f'(1) = 0`: crease-free joins with the fixed area and the handle.
    /// Default `true`.
    pub flat_ends: bool,
}

impl CurveOptions {
    /// The same options with whether the curve is monotone (Fritsch–Carlson tangents) set to `monotone`.
    #[must_use]
    pub fn with_monotone(mut self, monotone: bool) -> Self {
        self.monotone = monotone;
        self
    }

    /// The same options with whether the curve is flat at both ends set to `flat_ends`.
    #[must_use]
    pub fn with_flat_ends(mut self, flat_ends: bool) -> Self {
        self.flat_ends = flat_ends;
        self
    }
}

impl Default for CurveOptions {
    fn default() -> Self {
        Self {
            monotone: true,
            flat_ends: true,
        }
    }
}

/// A user-editable shape curve: the piecewise cubic Hermite interpolant of (0, 0), the
/// interior control points and (1, 1) (Bendels & Klein, Sec. 5 and Fig. 8: "the shape
/// function is interactively modified").
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeCurve {
    options: CurveOptions,
    xs: Vec<f64>,
    ys: Vec<f64>,
    slopes: Vec<f64>,
}

impl ShapeCurve {
    /// The curve through (0, 0), `interior` (strictly increasing x in (0, 1), y in
    /// [0, 1]) and (1, 1).
    ///
    /// # Errors
    /// [`BendelsKleinError::InvalidShapeCurve`] for points outside the open unit interval in x,
    /// outside [0, 1] in y, non-finite or not strictly increasing in x;
    /// [`BendelsKleinError::ShapeNotMonotone`] when `options.monotone` and the y decrease.
    pub fn new(interior: &[(f64, f64)], options: CurveOptions) -> Result<Self> {
        let mut xs = Vec::with_capacity(interior.len() + 2);
        let mut ys = Vec::with_capacity(interior.len() + 2);
        xs.push(0.0);
        ys.push(0.0);
        for (i, &(x, y)) in interior.iter().enumerate() {
            if !x.is_finite() || !y.is_finite() {
                return Err(BendelsKleinError::InvalidShapeCurve {
                    index: i,
                    point: (x, y),
                    problem: ControlPointProblem::NotFinite,
                });
            }
            if x <= 0.0 || x >= 1.0 || !(0.0..=1.0).contains(&y) {
                return Err(BendelsKleinError::InvalidShapeCurve {
                    index: i,
                    point: (x, y),
                    problem: ControlPointProblem::OutsideUnitSquare,
                });
            }
            if x <= *xs.last().expect("starts with 0") {
                return Err(BendelsKleinError::InvalidShapeCurve {
                    index: i,
                    point: (x, y),
                    problem: ControlPointProblem::NotIncreasing,
                });
            }
            xs.push(x);
            ys.push(y);
        }
        xs.push(1.0);
        ys.push(1.0);
        let mut curve = Self {
            options,
            xs,
            ys,
            slopes: Vec::new(),
        };
        curve.fit()?;
        Ok(curve)
    }

    /// The interior control points.
    #[must_use]
    pub fn control_points(&self) -> Vec<(f64, f64)> {
        let n = self.xs.len();
        (1..n - 1).map(|i| (self.xs[i], self.ys[i])).collect()
    }

    /// The fitting options.
    #[must_use]
    pub fn options(&self) -> CurveOptions {
        self.options
    }

    /// Moves interior control point `index` to `(x, y)` and refits (the user dragging a
    /// point of the curve). On error the curve is unchanged.
    ///
    /// # Errors
    /// As [`ShapeCurve::new`]; [`BendelsKleinError::InvalidParameter`] for a bad index.
    pub fn move_point(&mut self, index: usize, point: (f64, f64)) -> Result<()> {
        let mut points = self.control_points();
        let slot = points
            .get_mut(index)
            .ok_or_else(|| BendelsKleinError::InvalidParameter {
                name: "index",
                reason: format!("the curve has {} control points", self.xs.len() - 2),
            })?;
        *slot = point;
        *self = Self::new(&points, self.options)?;
        Ok(())
    }

    /// Computes the Hermite slopes.
    fn fit(&mut self) -> Result<()> {
        let n = self.xs.len();
        let secants: Vec<f64> = (0..n - 1)
            .map(|k| (self.ys[k + 1] - self.ys[k]) / (self.xs[k + 1] - self.xs[k]))
            .collect();
        let mut m = vec![0.0; n];
        if self.options.monotone {
            if let Some(k) = secants.iter().position(|&d| d < 0.0) {
                return Err(BendelsKleinError::ShapeNotMonotone {
                    x0: self.xs[k],
                    x1: self.xs[k + 1],
                });
            }
            // Fritsch–Carlson: start from averaged secants, zero at flat spots, then
            // limit (α, β) = (m_k, m_{k+1}) / Δ_k to the circle α² + β² ≤ 9.
            for k in 1..n - 1 {
                m[k] = if secants[k - 1] == 0.0 || secants[k] == 0.0 {
                    0.0
                } else {
                    0.5 * (secants[k - 1] + secants[k])
                };
            }
            if !self.options.flat_ends {
                m[0] = secants[0];
                m[n - 1] = secants[n - 2];
            }
            for k in 0..n - 1 {
                let d = secants[k];
                if d == 0.0 {
                    m[k] = 0.0;
                    m[k + 1] = 0.0;
                    continue;
                }
                let (a, b) = (m[k] / d, m[k + 1] / d);
                let s = a * a + b * b;
                if s > 9.0 {
                    let tau = 3.0 / s.sqrt();
                    m[k] = tau * a * d;
                    m[k + 1] = tau * b * d;
                }
            }
        } else {
            for (k, slope) in m.iter_mut().enumerate().take(n - 1).skip(1) {
                *slope = (self.ys[k + 1] - self.ys[k - 1]) / (self.xs[k + 1] - self.xs[k - 1]);
            }
            if !self.options.flat_ends {
                m[0] = secants[0];
                m[n - 1] = secants[n - 2];
            }
        }
        self.slopes = m;
        Ok(())
    }

    fn segment(&self, x: f64) -> usize {
        // Few points: a partition point on the sorted knots.
        self.xs[1..self.xs.len() - 1]
            .partition_point(|&k| k <= x)
            .min(self.xs.len() - 2)
    }

    /// `f(x)` for `x` in [0, 1].
    #[must_use]
    pub fn eval(&self, x: f64) -> f64 {
        let x = clamp01(x);
        let k = self.segment(x);
        let h = self.xs[k + 1] - self.xs[k];
        let t = (x - self.xs[k]) / h;
        let (t2, t3) = (t * t, t * t * t);
        let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
        let h10 = t3 - 2.0 * t2 + t;
        let h01 = -2.0 * t3 + 3.0 * t2;
        let h11 = t3 - t2;
        let y = h00 * self.ys[k]
            + h10 * h * self.slopes[k]
            + h01 * self.ys[k + 1]
            + h11 * h * self.slopes[k + 1];
        clamp01(y)
    }

    /// `f'(x)` for `x` in [0, 1] (of the unclamped cubic).
    #[must_use]
    pub fn derivative(&self, x: f64) -> f64 {
        let x = clamp01(x);
        let k = self.segment(x);
        let h = self.xs[k + 1] - self.xs[k];
        let t = (x - self.xs[k]) / h;
        let t2 = t * t;
        let d00 = 6.0 * t2 - 6.0 * t;
        let d10 = 3.0 * t2 - 4.0 * t + 1.0;
        let d01 = -6.0 * t2 + 6.0 * t;
        let d11 = 3.0 * t2 - 2.0 * t;
        (d00 * self.ys[k] + d01 * self.ys[k + 1]) / h
            + d10 * self.slopes[k]
            + d11 * self.slopes[k + 1]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn samples() -> impl Iterator<Item = f64> {
        (0..=1000).map(|i| i as f64 / 1000.0)
    }

    #[test]
    fn presets_hit_the_ends_and_have_the_documented_slopes() {
        for f in [
            ShapeFunction::Linear,
            ShapeFunction::Smoothstep,
            ShapeFunction::Smootherstep,
        ] {
            assert_eq!(f.eval(0.0), 0.0);
            assert_eq!(f.eval(1.0), 1.0);
            assert_eq!(f.eval(-3.0), 0.0);
            assert_eq!(f.eval(7.0), 1.0);
            let mut last = 0.0;
            for x in samples() {
                let y = f.eval(x);
                assert!((0.0..=1.0).contains(&y) && y >= last);
                last = y;
                // derivative agrees with finite differences
                if x > 0.01 && x < 0.99 {
                    let fd = (f.eval(x + 1e-6) - f.eval(x - 1e-6)) / 2e-6;
                    assert!((fd - f.derivative(x)).abs() < 1e-6);
                }
            }
        }
        assert_eq!(ShapeFunction::Smoothstep.derivative(0.0), 0.0);
        assert_eq!(ShapeFunction::Smoothstep.derivative(1.0), 0.0);
        assert_eq!(ShapeFunction::Smootherstep.derivative(1.0), 0.0);
        assert_eq!(ShapeFunction::Linear.derivative(0.0), 1.0);
    }

    #[test]
    fn monotone_curve_interpolates_and_never_decreases() {
        // The paper's Fig. 8 kind of curves: steep early, or late.
        for points in [
            vec![(0.1, 0.6), (0.3, 0.9)],
            vec![(0.5, 0.05), (0.8, 0.1), (0.9, 0.95)],
            vec![(0.2, 0.2), (0.4, 0.2), (0.6, 0.8)],
        ] {
            for flat_ends in [true, false] {
                let c = ShapeCurve::new(
                    &points,
                    CurveOptions {
                        monotone: true,
                        flat_ends,
                    },
                )
                .unwrap();
                for &(x, y) in &points {
                    assert!((c.eval(x) - y).abs() < 1e-15);
                }
                assert_eq!(c.eval(0.0), 0.0);
                assert_eq!(c.eval(1.0), 1.0);
                let mut last = 0.0;
                for x in samples() {
                    let y = c.eval(x);
                    assert!(y >= last - 1e-15, "decreases at {x}");
                    assert!((0.0..=1.0).contains(&y));
                    last = y;
                }
                if flat_ends {
                    assert_eq!(c.derivative(0.0), 0.0);
                    assert_eq!(c.derivative(1.0), 0.0);
                }
            }
        }
    }

    #[test]
    fn curve_is_c1_at_the_knots() {
        let c = ShapeCurve::new(&[(0.3, 0.1), (0.7, 0.8)], CurveOptions::default()).unwrap();
        for x in [0.3, 0.7] {
            let left = c.derivative(x - 1e-12);
            let right = c.derivative(x + 1e-12);
            assert!((left - right).abs() < 1e-9);
        }
        let f = ShapeFunction::Curve(c);
        assert_eq!(f.derivative(0.0), 0.0);
        assert_eq!(f.derivative(1.0), 0.0);
    }

    #[test]
    fn bad_points_are_refused() {
        let o = CurveOptions::default();
        assert!(matches!(
            ShapeCurve::new(&[(0.5, 0.8), (0.6, 0.4)], o),
            Err(BendelsKleinError::ShapeNotMonotone { .. })
        ));
        assert!(matches!(
            ShapeCurve::new(&[(0.0, 0.5)], o),
            Err(BendelsKleinError::InvalidShapeCurve { .. })
        ));
        assert!(matches!(
            ShapeCurve::new(&[(0.5, 1.5)], o),
            Err(BendelsKleinError::InvalidShapeCurve { .. })
        ));
        assert!(matches!(
            ShapeCurve::new(&[(0.5, 0.5), (0.5, 0.6)], o),
            Err(BendelsKleinError::InvalidShapeCurve { .. })
        ));
        assert!(matches!(
            ShapeCurve::new(&[(f64::NAN, 0.5)], o),
            Err(BendelsKleinError::InvalidShapeCurve { .. })
        ));
        // Non-monotone points are fine without the monotone option, and stay in [0, 1].
        let c = ShapeCurve::new(
            &[(0.3, 0.9), (0.6, 0.1)],
            CurveOptions {
                monotone: false,
                flat_ends: true,
            },
        )
        .unwrap();
        for x in samples() {
            assert!((0.0..=1.0).contains(&c.eval(x)));
        }
    }

    #[test]
    fn moving_a_point_refits_or_leaves_the_curve_alone() {
        let mut c = ShapeCurve::new(&[(0.3, 0.2), (0.7, 0.6)], CurveOptions::default()).unwrap();
        c.move_point(1, (0.8, 0.9)).unwrap();
        assert!((c.eval(0.8) - 0.9).abs() < 1e-15);
        let before = c.clone();
        assert!(c.move_point(0, (0.9, 0.95)).is_err());
        assert_eq!(c, before);
        assert!(c.move_point(5, (0.5, 0.5)).is_err());
    }
}
