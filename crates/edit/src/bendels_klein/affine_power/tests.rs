//! Tests of the matrix exponential and logarithm and of `α ⊙ A`.

use super::*;
use crate::bendels_klein::error::NoLogReason;
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
fn assert_refusal_is_right(a: &DMat4, e: &BendelsKleinError) {
    let m = DMat3::from_mat4(*a);
    match e {
        BendelsKleinError::NoRealLogarithm(NoLogReason::NegativeEigenvalue { re, .. }) => {
            let shifted = m - DMat3::from_diagonal(DVec3::splat(*re));
            let scale = norm1_3(&m);
            assert!(
                shifted.determinant().abs() < 1e-9 * scale.powi(3),
                "{re} is no eigenvalue of {m:?}"
            );
            assert!(*re < 0.0);
        }
        BendelsKleinError::NoRealLogarithm(NoLogReason::Reflection { .. }) => {
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
            Err(BendelsKleinError::InvalidParameter { .. })
        ));
    }
    assert!(matches!(
        scalar_power(1e5, a),
        Err(BendelsKleinError::TransformOverflow(_))
    ));
    assert!(scalar_power(2.0, a).unwrap().x_axis.x.is_finite());
}

#[test]
fn reflections_and_half_turns_are_refused() {
    let mirror = DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0));
    assert!(matches!(
        log(mirror),
        Err(BendelsKleinError::NoRealLogarithm(
            NoLogReason::Reflection { .. }
        ))
    ));
    let mirror_moved = DMat4::from_translation(DVec3::ONE)
        * DMat4::from_axis_angle(DVec3::Y, 0.3)
        * DMat4::from_scale(DVec3::new(1.0, 1.0, -2.0));
    assert!(matches!(
        AffinePower::new(mirror_moved),
        Err(BendelsKleinError::NoRealLogarithm(
            NoLogReason::Reflection { .. }
        ))
    ));
    let half_turn =
        DMat4::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), std::f64::consts::PI);
    assert!(matches!(
        log(half_turn),
        Err(BendelsKleinError::NoRealLogarithm(
            NoLogReason::NegativeEigenvalue { .. }
        ))
    ));
    let negative_pair = DMat4::from_scale(DVec3::new(-1.0, -2.0, 3.0));
    assert!(matches!(
        log(negative_pair),
        Err(BendelsKleinError::NoRealLogarithm(
            NoLogReason::NegativeEigenvalue { .. }
        ))
    ));
    let flat = DMat4::from_scale(DVec3::new(1.0, 0.0, 3.0));
    assert!(matches!(
        log(flat),
        Err(BendelsKleinError::NoRealLogarithm(NoLogReason::Singular))
    ));
    let mut projective = DMat4::IDENTITY;
    projective.x_axis.w = 0.5;
    assert!(matches!(
        log(projective),
        Err(BendelsKleinError::NotAffine(_))
    ));
    let mut nan = DMat4::IDENTITY;
    nan.w_axis.x = f64::NAN;
    assert!(matches!(log(nan), Err(BendelsKleinError::NonFiniteMatrix)));
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
