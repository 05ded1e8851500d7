//! Multilevel B-spline approximation of scattered 2D data with 3-vector values (Lee,
//! Wolberg & Shin 1997, *Scattered data interpolation with multilevel B-splines*), with
//! the continuous scale parameter and the boundary fixing of Lee 1999 (*Interactive
//! multiresolution editing of arbitrary meshes*, §5).
//!
//! # The method
//!
//! The data are points `p_c` in a rectangle `R = [min, max]` with values `z_c ∈ ℝ³` (the
//! three coordinates are fitted together: every weight below is shared). A *control
//! lattice* `Φ` of `(m+3) × (m+3)` control points `φ_ij`, `i, j = −1 … m+1`, overlays `R`
//! with `m × m` cells and defines the uniform cubic B-spline function
//!
//! ```text
//! f(x, y) = Σ_{a,b=0..3} B_a(s) B_b(t) φ_{(i+a−1)(j+b−1)},   i = ⌊x⌋, s = x − i, j = ⌊y⌋, t = y − j
//! ```
//!
//! in lattice coordinates (`x = m (u − min.x) / (max.x − min.x)`, same for `y`).
//!
//! - **B-spline approximation** (one level): each data point asks its 4 × 4 control
//!   points for `φ_c = w_c z_c / Σ_ab w_ab²` (which alone would interpolate it); each
//!   control point takes the `w_c²`-weighted average of the requests it received, and
//!   zero when it received none.
//! - **Multilevel**: levels `k = 1 … l` use lattices with `m_1 = 1`, `m_{k+1} = 2 m_k`;
//!   level `k` approximates the residuals left by the levels before it. The levels are
//!   summed into **one lattice** of the finest size by B-spline refinement (masks
//!   `(1, 6, 1)/8` at old knots and `(1, 1)/2` at new ones, applied along each axis), so
//!   evaluating the fit costs one 4 × 4 lattice lookup whatever the number of levels.
//! - **Scale parameter** `s ∈ [0, 1]` (Lee 1999 §5.2; the definitions implemented here,
//!   in full): `f_k` is
//!   the multilevel fit that *starts* at level `k` (lattices `Φ_k … Φ_l`), `f_{l+1}` is
//!   the function equal to the data values at the data points and zero elsewhere, and
//!   `f_k` belongs to `s_k = (l − k + 1)/l`. Between two `s_k` the two functions are
//!   interpolated linearly: `f_s = (1 − t) f_k + t f_{k+1}` with `t = (s_k − s) l`. Both
//!   lattices end at the finest level, so `f_s` is again one lattice (plus `t` times the
//!   data values at the data points when `k = l`). `s = 1` is the smoothest fit, `s = 0`
//!   touches the data points only.
//! - **Boundary fixing** (Lee 1999 §5.3): the control points of the finest lattice in
//!   rows and columns `−1, 0, 1, m_l − 1, m_l, m_l + 1` are set to zero, so the function,
//!   its first and its second derivatives vanish on the border of `R`. The fit then no
//!   longer interpolates data near the border. With fewer than 3 levels every control
//!   point is on the border and the function is zero.
//! - **Base** (optional, not in Lee 1999): the fit can start from the data's mean or
//!   least-squares plane and approximate the residuals, as the `mba` libraries of Hjelle
//!   (SINTEF) and Demidov do. Constants (and planes) are then reproduced exactly
//!   everywhere. Editing needs the zero base (offsets vanish away from the primitive), and
//!   a non-zero base cannot be combined with boundary fixing.
//!
//! # Speed
//!
//! The fit touches only the data points' control points (sparse per level) plus one dense
//! refinement pass per level; evaluation is 16 lattice reads per point.
//!
//! The editing session ([`AreaSession`](crate::lee::AreaSession)) uses the same B-splines and
//! refinement in a form of its own: boundary fixing at every level, a scale mapping that
//! does not depend on the level count, and sparse detail levels at the primitive (see
//! its docs). This type keeps the paper's literal §5.2–5.3.

use glam::{DVec2, DVec3};

use crate::lee::error::{LeeError, Result};

/// Largest number of levels accepted: the finest lattice then has `(2^11 + 3)²`
/// control points (about 4.2 million, 101 MB of `DVec3`), and an editing session's drag
/// holds about 2.5 such lattices: a session stays within about 250 MB. (Level 14, the
/// limit before, made one drag allocate 6.4 GB.) Far beyond any editing area: two
/// vertices per finest cell is a four-million-vertex area.
///
/// Paper: Lee, Wolberg & Shin 1997, *Scattered data interpolation with multilevel
/// B-splines*.
pub const MAX_LEVELS: usize = 12;

