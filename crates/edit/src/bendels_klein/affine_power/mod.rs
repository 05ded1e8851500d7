//! Matrix exponential and logarithm of 4×4 affine transforms, and Alexa's scalar
//! multiple of a transform `α ⊙ A = exp(α log A)` (Alexa 2002, *Linear combination of
//! transformations*; used by Bendels & Klein, Sec. 3, to spread the handle transform over
//! the deformable area).
//!
//! - [`exp`]: Padé approximants of degree 3, 5, 7, 9 or 13 with scaling and squaring
//!   (Higham 2005, *The scaling and squaring method for the matrix exponential
//!   revisited*, Algorithm 2.3), for any 4×4 matrix.
//! - [`log`]: inverse scaling and squaring (Kenney & Laub; Higham 2001): take square
//!   roots of the linear part by the Denman–Beavers iteration (product form with
//!   determinant scaling) until `‖X − I‖₁ ≤ 0.3`, then the [8/8] Padé approximant of
//!   `log(I + Y)` in partial fractions (Gauss–Legendre nodes), times `2^k`; the
//!   translation part follows in closed form. Only for affine matrices whose
//!   linear part has no eigenvalue on the closed negative real axis: a reflection
//!   (`det < 0`), a singular matrix or a negative real eigenvalue (a half turn, or a
//!   pair like `diag(−1, −2, 3)`) has no real principal logarithm, and is refused with
//!   [`BendelsKleinError::NoRealLogarithm`] and the reason.
//! - [`scalar_power`]: `α ⊙ A`, with `0 ⊙ A = I` and `1 ⊙ A = A` exactly.
//! - [`AffinePower`]: the per-vertex evaluator. An edit computes `log A` once; every
//!   deformable vertex then needs `exp(α L)` for its own α ∈ [0, 1]. Since α is a
//!   scalar and `L` is fixed, `α ↦ exp(α L)` is an entire matrix-valued function of one
//!   variable: [`AffinePower`] splits [0, 1] into `P` pieces and stores, for each piece
//!   centred at `c`, the Taylor coefficients `exp(c L) Lᵏ / k!` (each `exp(c L)` by
//!   Padé). A vertex then costs one Horner evaluation of a 3×4 matrix polynomial in
//!   `α − c` (about ten steps of twelve multiply-adds) instead of a Padé
//!   exponential with matrix inversions: see the `blend` bench for both timings. `P`
//!   and the order are chosen from `‖L‖` so that the truncation error is below 1e-16
//!   relative, i.e. the result agrees with the Padé exponential to rounding.

mod matrix;

use glam::{DMat3, DMat4, DVec2, DVec3, DVec4};

use crate::bendels_klein::error::{BendelsKleinError, Result, TransformOverflow};

use matrix::{affine, is_finite, norm1_3};
pub use matrix::{exp, log, norm1, sqrt_denman_beavers};

/// Alexa's scalar multiple `α ⊙ A = exp(α log A)` (Alexa 2002; Bendels & Klein, Sec. 3):
/// `0 ⊙ A = I` and `1 ⊙ A = A` exactly, `(½ ⊙ A)² = A`. For many α with the same `A`
/// use [`AffinePower`].
///
/// # Errors
/// As [`log`]; [`BendelsKleinError::InvalidParameter`] for a non-finite α, and
/// [`BendelsKleinError::TransformOverflow`] when `α ⊙ A` does not fit in f64 (a large α of a large
/// transform).
pub fn scalar_power(alpha: f64, a: DMat4) -> Result<DMat4> {
    if !alpha.is_finite() {
        return Err(BendelsKleinError::InvalidParameter {
            name: "alpha",
            reason: format!("{alpha} is not finite"),
        });
    }
    let m = AffinePower::new(a)?.matrix(alpha);
    if !is_finite(&m) {
        return Err(BendelsKleinError::TransformOverflow(
            TransformOverflow::Power { alpha },
        ));
    }
    Ok(m)
}

/// `α ⊙ A` for one transform `A` and many α ∈ [0, 1]: `log A` computed once, then a
/// piecewise Taylor table in α (see the module docs). Bendels & Klein's per-vertex
/// transform of the deformable area.
#[derive(Clone, Debug)]
pub struct AffinePower {
    a: DMat4,
    log: DMat4,
    pieces: usize,
    order: usize,
    /// `pieces × order` coefficient blocks, each the top three rows of
    /// `exp(c_j L) Lᵏ / k!`, row-major (12 values).
    coefficients: Vec<[f64; 12]>,
}

