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
//!   [`EditError::NoRealLogarithm`] and the reason.
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

use glam::{DMat3, DMat4, DVec2, DVec3, DVec4};

use crate::{EditError, Result};

/// Why a transform has no real logarithm (see [`log`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NoLogReason {
    /// The linear part has a negative determinant: the transform contains a reflection
    /// (Alexa 2002, Sec. 3: reflections have no real logarithm).
    Reflection {
        /// The determinant of the linear part.
        det: f64,
    },
    /// The linear part is singular (it flattens space).
    Singular,
    /// The linear part has an eigenvalue on (or within rounding of) the negative real
    /// axis, e.g. a rotation by exactly π: no real principal logarithm exists.
    NegativeEigenvalue {
        /// Real part of the eigenvalue.
        re: f64,
        /// Imaginary part of the eigenvalue (zero or rounding-sized).
        im: f64,
    },
    /// The square-root iteration did not converge (a matrix too close to the cases
    /// above).
    NotConverged,
}

impl std::fmt::Display for NoLogReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Reflection { det } => write!(
                f,
                "it contains a reflection (determinant of the linear part is {det})"
            ),
            Self::Singular => write!(f, "its linear part is singular"),
            Self::NegativeEigenvalue { re, im } => write!(
                f,
                "its linear part has the eigenvalue {re}{im:+}i on the negative real axis \
                 (e.g. a rotation by exactly π)"
            ),
            Self::NotConverged => write!(f, "the square-root iteration did not converge"),
        }
    }
}

/// The 1-norm (largest absolute column sum) of a 4×4 matrix.
#[inline]
#[must_use]
pub fn norm1(m: &DMat4) -> f64 {
    [m.x_axis, m.y_axis, m.z_axis, m.w_axis]
        .iter()
        .map(|c| c.abs().element_sum())
        .fold(0.0, f64::max)
}

fn norm1_3(m: &DMat3) -> f64 {
    [m.x_axis, m.y_axis, m.z_axis]
        .iter()
        .map(|c| c.abs().element_sum())
        .fold(0.0, f64::max)
}

fn is_finite(m: &DMat4) -> bool {
    m.to_cols_array().iter().all(|x| x.is_finite())
}

/// The matrix exponential of any 4×4 matrix: Padé approximant of degree 3, 5, 7, 9 or
/// 13 chosen from `‖M‖₁`, with scaling and squaring for larger norms (Higham 2005,
/// Algorithm 2.3). A non-finite input gives a non-finite output.
#[must_use]
pub fn exp(m: DMat4) -> DMat4 {
    // θ_m of Higham 2005, Table 2.3 (double precision).
    const THETA: [(usize, f64); 4] = [
        (3, 1.495_585_217_958_292e-2),
        (5, 2.539_398_330_063_23e-1),
        (7, 9.504_178_996_162_932e-1),
        (9, 2.097_847_961_257_068),
    ];
    const THETA_13: f64 = 5.371_920_351_148_152;
    let n = norm1(&m);
    if !n.is_finite() {
        return DMat4::from_cols_array(&[f64::NAN; 16]);
    }
    for (degree, theta) in THETA {
        if n <= theta {
            return pade(m, degree);
        }
    }
    let s = if n <= THETA_13 {
        0
    } else {
        (n / THETA_13).log2().ceil() as i32
    };
    let mut r = pade(m * 2f64.powi(-s), 13);
    for _ in 0..s {
        r = r * r;
    }
    r
}