/// The four uniform cubic B-spline basis functions `B_0 … B_3` at `t ∈ [0, 1]`
/// (Lee, Wolberg & Shin 1997, eq. 2). They are non-negative and sum to 1.
#[inline]
#[must_use]
pub fn cubic_bspline_weights(t: f64) -> [f64; 4] {
    let t2 = t * t;
    let t3 = t2 * t;
    let u = 1.0 - t;
    [
        u * u * u / 6.0,
        (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0,
        (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0,
        t3 / 6.0,
    ]
}

/// Lattice size parameter `m_k = 2^{k−1}` of level `k` (Lee 1999, §5.2: `m_1 = 1`,
/// `m_{k+1} = 2 m_k`).
#[inline]
#[must_use]
pub const fn level_size(k: usize) -> usize {
    1 << (k - 1)
}

/// Where a point falls in a control lattice: the storage index of its first control point
/// and the B-spline weights along each axis. Computing it once per point lets repeated
/// evaluations (every drag of an editing session) skip the division and the cubic.
///
/// Paper: Lee, Wolberg & Shin 1997, *Scattered data interpolation with multilevel
/// B-splines*.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LatticeBasis {
    /// Storage index of control point `(i − 1, j − 1)`; the 4 × 4 block starts here.
    pub base: u32,
    /// Weights along u (`B_0(s) … B_3(s)`).
    pub wu: [f64; 4],
    /// Weights along v (`B_0(t) … B_3(t)`).
    pub wv: [f64; 4],
}

impl LatticeBasis {
    /// The basis of point `p` in a lattice with `m × m` cells over `[min, max]`. Points
    /// outside the rectangle are clamped onto it; `m = 0` is taken as 1.
    #[must_use]
    pub fn locate(p: DVec2, min: DVec2, max: DVec2, m: usize) -> Self {
        let m = m.max(1);
        let n = m + 3;
        let extent = (max - min).max(DVec2::splat(f64::MIN_POSITIVE));
        let x = ((p.x - min.x) / extent.x).clamp(0.0, 1.0) * m as f64;
        let y = ((p.y - min.y) / extent.y).clamp(0.0, 1.0) * m as f64;
        let i = (x.floor() as usize).min(m - 1);
        let j = (y.floor() as usize).min(m - 1);
        let s = (x - i as f64).clamp(0.0, 1.0);
        let t = (y - j as f64).clamp(0.0, 1.0);
        Self {
            base: (j * n + i) as u32,
            wu: cubic_bspline_weights(s),
            wv: cubic_bspline_weights(t),
        }
    }

    /// Evaluates the lattice `phi` (row length `n = m + 3`) at this basis; `None` when
    /// the basis's 4 × 4 block does not lie in `phi`.
    #[must_use]
    pub fn evaluate(&self, phi: &[DVec3], n: usize) -> Option<DVec3> {
        let base = self.base as usize;
        let last = base.checked_add(n.checked_mul(3)?)?.checked_add(4)?;
        (n >= 4 && last <= phi.len()).then(|| self.evaluate_unchecked(phi, n))
    }

    /// [`evaluate`](Self::evaluate) for a basis known to fit the lattice.
    #[inline]
    pub(crate) fn evaluate_unchecked(&self, phi: &[DVec3], n: usize) -> DVec3 {
        let mut sum = DVec3::ZERO;
        let base = self.base as usize;
        for b in 0..4 {
            let row = &phi[base + b * n..base + b * n + 4];
            let r = row[0] * self.wu[0]
                + row[1] * self.wu[1]
                + row[2] * self.wu[2]
                + row[3] * self.wu[3];
            sum += r * self.wv[b];
        }
        sum
    }
}

/// A control lattice of `(m+3) × (m+3)` 3-vector control points over a rectangle: one
/// uniform cubic B-spline function `R → ℝ³` (Lee, Wolberg & Shin 1997, §3).
#[derive(Clone, Debug, PartialEq)]
pub struct ControlLattice {
    m: usize,
    min: DVec2,
    max: DVec2,
    phi: Vec<DVec3>,
}

impl ControlLattice {
    /// The zero lattice with `m × m` cells over `[min, max]`.
    ///
    /// # Errors
    /// [`LeeError::InvalidParameter`] unless `1 ≤ m ≤ 2^(MAX_LEVELS − 1)` (the finest
    /// lattice of [`MAX_LEVELS`]).
    pub fn zeros(m: usize, min: DVec2, max: DVec2) -> Result<Self> {
        check_cells(m)?;
        Ok(Self {
            m,
            min,
            max,
            phi: vec![DVec3::ZERO; (m + 3) * (m + 3)],
        })
    }

    /// Number of cells along each axis.
    #[must_use]
    pub fn m(&self) -> usize {
        self.m
    }

    /// The rectangle `(min, max)` the lattice covers.
    #[must_use]
    pub fn domain(&self) -> (DVec2, DVec2) {
        (self.min, self.max)
    }

    /// Control point `φ_ij`, `i` along u and `j` along v, both in `−1 ..= m+1`; `None`
    /// outside.
    #[must_use]
    pub fn control_point(&self, i: isize, j: isize) -> Option<DVec3> {
        let n = self.m as isize + 3;
        ((-1..n - 1).contains(&i) && (-1..n - 1).contains(&j))
            .then(|| self.phi[((j + 1) * n + i + 1) as usize])
    }

    /// All control points, row by row along v: `φ_ij` is at `(j+1)(m+3) + i + 1`.
    #[must_use]
    pub fn control_points(&self) -> &[DVec3] {
        &self.phi
    }

    /// The value of the B-spline function at `p` (clamped onto the rectangle).
    #[must_use]
    pub fn evaluate(&self, p: DVec2) -> DVec3 {
        LatticeBasis::locate(p, self.min, self.max, self.m)
            .evaluate_unchecked(&self.phi, self.m + 3)
    }

    /// The same function on the lattice with twice as many cells along each axis
    /// (B-spline refinement, Lee, Wolberg & Shin 1997, §4.2).
    ///
    /// # Errors
    /// [`LeeError::InvalidParameter`] when the refined lattice would be finer than the
    /// finest of [`MAX_LEVELS`] (see [`ControlLattice::zeros`]).
    pub fn refined(&self) -> Result<Self> {
        check_cells(2 * self.m)?;
        let mut out = Vec::new();
        let mut scratch = Vec::new();
        refine(&self.phi, self.m, &mut out, &mut scratch);
        Ok(Self {
            m: 2 * self.m,
            min: self.min,
            max: self.max,
            phi: out,
        })
    }

    /// Zeroes the control points of the three border rows and columns on each side
    /// (Lee 1999, §5.3): the function then vanishes on the border of the rectangle.
    pub fn zero_border(&mut self) {
        zero_border(&mut self.phi, self.m);
    }
}

/// `Ok` for a lattice of `1 ..= 2^(MAX_LEVELS − 1)` cells per axis.
fn check_cells(m: usize) -> Result<()> {
    if !(1..=level_size(MAX_LEVELS)).contains(&m) {
        return Err(LeeError::InvalidParameter {
            name: "m",
            reason: format!(
                "a lattice of {m} cells per axis (needs 1..={}, the finest of {MAX_LEVELS} levels)",
                level_size(MAX_LEVELS)
            ),
        });
    }
    Ok(())
}

/// Refines the lattice `src` with `m` cells into `dst` with `2m` cells (separable
/// B-spline subdivision); `scratch` is reused between calls.
pub(crate) fn refine(src: &[DVec3], m: usize, dst: &mut Vec<DVec3>, scratch: &mut Vec<DVec3>) {
    let nc = m + 3;
    let nf = 2 * m + 3;
    debug_assert_eq!(src.len(), nc * nc);
    // Along u: nc rows of nc → nc rows of nf.
    scratch.clear();
    scratch.resize(nc * nf, DVec3::ZERO);
    for (row_in, row_out) in src.chunks_exact(nc).zip(scratch.chunks_exact_mut(nf)) {
        refine_1d(row_in, row_out);
    }
    // Along v: for each fine column, nc coarse entries → nf fine entries.
    dst.clear();
    dst.resize(nf * nf, DVec3::ZERO);
    for i in 0..=m {
        // fine row 2i+1 (old knot) from coarse rows i, i+1, i+2
        let (a, b, c) = (
            &scratch[i * nf..],
            &scratch[(i + 1) * nf..],
            &scratch[(i + 2) * nf..],
        );
        let out = &mut dst[(2 * i + 1) * nf..(2 * i + 2) * nf];
        for x in 0..nf {
            out[x] = (a[x] + 6.0 * b[x] + c[x]) * 0.125;
        }
    }
    for i in 0..=m + 1 {
        // fine row 2i (new knot) from coarse rows i, i+1
        let (a, b) = (&scratch[i * nf..], &scratch[(i + 1) * nf..]);
        let out = &mut dst[2 * i * nf..(2 * i + 1) * nf];
        for x in 0..nf {
            out[x] = (a[x] + b[x]) * 0.5;
        }
    }
}

/// One-dimensional refinement of `c` (`m+3` entries) into `f` (`2m+3` entries).
#[inline]
fn refine_1d(c: &[DVec3], f: &mut [DVec3]) {
    let m = c.len() - 3;
    for i in 0..=m {
        f[2 * i + 1] = (c[i] + 6.0 * c[i + 1] + c[i + 2]) * 0.125;
    }
    for i in 0..=m + 1 {
        f[2 * i] = (c[i] + c[i + 1]) * 0.5;
    }
}

/// Zeroes rows and columns `−1, 0, 1, m−1, m, m+1` (storage `0, 1, 2, m, m+1, m+2`).
pub(crate) fn zero_border(phi: &mut [DVec3], m: usize) {
    let n = m + 3;
    let is_border = |k: usize| k <= 2 || k >= m;
    for j in 0..n {
        let row = &mut phi[j * n..(j + 1) * n];
        if is_border(j) {
            row.fill(DVec3::ZERO);
        } else {
            for (i, p) in row.iter_mut().enumerate() {
                if is_border(i) {
                    *p = DVec3::ZERO;
                }
            }
        }
    }
}

/// Which function a scale value `s` selects: `f_s = (1 − t) f_k + t f_{k+1}` (Lee 1999
/// §5.2), with `k = l + 1` meaning the data-only function `f_{l+1}` (`s = 0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScaleSplit {
    /// The coarser function's index `k ∈ 1 ..= l + 1`.
    pub k: usize,
    /// The weight `t ∈ [0, 1)` of `f_{k+1}`.
    pub t: f64,
}