fn top_rows(m: &DMat4) -> [f64; 12] {
    let (r0, r1, r2) = (m.row(0), m.row(1), m.row(2));
    [
        r0.x, r0.y, r0.z, r0.w, r1.x, r1.y, r1.z, r1.w, r2.x, r2.y, r2.z, r2.w,
    ]
}

impl AffinePower {
    /// Prepares `α ⊙ A` for the affine transform `a`: computes `log A` and the tables.
    ///
    /// # Errors
    /// As [`log`].
    pub fn new(a: DMat4) -> Result<Self> {
        let a = affine(&a)?;
        let log = log(a)?;
        Ok(Self::from_log(a, log))
    }

    /// Builds the tables from a transform and its logarithm (no checks: `log` must be
    /// `log(a)` with a zero bottom row).
    #[must_use]
    pub fn from_log(a: DMat4, log: DMat4) -> Self {
        // Convergence is governed by the linear block B of L: Lᵏ = [Bᵏ, Bᵏ⁻¹c].
        let rho = norm1_3(&DMat3::from_mat4(log));
        // Many short pieces (ρh ≤ 1/64) keep the order low: 7 terms reach 1e-16 where
        // 4 pieces per unit of ρ need 11. The table stays small (≤ 1024 pieces of
        // order × 96 bytes) and the pieces are visited coherently (α is smooth).
        let pieces = ((32.0 * rho).ceil() as usize).clamp(1, 1024);
        let h = 0.5 / pieces as f64; // half-width of a piece
        let x = rho * h;
        let mut order = 2;
        let mut term = x * x / 2.0;
        while term > 1e-16 && order < 40 {
            order += 1;
            term *= x / order as f64;
        }
        // Lᵏ / k!
        let mut powers = Vec::with_capacity(order);
        let mut p = DMat4::IDENTITY;
        for k in 0..order {
            if k > 0 {
                p = p * log * (1.0 / k as f64);
            }
            powers.push(p);
        }
        let mut coefficients = Vec::with_capacity(pieces * order);
        for j in 0..pieces {
            let c = (j as f64 + 0.5) / pieces as f64;
            let e = exp(log * c);
            for pk in &powers {
                coefficients.push(top_rows(&(e * *pk)));
            }
        }
        Self {
            a,
            log,
            pieces,
            order,
            coefficients,
        }
    }

    /// The transform `A`.
    #[must_use]
    pub fn transform(&self) -> DMat4 {
        self.a
    }
    /// `log A`.
    #[must_use]
    pub fn log(&self) -> DMat4 {
        self.log
    }
    /// Number of pieces and Taylor order of the table (for reports and benches).
    #[must_use]
    pub fn table_size(&self) -> (usize, usize) {
        (self.pieces, self.order)
    }

    /// The top three rows of `α ⊙ A` for α ∈ (0, 1), from the table.
    #[inline]
    fn rows(&self, alpha: f64) -> [f64; 12] {
        let n = self.pieces as f64;
        let j = ((alpha * n) as usize).min(self.pieces - 1);
        let t = alpha - (j as f64 + 0.5) / n;
        let block = &self.coefficients[j * self.order..(j + 1) * self.order];
        let mut acc = block[self.order - 1];
        for c in block[..self.order - 1].iter().rev() {
            // Plain multiply-add: `f64::mul_add` is a libm call without hardware FMA.
            for (x, y) in acc.iter_mut().zip(c) {
                *x = *x * t + *y;
            }
        }
        acc
    }

    /// `α ⊙ A` as a matrix: `I` for α = 0 and `A` for α = 1 exactly; from the table for
    /// α ∈ (0, 1); by the Padé exponential of `α log A` otherwise (non-finite for a
    /// non-finite α, or when `α ⊙ A` overflows: [`scalar_power`] checks both).
    #[must_use]
    pub fn matrix(&self, alpha: f64) -> DMat4 {
        if alpha == 0.0 {
            DMat4::IDENTITY
        } else if alpha == 1.0 {
            self.a
        } else if alpha > 0.0 && alpha < 1.0 {
            let r = self.rows(alpha);
            DMat4::from_cols_array(&[
                r[0], r[4], r[8], 0.0, r[1], r[5], r[9], 0.0, r[2], r[6], r[10], 0.0, r[3], r[7],
                r[11], 1.0,
            ])
        } else {
            self.matrix_pade(alpha)
        }
    }

