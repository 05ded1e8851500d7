//! Clamped ("Bézier-type") uniform B-spline surfaces (Feng, Ma & Peng §2), evaluated
//! either directly (Cox–de Boor, The NURBS Book A2.2/A2.3) or, for speed, through their
//! polynomial pieces in power form on each knot cell.

use std::ops::{Add, Mul};

use glam::DVec3;

use crate::deform::error::{DeformError, Result, SurfaceProblem};
use crate::deform::ffd::frame::LatticeFrame;

/// A tensor-product B-spline surface `S(u, v) = Σ_i Σ_j P_ij N_i,ku(u) N_j,kv(v)`,
/// `(u, v) ∈ [0, 1]²`, with the clamped uniform knot vectors of Feng, Ma & Peng §2:
/// `k + 1` zeros, interior knots `(i − k)/(m − k + 1)`, `k + 1` ones (`k` the degree,
/// `m + 1` control points), so that the surface interpolates its corner control points
/// and its boundary curves are those of the boundary rows, as for a Bézier surface.
///
/// Control point `(i, j)` (`i` along `u`, `j` along `v`) is stored at `i · count_v + j`.
#[derive(Clone, Debug, PartialEq)]
pub struct BSplineSurface {
    degree: [usize; 2],
    count: [usize; 2],
    control: Vec<DVec3>,
}

/// Largest degree per direction.
const MAX_DEGREE: usize = 15;

/// Largest number of control points of a surface.
const MAX_CONTROL_POINTS: usize = 1 << 20;

/// Largest number of polynomial coefficients of a surface in power form
/// (`spans_u · spans_v · (k_u + 1) · (k_v + 1)`; the deformation keeps one such table per
/// surface, 24 bytes a coefficient): about 100 MB.
const MAX_PATCH_COEFFICIENTS: usize = 1 << 22;

/// The parameter directions, for errors.
const DIRECTIONS: [char; 2] = ['u', 'v'];

/// The error of a surface not yet in an FFD.
fn invalid(problem: SurfaceProblem) -> DeformError {
    DeformError::InvalidSurface {
        surface: "B-spline",
        problem,
    }
}

/// Checks degrees and control-grid sizes against the limits above, before anything is
/// allocated.
fn check_size(degree: [usize; 2], count: [usize; 2]) -> Result<()> {
    for d in 0..2 {
        if degree[d] == 0 || degree[d] > MAX_DEGREE {
            return Err(invalid(SurfaceProblem::Degree {
                direction: DIRECTIONS[d],
                degree: degree[d],
                max: MAX_DEGREE,
            }));
        }
        if count[d] <= degree[d] {
            return Err(invalid(SurfaceProblem::TooFewControlPoints {
                direction: DIRECTIONS[d],
                count: count[d],
                degree: degree[d],
            }));
        }
    }
    let points = count[0].checked_mul(count[1]);
    if points.is_none_or(|n| n > MAX_CONTROL_POINTS) {
        return Err(invalid(SurfaceProblem::TooManyControlPoints {
            count,
            max: MAX_CONTROL_POINTS,
        }));
    }
    let coefficients = (count[0] - degree[0])
        .checked_mul(count[1] - degree[1])
        .and_then(|n| n.checked_mul((degree[0] + 1) * (degree[1] + 1)));
    if coefficients.is_none_or(|n| n > MAX_PATCH_COEFFICIENTS) {
        return Err(invalid(SurfaceProblem::TooManyCoefficients {
            count,
            degree,
            max: MAX_PATCH_COEFFICIENTS,
        }));
    }
    Ok(())
}