impl ScaleSplit {
    /// Splits `s ∈ [0, 1]` for `levels` levels: `s_k = (l − k + 1)/l`, `t = (s_k − s) l`.
    /// Values within `1e-12` of an `s_k` snap to it.
    #[must_use]
    pub fn new(s: f64, levels: usize) -> Self {
        let l = levels as f64;
        let mut x = (1.0 - s.clamp(0.0, 1.0)) * l;
        if (x - x.round()).abs() < 1e-12 {
            x = x.round();
        }
        let k = (x.floor() as usize).min(levels) + 1;
        let t = if k == levels + 1 {
            0.0
        } else {
            x - (k - 1) as f64
        };
        Self { k, t }
    }

    /// Weight of the data-only function `f_{l+1}` (non-zero only on the last interval).
    #[must_use]
    pub fn data_weight(&self, levels: usize) -> f64 {
        if self.k == levels + 1 {
            1.0
        } else if self.k == levels {
            self.t
        } else {
            0.0
        }
    }
}

/// Reusable buffers of the multilevel fit (one per editing session).
#[derive(Clone, Debug, Default)]
pub(crate) struct FitWorkspace {
    delta: Vec<DVec3>,
    omega: Vec<f64>,
    level_phi: Vec<DVec3>,
    touched: Vec<u32>,
    residual_a: Vec<DVec3>,
    residual_b: Vec<DVec3>,
    scratch: Vec<DVec3>,
    refined: Vec<DVec3>,
}