/// Padé approximant `r_m(M) = (V − U)⁻¹ (V + U)` of `exp`.
fn pade(m: DMat4, degree: usize) -> DMat4 {
    let i = DMat4::IDENTITY;
    let m2 = m * m;
    let (u, v) = match degree {
        3 => {
            let b = [120.0, 60.0, 12.0, 1.0];
            (m * (m2 * b[3] + i * b[1]), m2 * b[2] + i * b[0])
        }
        5 => {
            let b = [30240.0, 15120.0, 3360.0, 420.0, 30.0, 1.0];
            let m4 = m2 * m2;
            (
                m * (m4 * b[5] + m2 * b[3] + i * b[1]),
                m4 * b[4] + m2 * b[2] + i * b[0],
            )
        }
        7 => {
            let b = [
                17_297_280.0,
                8_648_640.0,
                1_995_840.0,
                277_200.0,
                25_200.0,
                1_512.0,
                56.0,
                1.0,
            ];
            let m4 = m2 * m2;
            let m6 = m4 * m2;
            (
                m * (m6 * b[7] + m4 * b[5] + m2 * b[3] + i * b[1]),
                m6 * b[6] + m4 * b[4] + m2 * b[2] + i * b[0],
            )
        }
        9 => {
            let b = [
                17_643_225_600.0,
                8_821_612_800.0,
                2_075_673_600.0,
                302_702_400.0,
                30_270_240.0,
                2_162_160.0,
                110_880.0,
                3_960.0,
                90.0,
                1.0,
            ];
            let m4 = m2 * m2;
            let m6 = m4 * m2;
            let m8 = m6 * m2;
            (
                m * (m8 * b[9] + m6 * b[7] + m4 * b[5] + m2 * b[3] + i * b[1]),
                m8 * b[8] + m6 * b[6] + m4 * b[4] + m2 * b[2] + i * b[0],
            )
        }
        _ => {
            let b = [
                64_764_752_532_480_000.0,
                32_382_376_266_240_000.0,
                7_771_770_303_897_600.0,
                1_187_353_796_428_800.0,
                129_060_195_264_000.0,
                10_559_470_521_600.0,
                670_442_572_800.0,
                33_522_128_640.0,
                1_323_241_920.0,
                40_840_800.0,
                960_960.0,
                16_380.0,
                182.0,
                1.0,
            ];
            let m4 = m2 * m2;
            let m6 = m4 * m2;
            let u = m
                * (m6 * (m6 * b[13] + m4 * b[11] + m2 * b[9])
                    + m6 * b[7]
                    + m4 * b[5]
                    + m2 * b[3]
                    + i * b[1]);
            let v = m6 * (m6 * b[12] + m4 * b[10] + m2 * b[8])
                + m6 * b[6]
                + m4 * b[4]
                + m2 * b[2]
                + i * b[0];
            (u, v)
        }
    };
    (v - u).inverse() * (v + u)
}

/// Checks that `a` is finite and affine (bottom row `(0, 0, 0, 1)` up to 1e-12) and
/// returns it with the bottom row set exactly.
fn affine(a: &DMat4) -> Result<DMat4> {
    if !is_finite(a) {
        return Err(EditError::NonFiniteMatrix);
    }
    let row = a.row(3);
    if (row - DVec4::W).abs().max_element() > 1e-12 {
        return Err(EditError::NotAffine(row.to_array()));
    }
    let mut a = *a;
    a.x_axis.w = 0.0;
    a.y_axis.w = 0.0;
    a.z_axis.w = 0.0;
    a.w_axis.w = 1.0;
    Ok(a)
}

/// Eigenvalues `(re, im)` of a 3×3 matrix from its characteristic polynomial (Cardano
/// or the trigonometric form, polished by Newton, then deflation). Enough to find
/// eigenvalues on the negative real axis; not meant as a general eigen-solver.
fn eigenvalues3(m: &DMat3) -> [(f64, f64); 3] {
    let tr = m.x_axis.x + m.y_axis.y + m.z_axis.z;
    let minors = m.x_axis.x * m.y_axis.y - m.y_axis.x * m.x_axis.y + m.x_axis.x * m.z_axis.z
        - m.z_axis.x * m.x_axis.z
        + m.y_axis.y * m.z_axis.z
        - m.z_axis.y * m.y_axis.z;
    let det = m.determinant();
    // λ³ + a λ² + b λ + c
    let (a, b, c) = (-tr, minors, -det);
    let p = b - a * a / 3.0;
    let q = 2.0 * a * a * a / 27.0 - a * b / 3.0 + c;
    let disc = (q / 2.0).powi(2) + (p / 3.0).powi(3);
    let mut r = if disc > 0.0 {
        let s = disc.sqrt();
        (-q / 2.0 + s).cbrt() + (-q / 2.0 - s).cbrt() - a / 3.0
    } else if p == 0.0 {
        -a / 3.0
    } else {
        let k = 2.0 * (-p / 3.0).sqrt();
        let arg = ((3.0 * q) / (2.0 * p) * (-3.0 / p).sqrt()).clamp(-1.0, 1.0);
        k * (arg.acos() / 3.0).cos() - a / 3.0
    };
    for _ in 0..4 {
        let f = ((r + a) * r + b) * r + c;
        let df = (3.0 * r + 2.0 * a) * r + b;
        if df == 0.0 {
            break;
        }
        let step = f / df;
        if !step.is_finite() {
            break;
        }
        r -= step;
    }
    // Deflate: λ² + B λ + C.
    let bb = a + r;
    let cc = b + r * bb;
    let d = bb * bb - 4.0 * cc;
    if d >= 0.0 {
        let s = d.sqrt();
        let x1 = if bb >= 0.0 {
            (-bb - s) / 2.0
        } else {
            (-bb + s) / 2.0
        };
        let x2 = if x1 != 0.0 { cc / x1 } else { -bb - x1 };
        [(r, 0.0), (x1, 0.0), (x2, 0.0)]
    } else {
        let im = (-d).sqrt() / 2.0;
        [(r, 0.0), (-bb / 2.0, im), (-bb / 2.0, -im)]
    }
}