impl BSplineSurface {
    /// Largest degree per direction.
    pub const MAX_DEGREE: usize = MAX_DEGREE;
    /// Largest number of control points of a surface.
    pub const MAX_CONTROL_POINTS: usize = MAX_CONTROL_POINTS;
    /// Largest number of polynomial coefficients of a surface in power form
    /// (`spans_u · spans_v · (k_u + 1) · (k_v + 1)`; the deformation keeps one such table
    /// per surface, 24 bytes a coefficient): about 100 MB.
    pub const MAX_PATCH_COEFFICIENTS: usize = MAX_PATCH_COEFFICIENTS;

    /// A surface of degrees `degree = [k_u, k_v]` (`1 ..= MAX_DEGREE`) with
    /// `count = [m_u + 1, m_v + 1]` control points per direction (more than the degree, at
    /// most [`MAX_CONTROL_POINTS`](Self::MAX_CONTROL_POINTS) in all, at most [`MAX_PATCH_COEFFICIENTS`](Self::MAX_PATCH_COEFFICIENTS) polynomial
    /// coefficients) given row by row.
    pub fn new(degree: [usize; 2], count: [usize; 2], control: Vec<DVec3>) -> Result<Self> {
        check_size(degree, count)?;
        if Some(control.len()) != count[0].checked_mul(count[1]) {
            return Err(invalid(SurfaceProblem::ControlPointCount {
                given: control.len(),
                count,
            }));
        }
        if let Some(k) = control.iter().position(|p| !p.is_finite()) {
            return Err(invalid(SurfaceProblem::NonFiniteControlPoint {
                index: [k / count[1], k % count[1]],
                point: control[k],
            }));
        }
        Ok(Self {
            degree,
            count,
            control,
        })
    }

    /// A flat surface on the plane `y = height` of `frame` (the paper's initial shape
    /// surface on the XZ plane, `height = 0`, and height surface on `y = 1`): control
    /// points evenly spaced over `[min_x, max_x] × [min_z, max_z]` in frame coordinates,
    /// `u` along the frame's x axis and `v` along its z axis.
    ///
    /// # Errors
    /// [`DeformError::InvalidSurface`] for sizes out of range (see [`new`](Self::new)) or
    /// control points that are not finite (a rectangle too large for the frame);
    /// [`DeformError::InvalidParameter`] for a non-finite rectangle or height.
    pub fn planar(
        frame: &LatticeFrame,
        degree: [usize; 2],
        count: [usize; 2],
        min: [f64; 2],
        max: [f64; 2],
        height: f64,
    ) -> Result<Self> {
        if count[0] < 2 || count[1] < 2 {
            return Err(invalid(SurfaceProblem::GridTooSmall { count }));
        }
        check_size(degree, count)?;
        for (name, x) in [("min", min), ("max", max)] {
            if !(x[0].is_finite() && x[1].is_finite()) {
                return Err(DeformError::InvalidParameter {
                    name,
                    reason: format!("{x:?} is not finite"),
                });
            }
        }
        crate::deform::checks::finite("height", height)?;
        let mut control = Vec::with_capacity(count[0] * count[1]);
        for i in 0..count[0] {
            let x = min[0] + (max[0] - min[0]) * i as f64 / (count[0] - 1) as f64;
            for j in 0..count[1] {
                let z = min[1] + (max[1] - min[1]) * j as f64 / (count[1] - 1) as f64;
                control.push(frame.to_world(DVec3::new(x, height, z)));
            }
        }
        Self::new(degree, count, control)
    }

    /// The degrees `[k_u, k_v]`.
    pub fn degree(&self) -> [usize; 2] {
        self.degree
    }

    /// The control-grid size `[m_u + 1, m_v + 1]`.
    pub fn count(&self) -> [usize; 2] {
        self.count
    }

    /// Number of knot spans (polynomial pieces) per direction, `m − k + 1`.
    pub fn spans(&self) -> [usize; 2] {
        [
            self.count[0] - self.degree[0],
            self.count[1] - self.degree[1],
        ]
    }

    /// The knot vector of direction `d` (0: u, 1: v).
    pub fn knots(&self, d: usize) -> Vec<f64> {
        clamped_uniform_knots(self.degree[d], self.count[d])
    }