/// Bases of every data point at every level, level-major: `bases[(k−1)·P + c]`.
pub(crate) fn point_bases(
    points: &[DVec2],
    min: DVec2,
    max: DVec2,
    levels: usize,
) -> Vec<LatticeBasis> {
    let mut bases = Vec::with_capacity(points.len() * levels);
    for k in 1..=levels {
        let m = level_size(k);
        bases.extend(points.iter().map(|&p| LatticeBasis::locate(p, min, max, m)));
    }
    bases
}

impl FitWorkspace {
    /// Computes the finest-level lattice of `(1 − t) Ψ_k + t Ψ_{k+1}` into `out`, where
    /// `Ψ_j` is the multilevel fit over levels `j ..= levels` refined into one lattice
    /// and `Ψ_{levels+1} = 0` (the data-only part of `f_{l+1}` is the caller's).
    /// `bases` is level-major (see [`point_bases`]). Border rows and columns are zeroed
    /// when `fixed_boundary`.
    pub(crate) fn fit(
        &mut self,
        levels: usize,
        split: ScaleSplit,
        bases: &[LatticeBasis],
        values: &[DVec3],
        fixed_boundary: bool,
        out: &mut Vec<DVec3>,
    ) {
        let p = values.len();
        let nl = level_size(levels) + 3;
        out.clear();
        if split.k > levels {
            out.resize(nl * nl, DVec3::ZERO);
            return;
        }
        if self.omega.len() < nl * nl {
            self.delta.resize(nl * nl, DVec3::ZERO);
            self.omega.resize(nl * nl, 0.0);
            self.level_phi.resize(nl * nl, DVec3::ZERO);
        }
        let wa = 1.0 - split.t;
        let wb = if split.k < levels { split.t } else { 0.0 };
        self.residual_a.clear();
        self.residual_a.extend_from_slice(values);
        self.residual_b.clear();
        if wb > 0.0 {
            self.residual_b.extend_from_slice(values);
        }
        let k = split.k;
        let n0 = level_size(k) + 3;
        out.resize(n0 * n0, DVec3::ZERO);
        for j in k..=levels {
            let m = level_size(j);
            let n = m + 3;
            if j > k {
                refine(out, m / 2, &mut self.refined, &mut self.scratch);
                std::mem::swap(out, &mut self.refined);
            }
            let level_bases = &bases[(j - 1) * p..j * p];
            let last = j == levels;
            let mut residual = std::mem::take(&mut self.residual_a);
            self.approximate_level(level_bases, &mut residual, n, wa, last, out);
            self.residual_a = residual;
            if wb > 0.0 && j > k {
                let mut residual = std::mem::take(&mut self.residual_b);
                self.approximate_level(level_bases, &mut residual, n, wb, last, out);
                self.residual_b = residual;
            }
        }
        if fixed_boundary {
            zero_border(out, level_size(levels));
        }
    }