/// Refuses linear parts without a real principal logarithm. `m` is scaled so that its
/// largest entry is in [1, 2) (see [`log`]): determinants cannot overflow.
///
/// Singular means numerically singular: `|det m|` below 1e-14 of the product of the
/// column lengths (Hadamard's bound, which `|det|` reaches for orthogonal columns). A
/// uniform scale of any size is not singular, nor is a shear of 1e12 (its ratio is 1e-12).
/// Reasons report determinants and eigenvalues of the unscaled matrix (`m · scale`).
fn check_log_exists(m: &DMat3, scale: f64) -> Result<()> {
    let det = m.determinant();
    let hadamard = m.x_axis.length() * m.y_axis.length() * m.z_axis.length();
    if hadamard == 0.0 || det.abs() <= 1e-14 * hadamard {
        return Err(EditError::NoRealLogarithm(NoLogReason::Singular));
    }
    if det < 0.0 {
        return Err(EditError::NoRealLogarithm(NoLogReason::Reflection {
            det: det * scale * scale * scale,
        }));
    }
    for (re, im) in eigenvalues3(m) {
        let size = re.hypot(im);
        // A double eigenvalue on the negative axis comes out of the cubic with an
        // imaginary part of order sqrt(ε): treat |im| ≤ 1e-7 |λ| as on the axis.
        if re < 0.0 && im.abs() <= 1e-7 * size {
            return Err(EditError::NoRealLogarithm(
                NoLogReason::NegativeEigenvalue {
                    re: re * scale,
                    im: im * scale,
                },
            ));
        }
    }
    Ok(())
}

/// Principal square root of a 3×3 matrix by the product form of the Denman–Beavers
/// iteration with determinant scaling (Higham, *Functions of Matrices*, eq. 6.29):
/// `M ← ½(I + (μ²M + μ⁻²M⁻¹)/2)`, `Y ← ½ μ Y (I + μ⁻² M⁻¹)`, `M₀ = Y₀ = A`,
/// `μ = |det M|^(−1/6)`; `Y → A^½`, `M → I`. `None` when it does not converge
/// (eigenvalues on the closed negative real axis).
#[must_use]
pub fn sqrt_denman_beavers(a: DMat3) -> Option<DMat3> {
    let i = DMat3::IDENTITY;
    let mut m = a;
    let mut y = a;
    for iteration in 0..100 {
        let det = m.determinant();
        if !det.is_finite() || det == 0.0 {
            return None;
        }
        // Scale while far from convergence; plain steps at the end keep it quadratic.
        let mu = if iteration < 6 {
            det.abs().powf(-1.0 / 6.0)
        } else {
            1.0
        };
        let m_inv = m.inverse();
        let mu2 = mu * mu;
        y = (y * (i + m_inv * (1.0 / mu2))) * (0.5 * mu);
        m = (i + (m * mu2 + m_inv * (1.0 / mu2)) * 0.5) * 0.5;
        if !y.to_cols_array().iter().all(|x| x.is_finite()) {
            return None;
        }
        if norm1_3(&(m - i)) <= 1e-15 {
            return Some(y);
        }
    }
    None
}