    /// All control points, row by row (`i · count_v + j`).
    pub fn control_points(&self) -> &[DVec3] {
        &self.control
    }

    /// All control points, mutable. Nothing checks what is written here:
    /// [`Ffd::deform`](super::Ffd::deform) refuses surfaces with non-finite control points.
    pub fn control_points_mut(&mut self) -> &mut [DVec3] {
        &mut self.control
    }

    /// Control point `(i, j)`; `None` outside the grid.
    pub fn control_point(&self, i: usize, j: usize) -> Option<DVec3> {
        (i < self.count[0] && j < self.count[1]).then(|| self.control[i * self.count[1] + j])
    }

    /// Moves control point `(i, j)`.
    pub fn set_control_point(&mut self, i: usize, j: usize, p: DVec3) -> Result<()> {
        if i >= self.count[0] || j >= self.count[1] {
            return Err(DeformError::InvalidParameter {
                name: "control point index",
                reason: format!(
                    "({i}, {j}) outside the {}×{} grid",
                    self.count[0], self.count[1]
                ),
            });
        }
        if !p.is_finite() {
            return Err(DeformError::InvalidParameter {
                name: "control point",
                reason: format!("{p} is not finite"),
            });
        }
        self.control[i * self.count[1] + j] = p;
        Ok(())
    }

    /// `S(u, v)` (parameters clamped to `[0, 1]`).
    pub fn evaluate(&self, u: f64, v: f64) -> DVec3 {
        self.derivatives(u, v).0
    }

    /// `(S, ∂S/∂u, ∂S/∂v)` at `(u, v)`, by Cox–de Boor (The NURBS Book A2.3).
    pub fn derivatives(&self, u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
        let (su, du) = self.basis(0, u);
        let (sv, dv) = self.basis(1, v);
        let mut s = DVec3::ZERO;
        let mut s_u = DVec3::ZERO;
        let mut s_v = DVec3::ZERO;
        for (a, (&n0, &n1)) in du[0].iter().zip(&du[1]).enumerate() {
            let row = (su + a) * self.count[1] + sv;
            for (b, (&m0, &m1)) in dv[0].iter().zip(&dv[1]).enumerate() {
                let p = self.control[row + b];
                s += n0 * m0 * p;
                s_u += n1 * m0 * p;
                s_v += n0 * m1 * p;
            }
        }
        (s, s_u, s_v)
    }

    /// The unit normal `∂S/∂v × ∂S/∂u` normalised (for the default frame, `+y` on the
    /// initial surface); zero where the surface is degenerate.
    pub fn normal(&self, u: f64, v: f64) -> DVec3 {
        let (_, s_u, s_v) = self.derivatives(u, v);
        s_v.cross(s_u).normalize_or_zero()
    }

    /// First control index and the values and first derivatives of the `k + 1` basis
    /// functions not zero at parameter `t` of direction `d`.
    fn basis(&self, d: usize, t: f64) -> (usize, Vec<Vec<f64>>) {
        let (k, n) = (self.degree[d], self.count[d]);
        let spans = n - k;
        let t = t.clamp(0.0, 1.0);
        let sigma = ((t * spans as f64) as usize).min(spans - 1);
        let knots = clamped_uniform_knots(k, n);
        (sigma, basis_derivatives(k + sigma, t, k, 1, &knots))
    }
}

/// The clamped uniform knot vector of Feng, Ma & Peng §2 for degree `k` and `n` control
/// points: `k + 1` zeros, `(i − k)/(n − k)` for `i = k + 1 ..= n − 1`, `k + 1` ones.
pub(crate) fn clamped_uniform_knots(k: usize, n: usize) -> Vec<f64> {
    let spans = n - k;
    (0..n + k + 1)
        .map(|i| {
            if i <= k {
                0.0
            } else if i >= n {
                1.0
            } else {
                (i - k) as f64 / spans as f64
            }
        })
        .collect()
}