    /// One level of B-spline approximation of `residual` (Lee, Wolberg & Shin 1997,
    /// §3.2): adds `weight · Φ` into `acc` and, unless `last`, subtracts `Φ`'s values at
    /// the data points from `residual`. Only touched control points are visited.
    fn approximate_level(
        &mut self,
        bases: &[LatticeBasis],
        residual: &mut [DVec3],
        n: usize,
        weight: f64,
        last: bool,
        acc: &mut [DVec3],
    ) {
        for (b, &z) in bases.iter().zip(residual.iter()) {
            let mut w = [[0.0; 4]; 4];
            let mut sum2 = 0.0;
            for (bv, row) in w.iter_mut().enumerate() {
                for (bu, x) in row.iter_mut().enumerate() {
                    *x = b.wu[bu] * b.wv[bv];
                    sum2 += *x * *x;
                }
            }
            let base = b.base as usize;
            for (bv, row) in w.iter().enumerate() {
                for (bu, &x) in row.iter().enumerate() {
                    let w2 = x * x;
                    if w2 == 0.0 {
                        continue;
                    }
                    let idx = base + bv * n + bu;
                    if self.omega[idx] == 0.0 {
                        self.touched.push(idx as u32);
                    }
                    // w² · φ_c with φ_c = w z / Σ w²
                    self.delta[idx] += z * (w2 * x / sum2);
                    self.omega[idx] += w2;
                }
            }
        }
        for &idx in &self.touched {
            let idx = idx as usize;
            let phi = self.delta[idx] / self.omega[idx];
            self.level_phi[idx] = phi;
            acc[idx] += phi * weight;
        }
        if !last {
            for (b, r) in bases.iter().zip(residual.iter_mut()) {
                *r -= b.evaluate_unchecked(&self.level_phi, n);
            }
        }
        for &idx in &self.touched {
            let idx = idx as usize;
            self.delta[idx] = DVec3::ZERO;
            self.omega[idx] = 0.0;
            self.level_phi[idx] = DVec3::ZERO;
        }
        self.touched.clear();
    }
}

/// The function the fit starts from, before the B-spline levels (not part of Lee 1999;
/// see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MbaBase {
    /// Start from zero (Lee 1999; needed for editing and for boundary fixing).
    #[default]
    Zero,
    /// Start from the mean of the values: constants are reproduced exactly.
    Mean,
    /// Start from the least-squares plane `a + b u + c v` (per coordinate): planes are
    /// reproduced exactly. Falls back to the mean when the points are collinear.
    Plane,
}