/// Principal square root of a 3×3 matrix without eigenvalues on the closed negative
/// real axis, in closed form from a real Schur form `M = Q T Qᵀ`, `T = [[r, wᵀ], [0, B]]`:
/// `√T = [[√r, xᵀ], [0, √B]]` with `xᵀ (√r I + √B) = wᵀ`, and the 2×2 root
/// `√B = p I + (B − a I) / (2p)` for eigenvalues `a ± ib` (`p = Re √λ`, computed without
/// cancellation), or `(B + √det B · I) / (√λ₁ + √λ₂)` for real eigenvalues.
///
/// Used for the first root of a matrix with eigenvalues in the left half-plane (a
/// rotation by nearly π): there Denman–Beavers passes through a nearly singular iterate
/// (`½(I + (M + M⁻¹)/2)` has eigenvalues `(1 + cos θ)/2`) and loses accuracy as
/// `ε / (π − θ)³`, while this form stays at the conditioning of the root, `ε / (π − θ)`.
fn sqrt3_schur(m: &DMat3) -> Option<DMat3> {
    let eig = eigenvalues3(m);
    let r = eig[0].0;
    if r <= 0.0 {
        return None;
    }
    let k = *m - DMat3::from_diagonal(DVec3::splat(r));
    let rows = [k.row(0), k.row(1), k.row(2)];
    let crosses = [
        rows[0].cross(rows[1]),
        rows[1].cross(rows[2]),
        rows[2].cross(rows[0]),
    ];
    let best = crosses
        .iter()
        .copied()
        .max_by(|a, b| a.length_squared().total_cmp(&b.length_squared()))
        .expect("three candidates");
    let scale = norm1_3(m).max(f64::MIN_POSITIVE);
    let u = if best.length() > 1e-10 * scale * scale {
        best.normalize()
    } else {
        // Eigenspace of dimension ≥ 2: any unit vector orthogonal to the largest row.
        let row = rows
            .iter()
            .copied()
            .max_by(|a, b| a.length_squared().total_cmp(&b.length_squared()))
            .expect("three rows");
        if row.length() <= 1e-14 * scale {
            DVec3::X
        } else {
            row.any_orthonormal_vector()
        }
    };
    let v = u.any_orthonormal_vector();
    let w = u.cross(v);
    let q = DMat3::from_cols(u, v, w);
    let t = q.transpose() * *m * q;
    let rr = t.x_axis.x;
    if rr <= 0.0 {
        return None;
    }
    // T = [[rr, wᵀ], [0, B]] (column-major: t.col(c)[row]).
    let (b00, b01, b10, b11) = (t.y_axis.y, t.z_axis.y, t.y_axis.z, t.z_axis.z);
    let wt = (t.y_axis.x, t.z_axis.x);
    let a = 0.5 * (b00 + b11);
    let disc = 0.25 * (b00 - b11) * (b00 - b11) + b01 * b10;
    let sb = if disc < 0.0 {
        let im = (-disc).sqrt();
        let modulus = a.hypot(im);
        let p = if a >= 0.0 {
            (0.5 * (modulus + a)).sqrt()
        } else {
            im / (2.0 * (modulus - a)).sqrt()
        };
        if p <= 0.0 {
            return None;
        }
        let c = 0.5 / p;
        [(b00 - a) * c + p, b01 * c, b10 * c, (b11 - a) * c + p]
    } else {
        let det = b00 * b11 - b01 * b10;
        let sq = disc.sqrt();
        let (l1, l2) = (a + sq, a - sq);
        if l1 <= 0.0 || l2 <= 0.0 || det <= 0.0 {
            return None;
        }
        let s = det.sqrt();
        let tt = l1.sqrt() + l2.sqrt();
        [(b00 + s) / tt, b01 / tt, b10 / tt, (b11 + s) / tt]
    };
    let sr = rr.sqrt();
    // xᵀ (√r I + √B) = wᵀ  ⇔  (√r I + √B)ᵀ x = w.
    let (m00, m01, m10, m11) = (sr + sb[0], sb[1], sb[2], sr + sb[3]);
    let det = m00 * m11 - m01 * m10;
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    // Solve [x0 x1] [[m00, m01], [m10, m11]] = [w0 w1].
    let x0 = (wt.0 * m11 - wt.1 * m10) / det;
    let x1 = (wt.1 * m00 - wt.0 * m01) / det;
    let st = DMat3::from_cols(
        DVec3::new(sr, 0.0, 0.0),
        DVec3::new(x0, sb[0], sb[2]),
        DVec3::new(x1, sb[1], sb[3]),
    );
    Some(q * st * q.transpose())
}