/// The values and derivatives up to order `n` of the `p + 1` B-spline basis functions
/// of degree `p` not zero on knot span `span` (`U[span] ≤ u < U[span + 1]`), at `u`:
/// `ders[k][j]` is the `k`-th derivative of `N_{span − p + j, p}` (The NURBS Book, A2.3).
pub(crate) fn basis_derivatives(
    span: usize,
    u: f64,
    p: usize,
    n: usize,
    knots: &[f64],
) -> Vec<Vec<f64>> {
    let mut ndu = vec![vec![0.0; p + 1]; p + 1];
    let mut left = vec![0.0; p + 1];
    let mut right = vec![0.0; p + 1];
    ndu[0][0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j][r] = right[r + 1] + left[j - r];
            let temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    let mut ders = vec![vec![0.0; p + 1]; n + 1];
    for j in 0..=p {
        ders[0][j] = ndu[j][p];
    }
    let mut a = [vec![0.0; p + 1], vec![0.0; p + 1]];
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, 1usize);
        a[0][0] = 1.0;
        for k in 1..=n.min(p) {
            let mut d = 0.0;
            let rk = r as isize - k as isize;
            let pk = p as isize - k as isize;
            if r >= k {
                a[s2][0] = a[s1][0] / ndu[(pk + 1) as usize][rk as usize];
                d = a[s2][0] * ndu[rk as usize][pk as usize];
            }
            let j1: isize = if rk >= -1 { 1 } else { -rk };
            let j2: isize = if r as isize - 1 <= pk {
                k as isize - 1
            } else {
                p as isize - r as isize
            };
            for j in j1..=j2 {
                let j = j as usize;
                a[s2][j] =
                    (a[s1][j] - a[s1][j - 1]) / ndu[(pk + 1) as usize][(rk + j as isize) as usize];
                d += a[s2][j] * ndu[(rk + j as isize) as usize][pk as usize];
            }
            if r as isize <= pk {
                a[s2][k] = -a[s1][k - 1] / ndu[(pk + 1) as usize][r];
                d += a[s2][k] * ndu[r][pk as usize];
            }
            ders[k][r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut factor = p as f64;
    for (k, der) in ders.iter_mut().enumerate().take(n.min(p) + 1).skip(1) {
        for x in der.iter_mut() {
            *x *= factor;
        }
        factor *= (p - k) as f64;
    }
    ders
}

/// The power-form coefficients of the basis functions on each knot span of one
/// direction: on span `σ` with local parameter `t = u·spans − σ ∈ [0, 1]`,
/// `N_{σ+i}(u) = Σ_a coef[σ][i][a] t^a` (Taylor expansion at the span's left end).
#[derive(Clone, Debug)]
pub(crate) struct SpanPolynomials {
    order: usize,
    spans: usize,
    coef: Vec<f64>,
}

impl SpanPolynomials {
    pub(crate) fn new(degree: usize, count: usize) -> Self {
        let spans = count - degree;
        let order = degree + 1;
        let knots = clamped_uniform_knots(degree, count);
        let width = 1.0 / spans as f64;
        let mut coef = vec![0.0; spans * order * order];
        for sigma in 0..spans {
            let span = degree + sigma;
            let ders = basis_derivatives(span, knots[span], degree, degree, &knots);
            let mut scale = 1.0; // width^a / a!
            for (a, der) in ders.iter().enumerate() {
                if a > 0 {
                    scale *= width / a as f64;
                }
                for (i, &d) in der.iter().enumerate() {
                    coef[(sigma * order + i) * order + a] = d * scale;
                }
            }
        }
        Self { order, spans, coef }
    }

    #[inline]
    fn at(&self, sigma: usize, i: usize, a: usize) -> f64 {
        self.coef[(sigma * self.order + i) * self.order + a]
    }
}

/// A value type of a polynomial patch: points (`DVec3`) or scalars (`f64`).
pub(crate) trait Coefficient:
    Copy + Default + Add<Output = Self> + Mul<f64, Output = Self> + Send + Sync
{
}
impl Coefficient for DVec3 {}
impl Coefficient for f64 {}

/// A tensor-product spline in power form on each knot cell: cell `(σu, σv)` holds
/// `C_ab` with `S = Σ_a Σ_b C_ab s^a t^b`, `s, t ∈ [0, 1]` the cell's local parameters.
/// Evaluating it costs a few Horner loops per point, with no per-point basis storage.
#[derive(Clone, Debug)]
pub(crate) struct Patches<T> {
    order: [usize; 2],
    spans: [usize; 2],
    coef: Vec<T>,
}

/// Second-order derivatives at a point: `(S, S_u, S_v, S_uu, S_uv, S_vv)`.
pub(crate) type Second<T> = (T, T, T, T, T, T);

impl<T: Coefficient> Patches<T> {
    /// The patches of the spline with control values `control` (row-major, `count[1]`
    /// per row) and degrees `degree`.
    pub(crate) fn new(degree: [usize; 2], count: [usize; 2], control: &[T]) -> Self {
        let pu = SpanPolynomials::new(degree[0], count[0]);
        let pv = SpanPolynomials::new(degree[1], count[1]);
        let order = [degree[0] + 1, degree[1] + 1];
        let spans = [pu.spans, pv.spans];
        let cell = order[0] * order[1];
        let mut coef = vec![T::default(); spans[0] * spans[1] * cell];
        let mut tmp = vec![T::default(); cell];
        for su in 0..spans[0] {
            for sv in 0..spans[1] {
                // tmp[i][b] = Σ_j cv[j][b] P[su + i][sv + j]
                for i in 0..order[0] {
                    for b in 0..order[1] {
                        let mut acc = T::default();
                        for j in 0..order[1] {
                            acc = acc + control[(su + i) * count[1] + sv + j] * pv.at(sv, j, b);
                        }
                        tmp[i * order[1] + b] = acc;
                    }
                }
                let base = (su * spans[1] + sv) * cell;
                for a in 0..order[0] {
                    for b in 0..order[1] {
                        let mut acc = T::default();
                        for i in 0..order[0] {
                            acc = acc + tmp[i * order[1] + b] * pu.at(su, i, a);
                        }
                        coef[base + a * order[1] + b] = acc;
                    }
                }
            }
        }
        Self { order, spans, coef }
    }

    /// The cell of `(u, v)` (clamped into `[0, 1]²`), its local parameters, and the
    /// derivative scales `du/ds`, `dv/dt` inverted (`spans`).
    #[inline]
    fn locate(&self, u: f64, v: f64) -> (usize, f64, f64) {
        let (nu, nv) = (self.spans[0] as f64, self.spans[1] as f64);
        let x = u.clamp(0.0, 1.0) * nu;
        let y = v.clamp(0.0, 1.0) * nv;
        let su = (x as usize).min(self.spans[0] - 1);
        let sv = (y as usize).min(self.spans[1] - 1);
        (
            (su * self.spans[1] + sv) * self.order[0] * self.order[1],
            x - su as f64,
            y - sv as f64,
        )
    }

    /// `S(u, v)`.
    #[inline]
    pub(crate) fn value(&self, u: f64, v: f64) -> T {
        let (base, s, t) = self.locate(u, v);
        let cell = &self.coef[base..base + self.order[0] * self.order[1]];
        match self.order {
            [2, 2] => value_fixed::<T, 2, 2>(cell, s, t),
            [3, 3] => value_fixed::<T, 3, 3>(cell, s, t),
            [4, 4] => value_fixed::<T, 4, 4>(cell, s, t),
            [2, 3] => value_fixed::<T, 2, 3>(cell, s, t),
            [3, 2] => value_fixed::<T, 3, 2>(cell, s, t),
            [3, 4] => value_fixed::<T, 3, 4>(cell, s, t),
            [4, 3] => value_fixed::<T, 4, 3>(cell, s, t),
            [2, 4] => value_fixed::<T, 2, 4>(cell, s, t),
            [4, 2] => value_fixed::<T, 4, 2>(cell, s, t),
            [ou, ov] => value_dynamic(cell, ou, ov, s, t),
        }
    }

    /// `(S, S_s, S_t)` at `(u, v)`, derivatives with respect to the cell's local
    /// parameters (`S_u = spans_u · S_s`, `S_v = spans_v · S_t`).
    #[inline]
    pub(crate) fn first_local(&self, u: f64, v: f64) -> (T, T, T) {
        let (base, s, t) = self.locate(u, v);
        let cell = &self.coef[base..base + self.order[0] * self.order[1]];
        match self.order {
            [2, 2] => first_fixed::<T, 2, 2>(cell, s, t),
            [3, 3] => first_fixed::<T, 3, 3>(cell, s, t),
            [4, 4] => first_fixed::<T, 4, 4>(cell, s, t),
            [2, 3] => first_fixed::<T, 2, 3>(cell, s, t),
            [3, 2] => first_fixed::<T, 3, 2>(cell, s, t),
            [3, 4] => first_fixed::<T, 3, 4>(cell, s, t),
            [4, 3] => first_fixed::<T, 4, 3>(cell, s, t),
            [2, 4] => first_fixed::<T, 2, 4>(cell, s, t),
            [4, 2] => first_fixed::<T, 4, 2>(cell, s, t),
            [ou, ov] => first_dynamic(cell, ou, ov, s, t),
        }
    }

    /// `(S, S_u, S_v, S_uu, S_uv, S_vv)` at `(u, v)`, in the global parameters.
    pub(crate) fn second(&self, u: f64, v: f64) -> Second<T> {
        let (base, s, t) = self.locate(u, v);
        let cell = &self.coef[base..base + self.order[0] * self.order[1]];
        let local = match self.order {
            [2, 2] => second_fixed::<T, 2, 2>(cell, s, t),
            [3, 3] => second_fixed::<T, 3, 3>(cell, s, t),
            [4, 4] => second_fixed::<T, 4, 4>(cell, s, t),
            [ou, ov] => second_dynamic(cell, ou, ov, s, t),
        };
        let (nu, nv) = (self.spans[0] as f64, self.spans[1] as f64);
        (
            local.0,
            local.1 * nu,
            local.2 * nv,
            local.3 * (nu * nu),
            local.4 * (nu * nv),
            local.5 * (nv * nv),
        )
    }

    /// The number of knot spans per direction.
    pub(crate) fn spans(&self) -> [usize; 2] {
        self.spans
    }
}

/// Horner evaluation of one cell, any orders.
#[inline]
fn value_dynamic<T: Coefficient>(cell: &[T], ou: usize, ov: usize, s: f64, t: f64) -> T {
    let mut acc = T::default();
    for a in (0..ou).rev() {
        let mut r = T::default();
        for &c in cell[a * ov..(a + 1) * ov].iter().rev() {
            r = r * t + c;
        }
        acc = acc * s + r;
    }
    acc
}

/// Horner evaluation of one cell with orders known at compile time (unrolled).
#[inline(always)]
fn value_fixed<T: Coefficient, const OU: usize, const OV: usize>(cell: &[T], s: f64, t: f64) -> T {
    let cell = &cell[..OU * OV];
    let mut acc = T::default();
    for a in (0..OU).rev() {
        let mut r = T::default();
        for b in (0..OV).rev() {
            r = r * t + cell[a * OV + b];
        }
        acc = acc * s + r;
    }
    acc
}

/// Value and first local derivatives of one cell, any orders.
#[inline]
fn first_dynamic<T: Coefficient>(cell: &[T], ou: usize, ov: usize, s: f64, t: f64) -> (T, T, T) {
    let (mut p, mut p_s, mut p_t) = (T::default(), T::default(), T::default());
    for a in (0..ou).rev() {
        let (mut r, mut r_t) = (T::default(), T::default());
        for &c in cell[a * ov..(a + 1) * ov].iter().rev() {
            r_t = r_t * t + r;
            r = r * t + c;
        }
        p_s = p_s * s + p;
        p = p * s + r;
        p_t = p_t * s + r_t;
    }
    (p, p_s, p_t)
}

/// Value and first local derivatives of one cell with orders known at compile time.
#[inline(always)]
fn first_fixed<T: Coefficient, const OU: usize, const OV: usize>(
    cell: &[T],
    s: f64,
    t: f64,
) -> (T, T, T) {
    let cell = &cell[..OU * OV];
    let (mut p, mut p_s, mut p_t) = (T::default(), T::default(), T::default());
    for a in (0..OU).rev() {
        let (mut r, mut r_t) = (T::default(), T::default());
        for b in (0..OV).rev() {
            r_t = r_t * t + r;
            r = r * t + cell[a * OV + b];
        }
        p_s = p_s * s + p;
        p = p * s + r;
        p_t = p_t * s + r_t;
    }
    (p, p_s, p_t)
}

/// Value, first and second local derivatives of one cell, any orders:
/// `(S, S_s, S_t, S_ss, S_st, S_tt)`. Horner with derivatives in `t` for each row, then
/// in `s`.
#[inline]
fn second_dynamic<T: Coefficient>(cell: &[T], ou: usize, ov: usize, s: f64, t: f64) -> Second<T> {
    let z = T::default();
    let (mut p, mut p_s, mut p_ss2) = (z, z, z);
    let (mut q, mut q_s) = (z, z); // Σ r_t s^a and its s-derivative
    let mut w = z; // Σ r_tt s^a
    for a in (0..ou).rev() {
        let (mut r, mut r_t, mut r_tt2) = (z, z, z);
        for &c in cell[a * ov..(a + 1) * ov].iter().rev() {
            r_tt2 = r_tt2 * t + r_t;
            r_t = r_t * t + r;
            r = r * t + c;
        }
        p_ss2 = p_ss2 * s + p_s;
        p_s = p_s * s + p;
        p = p * s + r;
        q_s = q_s * s + q;
        q = q * s + r_t;
        w = w * s + r_tt2 * 2.0;
    }
    (p, p_s, q, p_ss2 * 2.0, q_s, w)
}

/// [`second_dynamic`] with orders known at compile time.
#[inline(always)]
fn second_fixed<T: Coefficient, const OU: usize, const OV: usize>(
    cell: &[T],
    s: f64,
    t: f64,
) -> Second<T> {
    let cell = &cell[..OU * OV];
    let z = T::default();
    let (mut p, mut p_s, mut p_ss2) = (z, z, z);
    let (mut q, mut q_s) = (z, z);
    let mut w = z;
    for a in (0..OU).rev() {
        let (mut r, mut r_t, mut r_tt2) = (z, z, z);
        for b in (0..OV).rev() {
            r_tt2 = r_tt2 * t + r_t;
            r_t = r_t * t + r;
            r = r * t + cell[a * OV + b];
        }
        p_ss2 = p_ss2 * s + p_s;
        p_s = p_s * s + p;
        p = p * s + r;
        q_s = q_s * s + q;
        q = q * s + r_t;
        w = w * s + r_tt2 * 2.0;
    }
    (p, p_s, q, p_ss2 * 2.0, q_s, w)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wavy() -> BSplineSurface {
        let (cu, cv) = (6, 5);
        let mut control = Vec::new();
        for i in 0..cu {
            for j in 0..cv {
                let (x, z) = (i as f64, j as f64);
                control.push(DVec3::new(
                    x + 0.1 * z,
                    (x * 1.3 + z * 0.7).sin(),
                    z - 0.2 * x,
                ));
            }
        }
        BSplineSurface::new([3, 2], [cu, cv], control).unwrap()
    }

    #[test]
    fn partition_of_unity_and_clamped_corners() {
        let s = wavy();
        for d in 0..2 {
            let k = s.degree[d];
            let knots = s.knots(d);
            for &u in &[0.0, 0.13, 0.5, 0.77, 1.0] {
                let spans = s.spans()[d];
                let sigma = ((u * spans as f64) as usize).min(spans - 1);
                let ders = basis_derivatives(k + sigma, u, k, 2, &knots);
                let sum: f64 = ders[0].iter().sum();
                assert!((sum - 1.0).abs() < 1e-14);
                let dsum: f64 = ders[1].iter().sum();
                assert!(dsum.abs() < 1e-12);
            }
        }
        assert!((s.evaluate(0.0, 0.0) - s.control_point(0, 0).unwrap()).length() < 1e-14);
        assert!((s.evaluate(1.0, 1.0) - s.control_point(5, 4).unwrap()).length() < 1e-14);
    }

    #[test]
    fn patches_match_cox_de_boor_with_derivatives() {
        let s = wavy();
        let patches = Patches::new(s.degree, s.count, &s.control);
        let h = 1e-6;
        for &u in &[0.0, 0.1, 0.3333, 0.5, 0.9, 1.0] {
            for &v in &[0.0, 0.25, 0.61, 1.0] {
                let (p, pu, pv) = s.derivatives(u, v);
                let (q, qu, qv, quu, quv, qvv) = patches.second(u, v);
                assert!((p - q).length() < 1e-12, "value at {u} {v}");
                assert!((pu - qu).length() < 1e-10, "S_u at {u} {v}: {pu} {qu}");
                assert!((pv - qv).length() < 1e-10, "S_v at {u} {v}");
                let (f, fs, ft) = patches.first_local(u, v);
                assert!((f - q).length() < 1e-14);
                assert!((fs * 3.0 - qu).length() < 1e-10);
                assert!((ft * 3.0 - qv).length() < 1e-10);
                assert!((patches.value(u, v) - q).length() < 1e-14);
                // second derivatives by central differences inside the cells
                if (0.05..0.95).contains(&u) && (0.05..0.95).contains(&v) {
                    let (_, au, _) = s.derivatives(u + h, v);
                    let (_, bu, _) = s.derivatives(u - h, v);
                    let (_, _, av) = s.derivatives(u, v + h);
                    let (_, _, bv) = s.derivatives(u, v - h);
                    let (_, cu, _) = s.derivatives(u, v + h);
                    let (_, du, _) = s.derivatives(u, v - h);
                    assert!(((au - bu) / (2.0 * h) - quu).length() < 1e-5);
                    assert!(((av - bv) / (2.0 * h) - qvv).length() < 1e-5);
                    assert!(((cu - du) / (2.0 * h) - quv).length() < 1e-5);
                }
            }
        }
    }

    #[test]
    fn rejects_bad_grids() {
        assert!(BSplineSurface::new([3, 3], [3, 4], vec![DVec3::ZERO; 12]).is_err());
        assert!(BSplineSurface::new([0, 1], [3, 4], vec![DVec3::ZERO; 12]).is_err());
        assert!(BSplineSurface::new([1, 1], [3, 4], vec![DVec3::ZERO; 11]).is_err());
        let mut s = BSplineSurface::new([1, 1], [2, 2], vec![DVec3::ZERO; 4]).unwrap();
        assert!(s.set_control_point(2, 0, DVec3::ZERO).is_err());
        assert!(s.set_control_point(0, 0, DVec3::NAN).is_err());
    }
}