/// Multilevel B-spline approximation over a rectangle (Lee, Wolberg & Shin 1997) with
/// 3-vector values, levels `m_1 = 1`, `m_{k+1} = 2 m_k`, the continuous scale parameter
/// and the boundary fixing of Lee 1999 §5. Usable for any scattered 2D data.
///
/// ```
/// use edit::lee::mba::Mba;
/// use glam::{DVec2, DVec3};
/// let mba = Mba::new(DVec2::ZERO, DVec2::ONE, 6).unwrap();
/// let points = [DVec2::new(0.3, 0.4), DVec2::new(0.7, 0.6)];
/// let values = [DVec3::X, DVec3::Y];
/// let f = mba.fit(&points, &values).unwrap();
/// assert!((f.evaluate(points[0]) - values[0]).length() < 1e-2);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Mba {
    min: DVec2,
    max: DVec2,
    levels: usize,
    fixed_boundary: bool,
    base: MbaBase,
}

impl Mba {
    /// A multilevel fit over the rectangle `[min, max]` with `levels` levels (finest
    /// lattice `m_l = 2^{l−1}`), no boundary fixing, zero base.
    ///
    /// # Errors
    /// [`LeeError::InvalidParameter`] for a degenerate or non-finite rectangle or
    /// `levels` outside `1 ..= MAX_LEVELS`.
    pub fn new(min: DVec2, max: DVec2, levels: usize) -> Result<Self> {
        if !(min.is_finite() && max.is_finite() && max.x > min.x && max.y > min.y) {
            return Err(LeeError::InvalidParameter {
                name: "domain",
                reason: format!("the rectangle {min}..{max} must be finite and non-empty"),
            });
        }
        if !(1..=MAX_LEVELS).contains(&levels) {
            return Err(LeeError::InvalidParameter {
                name: "levels",
                reason: format!("{levels} is outside 1..={MAX_LEVELS}"),
            });
        }
        Ok(Self {
            min,
            max,
            levels,
            fixed_boundary: false,
            base: MbaBase::Zero,
        })
    }

    /// Fixes the border (Lee 1999 §5.3): the finest lattice's three border rows and
    /// columns on each side are zeroed.
    #[must_use]
    pub fn with_fixed_boundary(mut self, fixed: bool) -> Self {
        self.fixed_boundary = fixed;
        self
    }

    /// Sets the base function the levels start from (default [`MbaBase::Zero`]).
    #[must_use]
    pub fn with_base(mut self, base: MbaBase) -> Self {
        self.base = base;
        self
    }

    /// Number of levels `l`.
    #[must_use]
    pub fn levels(&self) -> usize {
        self.levels
    }

    /// The rectangle `(min, max)`.
    #[must_use]
    pub fn domain(&self) -> (DVec2, DVec2) {
        (self.min, self.max)
    }

    /// The scale value `s_k = (l − k + 1)/l` that selects `f_k` alone (Lee 1999 §5.2).
    #[must_use]
    pub fn scale_of_level(&self, k: usize) -> f64 {
        (self.levels as f64 - k as f64 + 1.0) / self.levels as f64
    }

    /// The full multilevel fit `f_1` (all levels, scale `s = 1`).
    ///
    /// # Errors
    /// See [`fit_scaled`](Self::fit_scaled).
    pub fn fit(&self, points: &[DVec2], values: &[DVec3]) -> Result<MbaFit> {
        self.fit_scaled(1.0, points, values)
    }

    /// The fit `f_k` over levels `k ..= l` only (`k = l + 1`: the data-only function).
    ///
    /// # Errors
    /// [`LeeError::InvalidParameter`] for `k` outside `1 ..= l+1`; see
    /// [`fit_scaled`](Self::fit_scaled) for the data.
    pub fn fit_from_level(&self, k: usize, points: &[DVec2], values: &[DVec3]) -> Result<MbaFit> {
        if !(1..=self.levels + 1).contains(&k) {
            return Err(LeeError::InvalidParameter {
                name: "k",
                reason: format!("level {k} is outside 1..={}", self.levels + 1),
            });
        }
        self.fit_split(ScaleSplit { k, t: 0.0 }, points, values)
    }

    /// The function `f_s` of the continuous scale parameter `s ∈ [0, 1]` (Lee 1999 §5.2).
    ///
    /// # Errors
    /// [`LeeError::InvalidParameter`] for `s` outside `[0, 1]` or a non-zero base with
    /// boundary fixing; [`LeeError::MbaLengthMismatch`], [`LeeError::MbaNonFiniteData`],
    /// [`LeeError::MbaPointOutsideDomain`] for bad data.
    pub fn fit_scaled(&self, s: f64, points: &[DVec2], values: &[DVec3]) -> Result<MbaFit> {
        if !(0.0..=1.0).contains(&s) {
            return Err(LeeError::InvalidParameter {
                name: "s",
                reason: format!("the scale {s} is outside [0, 1]"),
            });
        }
        self.fit_split(ScaleSplit::new(s, self.levels), points, values)
    }