/// The [8/8] Padé approximant of `log(I + Y)` in partial fractions,
/// `Σ w_j Y (I + x_j Y)⁻¹` with Gauss–Legendre nodes `x_j` and weights `w_j` on [0, 1]
/// (Higham 2001, *Evaluating Padé approximants of the matrix logarithm*).
fn log_pade8(y: DMat3) -> DMat3 {
    const NODES: [(f64, f64); 4] = [
        (0.183_434_642_495_649_8, 0.362_683_783_378_362),
        (0.525_532_409_916_329, 0.313_706_645_877_887_3),
        (0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
        (0.960_289_856_497_536_3, 0.101_228_536_290_376_3),
    ];
    let i = DMat3::IDENTITY;
    let mut sum = DMat3::ZERO;
    for (t, w) in NODES {
        for x in [(1.0 - t) / 2.0, (1.0 + t) / 2.0] {
            sum += (y * (i + y * x).inverse()) * (w / 2.0);
        }
    }
    sum
}

/// The principal logarithm of a 3×3 matrix without eigenvalues on the closed negative
/// real axis: inverse scaling and squaring (Denman–Beavers roots until
/// `‖X − I‖₁ ≤ 0.3`, the [8/8] Padé approximant, times `2^k`). A matrix with eigenvalues
/// in the left half-plane takes its first root in closed form (see [`sqrt3_schur`]).
fn log3(m: DMat3) -> Result<DMat3> {
    let not_converged = || EditError::NoRealLogarithm(NoLogReason::NotConverged);
    let i = DMat3::IDENTITY;
    let mut x = m;
    let mut k = 0;
    // Eigenvalues more than π/4 away from the positive axis: roots in closed form until
    // they are not (each root halves the angles), Denman–Beavers for the rest.
    while eigenvalues3(&x).iter().any(|&(re, im)| re < im.abs()) {
        x = sqrt3_schur(&x).ok_or(EditError::NoRealLogarithm(NoLogReason::NotConverged))?;
        k += 1;
        if k > 4 {
            return Err(not_converged());
        }
    }
    while norm1_3(&(x - i)) > 0.3 {
        x = sqrt_denman_beavers(x).ok_or(EditError::NoRealLogarithm(NoLogReason::NotConverged))?;
        k += 1;
        if k > 64 {
            return Err(not_converged());
        }
    }
    let l = log_pade8(x - i) * 2f64.powi(k);
    if l.to_cols_array().iter().all(|x| x.is_finite()) {
        Ok(l)
    } else {
        Err(not_converged())
    }
}

/// `φ₁(B) = Σ Bᵏ / (k+1)! = ∫₀¹ exp(sB) ds`, column by column as the top-right block of
/// `exp([[B, e_j], [0, 0]])`.
fn phi1(b: DMat3) -> DMat3 {
    let mut cols = [DVec3::ZERO; 3];
    for (j, col) in cols.iter_mut().enumerate() {
        let mut aug = DMat4::from_mat3(b);
        aug.w_axis = DVec4::ZERO;
        aug.w_axis[j] = 1.0;
        *col = exp(aug).w_axis.truncate();
    }
    DMat3::from_cols(cols[0], cols[1], cols[2])
}

/// The principal matrix logarithm of an affine 4×4 transform `A = [[M, t], [0, 1]]`:
/// `log A = [[B, c], [0, 0]]` with `B = log M` by inverse scaling and squaring
/// (Denman–Beavers square roots, see the module docs) and `c = φ₁(B)⁻¹ t`, since
/// `exp([[B, c], [0, 0]]) = [[e^B, φ₁(B) c], [0, 1]]`. Treating the translation apart
/// keeps the number of square roots independent of its size (taking roots of the whole
/// 4×4 needs `log₂(‖t‖)` more of them, and loses that many bits). `φ₁(B)` is invertible
/// for a principal logarithm (its eigenvalues have imaginary parts in (−π, π)).
///
/// # Errors
/// [`EditError::NonFiniteMatrix`], [`EditError::NotAffine`], and
/// [`EditError::NoRealLogarithm`] for reflections, singular linear parts and negative
/// real eigenvalues (Alexa 2002, Sec. 3).
pub fn log(a: DMat4) -> Result<DMat4> {
    let a = affine(&a)?;
    let m = DMat3::from_mat4(a);
    // log(s M) = ln(s) I + log(M) for s > 0. The checks see M with its largest entry
    // scaled into [1, 2) by a power of two (exact): no determinant overflows or
    // underflows, whatever the size of a uniform scale. The logarithm is taken of M
    // scaled to determinant about 1 (s = |det M|^(1/3) rounded to a power of two), which
    // leaves a rotation or a shear alone.
    let largest = m.to_cols_array().iter().fold(0.0f64, |x, y| x.max(y.abs()));
    if largest == 0.0 {
        return Err(EditError::NoRealLogarithm(NoLogReason::Singular));
    }
    let e1 = largest.log2().floor() as i32;
    let m1 = m * 2f64.powi(-e1);
    check_log_exists(&m1, 2f64.powi(e1))?;
    let exponent = e1 + (m1.determinant().log2() / 3.0).round() as i32;
    let b = log3(m * 2f64.powi(-exponent))?
        + DMat3::from_diagonal(DVec3::splat(f64::from(exponent) * std::f64::consts::LN_2));
    let t = a.w_axis.truncate();
    let c = if b == DMat3::ZERO {
        // A translation: φ₁(0) = I.
        t
    } else {
        translation_log(b, t)?
    };
    let mut l = DMat4::from_mat3(b);
    l.w_axis = c.extend(0.0);
    if !is_finite(&l) {
        return Err(EditError::Overflow(format!(
            "the logarithm of the transform does not fit in f64 (translation {t})"
        )));
    }
    Ok(l)
}

/// `c = φ₁(B)⁻¹ t` (see [`log`]), with `φ₁(B)` and `t` scaled by powers of two so that
/// huge entries do not overflow on the way.
fn translation_log(b: DMat3, t: DVec3) -> Result<DVec3> {
    let phi = phi1(b);
    let largest = phi
        .to_cols_array()
        .iter()
        .fold(0.0f64, |x, y| x.max(y.abs()));
    if !largest.is_finite() || largest == 0.0 {
        return Err(EditError::Overflow(format!(
            "the linear part of the transform is too large for its translation to be \
             taken apart (φ₁(log M) has an entry of {largest})"
        )));
    }
    let phi_scale = 2f64.powi(largest.log2().floor() as i32);
    let phi = phi * (1.0 / phi_scale);
    let det = phi.determinant();
    if det == 0.0 || !det.is_finite() {
        return Err(EditError::NoRealLogarithm(NoLogReason::NotConverged));
    }
    let t_largest = t.abs().max_element();
    if t_largest == 0.0 {
        return Ok(DVec3::ZERO);
    }
    let t_scale = 2f64.powi(t_largest.log2().floor() as i32);
    Ok(phi.inverse() * (t / t_scale) * (t_scale / phi_scale))
}

/// Alexa's scalar multiple `α ⊙ A = exp(α log A)` (Alexa 2002; Bendels & Klein, Sec. 3):
/// `0 ⊙ A = I` and `1 ⊙ A = A` exactly, `(½ ⊙ A)² = A`. For many α with the same `A`
/// use [`AffinePower`].
///
/// # Errors
/// As [`log`]; [`EditError::InvalidParameter`] for a non-finite α, and
/// [`EditError::Overflow`] when `α ⊙ A` does not fit in f64 (a large α of a large
/// transform).
pub fn scalar_power(alpha: f64, a: DMat4) -> Result<DMat4> {
    crate::vertices::finite("alpha", alpha)?;
    let m = AffinePower::new(a)?.matrix(alpha);
    if !is_finite(&m) {
        return Err(EditError::Overflow(format!(
            "{alpha} ⊙ A does not fit in f64"
        )));
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
    /// `edit::polyline` and `edit::image_edit` build them): `exp(α log A)` keeps that
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
/// [`EditError::NotAffine`].
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
mod tests {
    use super::*;
    use glam::DQuat;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn close(a: &DMat4, b: &DMat4, tol: f64) -> bool {
        norm1(&(*a - *b)) <= tol * norm1(b).max(1.0)
    }

    fn random_rotation(rng: &mut ChaCha8Rng, max_angle: f64) -> DMat4 {
        let axis = DVec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        )
        .normalize();
        DMat4::from_quat(DQuat::from_axis_angle(
            axis,
            rng.random_range(-max_angle..max_angle),
        ))
    }

    fn random_transform(rng: &mut ChaCha8Rng, kind: usize) -> DMat4 {
        let t = DVec3::new(
            rng.random_range(-10.0..10.0),
            rng.random_range(-10.0..10.0),
            rng.random_range(-10.0..10.0),
        );
        let rotation = random_rotation(rng, 3.0);
        let scale = DMat4::from_scale(DVec3::new(
            rng.random_range(0.2..5.0),
            rng.random_range(0.2..5.0),
            rng.random_range(0.2..5.0),
        ));
        let mut shear = DMat4::IDENTITY;
        shear.y_axis.x = rng.random_range(-1.0..1.0);
        shear.z_axis.x = rng.random_range(-1.0..1.0);
        shear.z_axis.y = rng.random_range(-1.0..1.0);
        match kind % 5 {
            0 => DMat4::from_translation(t) * rotation,
            1 => scale,
            2 => shear,
            3 => DMat4::from_translation(t) * rotation * scale * shear,
            _ => random_rotation(rng, 3.0) * scale * rotation * shear * DMat4::from_translation(t),
        }
    }

    #[test]
    fn exp_of_log_and_half_power_squared_reproduce_random_transforms() {
        let mut rng = ChaCha8Rng::seed_from_u64(2003);
        let mut refused = 0;
        let mut ill_conditioned = 0;
        for k in 0..1000 {
            let a = random_transform(&mut rng, k);
            let l = match log(a) {
                Ok(l) => l,
                Err(e) => {
                    assert_refusal_is_right(&a, &e);
                    refused += 1;
                    continue;
                }
            };
            // Near the negative real axis a non-normal M has a logarithm of huge norm at
            // which exp is ill-conditioned: rounding L alone (relative 1e-16) moves
            // exp(L) by up to 1e-10 there, for any algorithm. The bound is 1e-12, or ten
            // times that rounding sensitivity where it is larger (counted: rare).
            let sensitivity = rounding_sensitivity(&l) / norm1(&a).max(1.0);
            let tol = 1e-12f64.max(10.0 * sensitivity);
            if tol > 1e-12 {
                ill_conditioned += 1;
            }
            assert!(close(&exp(l), &a, tol), "exp(log A) != A for {a:?}");
            let half = scalar_power(0.5, a).unwrap();
            assert!(close(&(half * half), &a, tol), "(½⊙A)² != A for {a:?}");
            let half_pade = exp(l * 0.5);
            assert!(close(&(half_pade * half_pade), &a, tol));
        }
        assert!(ill_conditioned < 30, "{ill_conditioned} ill-conditioned");
        // Products of rotations and anisotropic scalings may have a negative real
        // eigenvalue pair; they are refused, and rare.
        assert!(refused < 100, "{refused} refused");
        println!("{refused} refused, {ill_conditioned} ill-conditioned of 1000");
    }

    /// How much exp(L) moves when the entries of L are rounded differently (relative
    /// perturbations of ±2.2e-16): the accuracy any log/exp pair can reach at L.
    fn rounding_sensitivity(l: &DMat4) -> f64 {
        let e = exp(*l);
        (0..4)
            .map(|k| {
                let mut p = *l;
                for c in 0..4 {
                    for r in 0..3 {
                        let sign = if (c * 3 + r + k) % 3 == 0 { 1.0 } else { -1.0 };
                        p.col_mut(c)[r] *= 1.0 + sign * f64::EPSILON;
                    }
                }
                norm1(&(exp(p) - e))
            })
            .fold(0.0, f64::max)
    }

    /// A refusal must name a true eigenvalue on the negative axis (or a reflection).
    fn assert_refusal_is_right(a: &DMat4, e: &EditError) {
        let m = DMat3::from_mat4(*a);
        match e {
            EditError::NoRealLogarithm(NoLogReason::NegativeEigenvalue { re, .. }) => {
                let shifted = m - DMat3::from_diagonal(DVec3::splat(*re));
                let scale = norm1_3(&m);
                assert!(
                    shifted.determinant().abs() < 1e-9 * scale.powi(3),
                    "{re} is no eigenvalue of {m:?}"
                );
                assert!(*re < 0.0);
            }
            EditError::NoRealLogarithm(NoLogReason::Reflection { .. }) => {
                assert!(m.determinant() < 0.0);
            }
            other => panic!("unexpected refusal {other:?}"),
        }
    }

    #[test]
    fn haar_random_rotations_up_to_nearly_a_half_turn() {
        // Uniform random rotations (quaternions from a Gaussian), plus angles close to π.
        let mut rng = ChaCha8Rng::seed_from_u64(31);
        for k in 0..1000 {
            let q = glam::DQuat::from_xyzw(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            )
            .normalize();
            let mut a = DMat4::from_quat(q);
            if k % 10 == 0 {
                let axis = DVec3::new(1.0, -2.0, 0.5).normalize();
                a = DMat4::from_axis_angle(axis, std::f64::consts::PI - 1e-4 * (k as f64 + 1.0));
            }
            a.w_axis = DVec3::new(1.0, 2.0, -3.0).extend(1.0);
            let l = log(a).unwrap();
            assert!(close(&exp(l), &a, 1e-12), "exp(log A) != A for {a:?}");
            let half = exp(l * 0.5);
            assert!(close(&(half * half), &a, 1e-12));
        }
    }

    #[test]
    fn zero_and_one_are_identity_and_the_transform() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for k in 0..50 {
            let a = random_transform(&mut rng, k);
            if log(a).is_err() {
                continue;
            }
            assert_eq!(scalar_power(0.0, a).unwrap(), DMat4::IDENTITY);
            assert_eq!(scalar_power(1.0, a).unwrap(), a);
            let p = AffinePower::new(a).unwrap();
            assert!(close(&p.matrix_pade(1.0), &a, 1e-12));
            assert!(close(&p.matrix_pade(0.0), &DMat4::IDENTITY, 1e-15));
        }
    }

    #[test]
    fn rotation_blends_to_a_partial_rotation_about_the_same_axis() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for _ in 0..100 {
            let axis = DVec3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            )
            .normalize();
            let theta = rng.random_range(-3.1..3.1);
            let centre = DVec3::new(1.0, -2.0, 0.5);
            let a = DMat4::from_translation(centre)
                * DMat4::from_axis_angle(axis, theta)
                * DMat4::from_translation(-centre);
            let p = AffinePower::new(a).unwrap();
            for alpha in [0.1, 0.25, 0.5, 0.77, 0.999] {
                let expected = DMat4::from_translation(centre)
                    * DMat4::from_axis_angle(axis, alpha * theta)
                    * DMat4::from_translation(-centre);
                assert!(close(&p.matrix(alpha), &expected, 1e-12));
                // The centre of rotation stays put.
                assert!(p.transform_point(alpha, centre).distance(centre) < 1e-12);
            }
        }
    }

    #[test]
    fn table_matches_pade_exponential() {
        let mut rng = ChaCha8Rng::seed_from_u64(99);
        for k in 0..100 {
            let a = random_transform(&mut rng, k);
            let Ok(p) = AffinePower::new(a) else { continue };
            for _ in 0..50 {
                let alpha: f64 = rng.random_range(0.0..1.0);
                let fast = p.matrix(alpha);
                let pade = p.matrix_pade(alpha);
                assert!(
                    close(&fast, &pade, 1e-13),
                    "α = {alpha}: {fast:?} vs {pade:?}"
                );
                let x = DVec3::new(0.3, -1.2, 2.0);
                let q = p.transform_point(alpha, x);
                assert!(q.distance(pade.transform_point3(x)) <= 1e-12 * (1.0 + q.length()));
            }
        }
    }

    #[test]
    fn translations_and_scalings_blend_as_expected() {
        let t = DVec3::new(3.0, -4.0, 12.0);
        let p = AffinePower::new(DMat4::from_translation(t)).unwrap();
        let m = p.matrix(0.25);
        assert!(close(&m, &DMat4::from_translation(0.25 * t), 1e-14));
        let s = DVec3::new(8.0, 0.5, 2.0);
        let p = AffinePower::new(DMat4::from_scale(s)).unwrap();
        let m = p.matrix(1.0 / 3.0);
        let expected = DMat4::from_scale(DVec3::new(2.0, 0.5f64.cbrt(), 2f64.cbrt()));
        assert!(close(&m, &expected, 1e-14));
    }

    /// Transforms of extreme size have logarithms (or the refusal says overflow, never
    /// "singular" or "did not converge"), and α must be finite.
    #[test]
    fn extreme_transforms_and_alphas() {
        for s in [1e-300, 1e-103, 1e103, 1e300] {
            let a = DMat4::from_scale(DVec3::splat(s));
            let l = log(a).unwrap();
            let expected = s.ln();
            assert!(
                (l.x_axis.x - expected).abs() <= 1e-13 * expected.abs(),
                "{s}"
            );
            let half = scalar_power(0.5, a).unwrap();
            assert!((half.x_axis.x / s.sqrt() - 1.0).abs() < 1e-12, "{s}");
        }
        let mut shear = DMat4::IDENTITY;
        shear.y_axis.x = 1e12;
        let l = log(shear).unwrap();
        assert!((l.y_axis.x - 1e12).abs() < 1e-3, "{l:?}");
        assert!(close(&exp(l), &shear, 1e-3));
        for t in [f64::MAX, -f64::MAX, 1e308] {
            let a = DMat4::from_translation(DVec3::new(t, -t, t));
            let l = log(a).unwrap();
            assert_eq!(l.w_axis.truncate(), DVec3::new(t, -t, t));
            assert_eq!(scalar_power(1.0, a).unwrap(), a);
        }
        let a = DMat4::from_scale(DVec3::splat(10.0));
        for alpha in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(matches!(
                scalar_power(alpha, a),
                Err(EditError::InvalidParameter { .. })
            ));
        }
        assert!(matches!(scalar_power(1e5, a), Err(EditError::Overflow(_))));
        assert!(scalar_power(2.0, a).unwrap().x_axis.x.is_finite());
    }

    #[test]
    fn reflections_and_half_turns_are_refused() {
        let mirror = DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0));
        assert!(matches!(
            log(mirror),
            Err(EditError::NoRealLogarithm(NoLogReason::Reflection { .. }))
        ));
        let mirror_moved = DMat4::from_translation(DVec3::ONE)
            * DMat4::from_axis_angle(DVec3::Y, 0.3)
            * DMat4::from_scale(DVec3::new(1.0, 1.0, -2.0));
        assert!(matches!(
            AffinePower::new(mirror_moved),
            Err(EditError::NoRealLogarithm(NoLogReason::Reflection { .. }))
        ));
        let half_turn =
            DMat4::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), std::f64::consts::PI);
        assert!(matches!(
            log(half_turn),
            Err(EditError::NoRealLogarithm(
                NoLogReason::NegativeEigenvalue { .. }
            ))
        ));
        let negative_pair = DMat4::from_scale(DVec3::new(-1.0, -2.0, 3.0));
        assert!(matches!(
            log(negative_pair),
            Err(EditError::NoRealLogarithm(
                NoLogReason::NegativeEigenvalue { .. }
            ))
        ));
        let flat = DMat4::from_scale(DVec3::new(1.0, 0.0, 3.0));
        assert!(matches!(
            log(flat),
            Err(EditError::NoRealLogarithm(NoLogReason::Singular))
        ));
        let mut projective = DMat4::IDENTITY;
        projective.x_axis.w = 0.5;
        assert!(matches!(log(projective), Err(EditError::NotAffine(_))));
        let mut nan = DMat4::IDENTITY;
        nan.w_axis.x = f64::NAN;
        assert!(matches!(log(nan), Err(EditError::NonFiniteMatrix)));
        // Close to a half turn is fine.
        let almost = DMat4::from_axis_angle(DVec3::Z, std::f64::consts::PI - 1e-3);
        let l = log(almost).unwrap();
        assert!(close(&exp(l), &almost, 1e-12));
    }

    #[test]
    fn exp_matches_series_on_small_and_large_norms() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for scale in [1e-3, 0.1, 1.0, 4.0, 20.0] {
            let mut m = DMat4::ZERO;
            for c in 0..4 {
                for r in 0..4 {
                    m.col_mut(c)[r] = rng.random_range(-1.0..1.0) * scale / 4.0;
                }
            }
            // exp(M) exp(−M) = I.
            let prod = exp(m) * exp(-m);
            assert!(close(&prod, &DMat4::IDENTITY, 1e-11 * (1.0 + scale)));
            // exp(2M) = exp(M)².
            let e = exp(m);
            assert!(close(&exp(m * 2.0), &(e * e), 1e-12 * (1.0 + scale)));
        }
    }
}
