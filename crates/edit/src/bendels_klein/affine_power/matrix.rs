//! The matrix exponential and the principal logarithm of 4×4 affine transforms (see the
//! [module docs](super)): Padé with scaling and squaring (Higham 2005), inverse scaling and
//! squaring with Denman–Beavers square roots (Kenney & Laub; Higham 2001).

use glam::{DMat3, DMat4, DVec3, DVec4};

use crate::bendels_klein::error::{BendelsKleinError, NoLogReason, Result, TransformOverflow};

/// The 1-norm (largest absolute column sum) of a 4×4 matrix.
///
/// Paper: Higham 2005, *The scaling and squaring method for the matrix exponential
/// revisited* (for Alexa 2002's `exp(α log A)`).
#[inline]
#[must_use]
pub fn norm1(m: &DMat4) -> f64 {
    [m.x_axis, m.y_axis, m.z_axis, m.w_axis]
        .iter()
        .map(|c| c.abs().element_sum())
        .fold(0.0, f64::max)
}

pub(super) fn norm1_3(m: &DMat3) -> f64 {
    [m.x_axis, m.y_axis, m.z_axis]
        .iter()
        .map(|c| c.abs().element_sum())
        .fold(0.0, f64::max)
}

pub(super) fn is_finite(m: &DMat4) -> bool {
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
pub(super) fn affine(a: &DMat4) -> Result<DMat4> {
    if !is_finite(a) {
        return Err(BendelsKleinError::NonFiniteMatrix);
    }
    let row = a.row(3);
    if (row - DVec4::W).abs().max_element() > 1e-12 {
        return Err(BendelsKleinError::NotAffine(row.to_array()));
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
        return Err(BendelsKleinError::NoRealLogarithm(NoLogReason::Singular));
    }
    if det < 0.0 {
        return Err(BendelsKleinError::NoRealLogarithm(
            NoLogReason::Reflection {
                det: det * scale * scale * scale,
            },
        ));
    }
    for (re, im) in eigenvalues3(m) {
        let size = re.hypot(im);
        // A double eigenvalue on the negative axis comes out of the cubic with an
        // imaginary part of order sqrt(ε): treat |im| ≤ 1e-7 |λ| as on the axis.
        if re < 0.0 && im.abs() <= 1e-7 * size {
            return Err(BendelsKleinError::NoRealLogarithm(
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
    let not_converged = || BendelsKleinError::NoRealLogarithm(NoLogReason::NotConverged);
    let i = DMat3::IDENTITY;
    let mut x = m;
    let mut k = 0;
    // Eigenvalues more than π/4 away from the positive axis: roots in closed form until
    // they are not (each root halves the angles), Denman–Beavers for the rest.
    while eigenvalues3(&x).iter().any(|&(re, im)| re < im.abs()) {
        x = sqrt3_schur(&x).ok_or(BendelsKleinError::NoRealLogarithm(
            NoLogReason::NotConverged,
        ))?;
        k += 1;
        if k > 4 {
            return Err(not_converged());
        }
    }
    while norm1_3(&(x - i)) > 0.3 {
        x = sqrt_denman_beavers(x).ok_or(BendelsKleinError::NoRealLogarithm(
            NoLogReason::NotConverged,
        ))?;
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
/// [`BendelsKleinError::NonFiniteMatrix`], [`BendelsKleinError::NotAffine`], and
/// [`BendelsKleinError::NoRealLogarithm`] for reflections, singular linear parts and negative
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
        return Err(BendelsKleinError::NoRealLogarithm(NoLogReason::Singular));
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
        return Err(BendelsKleinError::TransformOverflow(
            TransformOverflow::Logarithm { translation: t },
        ));
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
        return Err(BendelsKleinError::TransformOverflow(
            TransformOverflow::LinearPart { largest },
        ));
    }
    let phi_scale = 2f64.powi(largest.log2().floor() as i32);
    let phi = phi * (1.0 / phi_scale);
    let det = phi.determinant();
    if det == 0.0 || !det.is_finite() {
        return Err(BendelsKleinError::NoRealLogarithm(
            NoLogReason::NotConverged,
        ));
    }
    let t_largest = t.abs().max_element();
    if t_largest == 0.0 {
        return Ok(DVec3::ZERO);
    }
    let t_scale = 2f64.powi(t_largest.log2().floor() as i32);
    Ok(phi.inverse() * (t / t_scale) * (t_scale / phi_scale))
}