    fn fit_split(&self, split: ScaleSplit, points: &[DVec2], values: &[DVec3]) -> Result<MbaFit> {
        self.check_data(points, values)?;
        if self.fixed_boundary && self.base != MbaBase::Zero {
            return Err(LeeError::InvalidParameter {
                name: "base",
                reason: "a non-zero base cannot be combined with boundary fixing".into(),
            });
        }
        let base = BasePlane::fit(self.base, points, values);
        let residuals: Vec<DVec3> = points
            .iter()
            .zip(values)
            .map(|(&p, &z)| z - base.evaluate(p))
            .collect();
        let bases = point_bases(points, self.min, self.max, self.levels);
        let mut phi = Vec::new();
        FitWorkspace::default().fit(
            self.levels,
            split,
            &bases,
            &residuals,
            self.fixed_boundary,
            &mut phi,
        );
        if let Some(p) = phi
            .iter()
            .chain([&base.a, &base.b, &base.c])
            .find(|p| !p.is_finite())
        {
            return Err(LeeError::FitOverflow { value: *p });
        }
        let data_weight = split.data_weight(self.levels);
        // f_{l+1} carries the data values themselves, without the base.
        let base_weight = if split.k > self.levels {
            0.0
        } else {
            1.0 - data_weight
        };
        Ok(MbaFit {
            lattice: ControlLattice {
                m: level_size(self.levels),
                min: self.min,
                max: self.max,
                phi,
            },
            base: base.scaled(base_weight),
            data_weight,
            points: points.to_vec(),
            values: values.to_vec(),
        })
    }

    fn check_data(&self, points: &[DVec2], values: &[DVec3]) -> Result<()> {
        if points.len() != values.len() {
            return Err(LeeError::MbaLengthMismatch {
                points: points.len(),
                values: values.len(),
            });
        }
        let tol = 1e-9 * (self.max - self.min);
        for (index, (p, z)) in points.iter().zip(values).enumerate() {
            if !(p.is_finite() && z.is_finite()) {
                return Err(LeeError::MbaNonFiniteData { index });
            }
            if p.cmplt(self.min - tol).any() || p.cmpgt(self.max + tol).any() {
                return Err(LeeError::MbaPointOutsideDomain {
                    index,
                    point: *p,
                    min: self.min,
                    max: self.max,
                });
            }
        }
        Ok(())
    }
}

/// `a + b u + c v` per coordinate.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct BasePlane {
    a: DVec3,
    b: DVec3,
    c: DVec3,
}

impl BasePlane {
    fn fit(kind: MbaBase, points: &[DVec2], values: &[DVec3]) -> Self {
        if kind == MbaBase::Zero || points.is_empty() {
            return Self::default();
        }
        let n = points.len() as f64;
        let mean_p = points.iter().copied().sum::<DVec2>() / n;
        let mean_z = values.iter().copied().sum::<DVec3>() / n;
        if kind == MbaBase::Mean {
            return Self {
                a: mean_z,
                ..Self::default()
            };
        }
        // Centred normal equations: [suu suv; suv svv] [b c]ᵀ = [suz svz]ᵀ.
        let (mut suu, mut suv, mut svv) = (0.0, 0.0, 0.0);
        let (mut suz, mut svz) = (DVec3::ZERO, DVec3::ZERO);
        for (p, z) in points.iter().zip(values) {
            let d = *p - mean_p;
            let dz = *z - mean_z;
            suu += d.x * d.x;
            suv += d.x * d.y;
            svv += d.y * d.y;
            suz += dz * d.x;
            svz += dz * d.y;
        }
        let det = suu * svv - suv * suv;
        if det <= 1e-12 * (suu * svv).max(f64::MIN_POSITIVE) {
            return Self {
                a: mean_z,
                ..Self::default()
            };
        }
        let b = (suz * svv - svz * suv) / det;
        let c = (svz * suu - suz * suv) / det;
        Self {
            a: mean_z - b * mean_p.x - c * mean_p.y,
            b,
            c,
        }
    }

    fn evaluate(&self, p: DVec2) -> DVec3 {
        self.a + self.b * p.x + self.c * p.y
    }

    fn scaled(self, w: f64) -> Self {
        Self {
            a: self.a * w,
            b: self.b * w,
            c: self.c * w,
        }
    }
}