    /// `exp(α log A)` by the Padé exponential, for every α (the reference the table is
    /// measured against).
    #[must_use]
    pub fn matrix_pade(&self, alpha: f64) -> DMat4 {
        exp(self.log * alpha)
    }

    /// `(α ⊙ A) p`: `p` for α = 0, `A p` for α = 1 (bit for bit), the table for
    /// α ∈ (0, 1), the Padé exponential otherwise.
    #[inline]
    #[must_use]
    pub fn transform_point(&self, alpha: f64, p: DVec3) -> DVec3 {
        if alpha == 0.0 {
            p
        } else if alpha == 1.0 {
            self.a.transform_point3(p)
        } else if alpha > 0.0 && alpha < 1.0 {
            let r = self.rows(alpha);
            DVec3::new(
                r[0] * p.x + r[1] * p.y + r[2] * p.z + r[3],
                r[4] * p.x + r[5] * p.y + r[6] * p.z + r[7],
                r[8] * p.x + r[9] * p.y + r[10] * p.z + r[11],
            )
        } else {
            self.matrix_pade(alpha).transform_point3(p)
        }
    }

    /// The entries `(0,0) (0,1) (0,3) (1,0) (1,1) (1,3)` of `α ⊙ A` for α ∈ (0, 1), from
    /// the table: all a plane transform needs (see [`AffinePower::transform_point2`]).
    #[inline]
    fn rows_xy(&self, alpha: f64) -> [f64; 6] {
        const PICK: [usize; 6] = [0, 1, 3, 4, 5, 7];
        let n = self.pieces as f64;
        let j = ((alpha * n) as usize).min(self.pieces - 1);
        let t = alpha - (j as f64 + 0.5) / n;
        let block = &self.coefficients[j * self.order..(j + 1) * self.order];
        let last = &block[self.order - 1];
        let mut acc = PICK.map(|k| last[k]);
        for c in block[..self.order - 1].iter().rev() {
            for (x, &k) in acc.iter_mut().zip(&PICK) {
                *x = *x * t + c[k];
            }
        }
        acc
    }

    /// `(α ⊙ A) p` for a point of the plane `z = 0`, when `A` is a 2-D affine map
    /// embedded in 4×4 (its third row and column those of the identity, as
    /// `edit::bendels_klein::polyline` and `edit::bendels_klein::image` build them): `exp(α log A)` keeps that
    /// block structure, so only six entries of the table are evaluated, half the work of
    /// [`AffinePower::transform_point`]. `p` for α = 0; for α = 1 the 2-D map itself,
    /// `M p + t` with the arithmetic of `DMat3::transform_point2`; the Padé exponential
    /// outside [0, 1]. Bendels & Klein's blend for polylines and images (Sec. 2, 7).
    #[inline]
    #[must_use]
    pub fn transform_point2(&self, alpha: f64, p: DVec2) -> DVec2 {
        if alpha == 0.0 {
            p
        } else if alpha == 1.0 {
            let a = &self.a;
            DVec2::new(a.x_axis.x, a.x_axis.y) * p.x
                + DVec2::new(a.y_axis.x, a.y_axis.y) * p.y
                + DVec2::new(a.w_axis.x, a.w_axis.y)
        } else if alpha > 0.0 && alpha < 1.0 {
            let r = self.rows_xy(alpha);
            DVec2::new(
                r[0] * p.x + r[1] * p.y + r[2],
                r[3] * p.x + r[4] * p.y + r[5],
            )
        } else {
            self.matrix_pade(alpha)
                .transform_point3(p.extend(0.0))
                .truncate()
        }
    }
}

/// The 2-D homogeneous affine map `m` (3×3, bottom row `0 0 1`) as a 4×4 transform of
/// space that acts on `x, y` as `m` does and leaves `z` alone: the form in which
/// [`log`], [`AffinePower`] and [`AffinePower::transform_point2`] blend plane transforms
/// (Bendels & Klein: polylines and images, 3×3 homogeneous). The bottom row is carried
/// over, so a non-affine `m` is refused by [`AffinePower::new`] as
/// [`BendelsKleinError::NotAffine`].
#[must_use]
pub fn embed_affine2(m: DMat3) -> DMat4 {
    DMat4::from_cols(
        DVec4::new(m.x_axis.x, m.x_axis.y, 0.0, m.x_axis.z),
        DVec4::new(m.y_axis.x, m.y_axis.y, 0.0, m.y_axis.z),
        DVec4::Z,
        DVec4::new(m.z_axis.x, m.z_axis.y, 0.0, m.z_axis.z),
    )
}

#[cfg(test)]
mod tests;