/// A fitted multilevel B-spline function: a base, one control lattice of the finest level
/// and, on the last scale interval, a weight on the data-only function `f_{l+1}`.
///
/// Paper: Lee, Wolberg & Shin 1997, *Scattered data interpolation with multilevel
/// B-splines*.
#[derive(Clone, Debug, PartialEq)]
pub struct MbaFit {
    lattice: ControlLattice,
    base: BasePlane,
    data_weight: f64,
    points: Vec<DVec2>,
    values: Vec<DVec3>,
}

impl MbaFit {
    /// The value at `p`. At a data point (bitwise equal coordinates, the first such point)
    /// the data-only part `data_weight · z_c` is added.
    #[must_use]
    pub fn evaluate(&self, p: DVec2) -> DVec3 {
        let smooth = self.base.evaluate(p) + self.lattice.evaluate(p);
        if self.data_weight == 0.0 {
            return smooth;
        }
        match self.points.iter().position(|&q| q == p) {
            Some(c) => smooth + self.values[c] * self.data_weight,
            None => smooth,
        }
    }

    /// The value at data point `c` (with its data-only part); `None` when `c` is not a
    /// data point index.
    #[must_use]
    pub fn evaluate_data_point(&self, c: usize) -> Option<DVec3> {
        let p = *self.points.get(c)?;
        Some(self.base.evaluate(p) + self.lattice.evaluate(p) + self.values[c] * self.data_weight)
    }

    /// The control lattice of the finest level (all levels refined into one).
    #[must_use]
    pub fn lattice(&self) -> &ControlLattice {
        &self.lattice
    }

    /// The weight of the data-only function `f_{l+1}` (0 unless `s < 1/l`).
    #[must_use]
    pub fn data_weight(&self) -> f64 {
        self.data_weight
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_a_partition_of_unity() {
        for t in [0.0, 0.25, 0.5, 0.9, 1.0] {
            let w = cubic_bspline_weights(t);
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-15);
            assert!(w.iter().all(|&x| x >= 0.0));
        }
    }

    #[test]
    fn refinement_preserves_the_function() {
        let mut lattice = ControlLattice::zeros(4, DVec2::ZERO, DVec2::new(2.0, 1.0)).unwrap();
        for (i, p) in lattice.phi.iter_mut().enumerate() {
            *p = DVec3::new((i as f64 * 0.37).sin(), (i * i % 7) as f64, i as f64 * 0.1);
        }
        let fine = lattice.refined().unwrap();
        assert_eq!(fine.m(), 8);
        for k in 0..50 {
            let p = DVec2::new(
                2.0 * ((k as f64) * 0.618).fract(),
                ((k as f64) * 0.377).fract(),
            );
            assert!((lattice.evaluate(p) - fine.evaluate(p)).length() < 1e-12);
        }
    }

    #[test]
    fn scale_split_follows_lee() {
        // l = 6: s = 2/3 ↔ f_3, 1/2 ↔ f_4, 7/12 halfway.
        assert_eq!(ScaleSplit::new(2.0 / 3.0, 6), ScaleSplit { k: 3, t: 0.0 });
        assert_eq!(ScaleSplit::new(0.5, 6), ScaleSplit { k: 4, t: 0.0 });
        let s = ScaleSplit::new(7.0 / 12.0, 6);
        assert_eq!(s.k, 3);
        assert!((s.t - 0.5).abs() < 1e-12);
        assert_eq!(ScaleSplit::new(1.0, 6), ScaleSplit { k: 1, t: 0.0 });
        assert_eq!(ScaleSplit::new(0.0, 6), ScaleSplit { k: 7, t: 0.0 });
        assert_eq!(ScaleSplit::new(0.0, 6).data_weight(6), 1.0);
        assert!((ScaleSplit::new(0.1, 6).data_weight(6) - 0.4).abs() < 1e-12);
    }

    #[test]
    fn zero_border_leaves_the_function_zero_on_the_border() {
        let mut lattice = ControlLattice::zeros(8, DVec2::ZERO, DVec2::ONE).unwrap();
        lattice.phi.fill(DVec3::ONE);
        lattice.zero_border();
        for k in 0..=20 {
            let x = k as f64 / 20.0;
            for p in [
                DVec2::new(x, 0.0),
                DVec2::new(x, 1.0),
                DVec2::new(0.0, x),
                DVec2::new(1.0, x),
            ] {
                assert_eq!(lattice.evaluate(p), DVec3::ZERO, "at {p}");
            }
        }
        assert!(lattice.evaluate(DVec2::splat(0.5)).x > 0.9);
    }
}
