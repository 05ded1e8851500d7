//! Multilevel B-spline approximation (Lee, Wolberg & Shin 1997) with the scale parameter
//! and boundary fixing of Lee 1999 §5: analytic cases and the paper's figures.

use edit::lee::mba::{Mba, MbaBase};
use edit::lee::LeeError;
use glam::{DVec2, DVec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn random_points(n: usize, min: DVec2, max: DVec2, seed: u64) -> Vec<DVec2> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| min + (max - min) * DVec2::new(rng.random::<f64>(), rng.random::<f64>()))
        .collect()
}

fn smooth(p: DVec2) -> DVec3 {
    DVec3::new(
        (3.0 * p.x).sin() * (2.0 * p.y).cos(),
        p.x * p.y - 0.5 * p.y,
        (p.x - 1.0).powi(2) + 0.25 * (5.0 * p.y).sin(),
    )
}

#[test]
fn constants_and_planes_are_reproduced_exactly_with_a_base() {
    let (min, max) = (DVec2::new(-1.0, 2.0), DVec2::new(3.0, 4.0));
    let points = random_points(60, min, max, 1);
    let probes = random_points(200, min, max, 2);
    let constant = DVec3::new(0.7, -2.0, 5.5);
    let plane = |p: DVec2| DVec3::new(1.0 + 2.0 * p.x - p.y, -0.5 * p.x, 3.0 + 0.25 * p.y);
    for levels in [1, 4, 8] {
        let mba = Mba::new(min, max, levels).unwrap();
        let values = vec![constant; points.len()];
        for base in [MbaBase::Mean, MbaBase::Plane] {
            let f = mba.clone().with_base(base).fit(&points, &values).unwrap();
            for &p in probes.iter().chain(&points) {
                assert!(
                    (f.evaluate(p) - constant).length() < 1e-12,
                    "{base:?} l={levels} at {p}"
                );
            }
        }
        let values: Vec<DVec3> = points.iter().map(|&p| plane(p)).collect();
        let f = mba.with_base(MbaBase::Plane).fit(&points, &values).unwrap();
        for &p in &probes {
            assert!(
                (f.evaluate(p) - plane(p)).length() < 1e-11,
                "plane l={levels} at {p}"
            );
        }
    }
}

#[test]
fn a_single_point_is_interpolated_at_every_level() {
    let mba = Mba::new(DVec2::ZERO, DVec2::ONE, 6).unwrap();
    let p = [DVec2::new(0.37, 0.61)];
    let z = [DVec3::new(1.0, -2.0, 0.5)];
    for k in 1..=6 {
        let f = mba.fit_from_level(k, &p, &z).unwrap();
        assert!((f.evaluate(p[0]) - z[0]).length() < 1e-14, "f_{k}");
    }
}

#[test]
fn error_at_the_data_points_falls_as_levels_are_added() {
    let (min, max) = (DVec2::ZERO, DVec2::new(2.0, 1.0));
    let points = random_points(300, min, max, 3);
    let values: Vec<DVec3> = points.iter().map(|&p| smooth(p)).collect();
    let max_error = |levels: usize| {
        let f = Mba::new(min, max, levels)
            .unwrap()
            .fit(&points, &values)
            .unwrap();
        (0..points.len())
            .map(|c| (f.evaluate(points[c]) - values[c]).length())
            .fold(0.0, f64::max)
    };
    let errors: Vec<f64> = (1..=11).map(max_error).collect();
    for l in 1..errors.len() {
        assert!(
            errors[l] < errors[l - 1],
            "levels {} → {}: {:?}",
            l,
            l + 1,
            errors
        );
    }
    assert!(errors[10] < 1e-3 * errors[0], "{errors:?}");
    // The paper's zero base also reproduces a constant at the data points, to MBA accuracy.
    let constant = vec![DVec3::ONE; points.len()];
    let f = Mba::new(min, max, 11)
        .unwrap()
        .fit(&points, &constant)
        .unwrap();
    for &p in &points {
        assert!((f.evaluate(p) - DVec3::ONE).length() < 1e-3);
    }
}

#[test]
fn scale_seven_twelfths_is_the_average_of_two_thirds_and_one_half() {
    // Lee 1999 Fig. 3/4: l = 6; m_1 = 4, 8 (f_3, f_4) belong to s = 2/3, 1/2.
    let points = random_points(40, DVec2::ZERO, DVec2::ONE, 4);
    let values: Vec<DVec3> = points.iter().map(|&p| smooth(p)).collect();
    let mba = Mba::new(DVec2::ZERO, DVec2::ONE, 6).unwrap();
    let f_two_thirds = mba.fit_scaled(2.0 / 3.0, &points, &values).unwrap();
    let f_half = mba.fit_scaled(0.5, &points, &values).unwrap();
    let f_seven_twelfths = mba.fit_scaled(7.0 / 12.0, &points, &values).unwrap();
    // s = 2/3 and 1/2 are f_3 and f_4 themselves
    let f3 = mba.fit_from_level(3, &points, &values).unwrap();
    let f4 = mba.fit_from_level(4, &points, &values).unwrap();
    assert_eq!(f3.lattice().m(), 32);
    for &p in random_points(100, DVec2::ZERO, DVec2::ONE, 5)
        .iter()
        .chain(&points)
    {
        assert!((f_two_thirds.evaluate(p) - f3.evaluate(p)).length() < 1e-12);
        assert!((f_half.evaluate(p) - f4.evaluate(p)).length() < 1e-12);
        let average = 0.5 * (f_two_thirds.evaluate(p) + f_half.evaluate(p));
        assert!(
            (f_seven_twelfths.evaluate(p) - average).length() < 1e-12,
            "at {p}"
        );
    }
    // a smaller scale has a narrower influence (Fig. 3): the support of one data point
    let p = [DVec2::new(0.4, 0.55)];
    let z = [DVec3::ONE];
    let support = |s: f64| {
        let f = mba.fit_scaled(s, &p, &z).unwrap();
        let mut count = 0;
        for i in 0..=200 {
            for j in 0..=200 {
                let q = DVec2::new(i as f64, j as f64) / 200.0;
                count += usize::from(f.evaluate(q) != DVec3::ZERO);
            }
        }
        count
    };
    let supports: Vec<usize> = [1.0, 5.0 / 6.0, 2.0 / 3.0, 0.5, 1.0 / 3.0, 1.0 / 6.0, 0.0]
        .into_iter()
        .map(support)
        .collect();
    // m = 1, 2, 4 lattices reach the whole square; from m = 8 on the support shrinks
    assert!(supports.windows(2).all(|w| w[1] <= w[0]), "{supports:?}");
    assert!(
        supports[3..].windows(2).all(|w| w[1] < w[0]),
        "{supports:?}"
    );
    assert_eq!(supports[6], 1, "s = 0 touches the data point only");
}

#[test]
fn scale_zero_is_the_data_only_and_scale_one_the_full_fit() {
    let points = random_points(20, DVec2::ZERO, DVec2::ONE, 6);
    let values: Vec<DVec3> = points.iter().map(|&p| smooth(p)).collect();
    let mba = Mba::new(DVec2::ZERO, DVec2::ONE, 5).unwrap();
    let f0 = mba.fit_scaled(0.0, &points, &values).unwrap();
    for (c, &p) in points.iter().enumerate() {
        assert_eq!(f0.evaluate(p), values[c]);
    }
    assert_eq!(f0.evaluate(DVec2::new(0.123456, 0.654321)), DVec3::ZERO);
    let f1 = mba.fit_scaled(1.0, &points, &values).unwrap();
    let full = mba.fit(&points, &values).unwrap();
    assert_eq!(f1, full);
    // on the last interval the data-only function takes weight t = (s_l − s) l
    let f = mba.fit_scaled(0.1, &points, &values).unwrap();
    assert!((f.data_weight() - 0.5).abs() < 1e-12);
    let f5 = mba.fit_from_level(5, &points, &values).unwrap();
    for (c, &p) in points.iter().enumerate() {
        let expected = 0.5 * f5.evaluate(p) + 0.5 * values[c];
        assert!((f.evaluate(p) - expected).length() < 1e-12);
    }
}

#[test]
fn fixed_boundary_vanishes_on_the_border_and_fits_inside() {
    let (min, max) = (DVec2::ZERO, DVec2::new(3.0, 2.0));
    // data well inside (more than three finest cells from the border)
    let points = random_points(30, DVec2::new(0.8, 0.6), DVec2::new(2.2, 1.4), 7);
    let values: Vec<DVec3> = points.iter().map(|&p| smooth(p)).collect();
    let mba = Mba::new(min, max, 8).unwrap().with_fixed_boundary(true);
    let f = mba.fit(&points, &values).unwrap();
    for k in 0..=100 {
        let a = k as f64 / 100.0;
        for p in [
            DVec2::new(3.0 * a, 0.0),
            DVec2::new(3.0 * a, 2.0),
            DVec2::new(0.0, 2.0 * a),
            DVec2::new(3.0, 2.0 * a),
        ] {
            assert_eq!(f.evaluate(p), DVec3::ZERO, "at {p}");
        }
    }
    for (c, &p) in points.iter().enumerate() {
        assert!(
            (f.evaluate(p) - values[c]).length() < 0.05,
            "data point {c}"
        );
    }
}

#[test]
fn bad_data_is_refused() {
    let mba = Mba::new(DVec2::ZERO, DVec2::ONE, 4).unwrap();
    let p = [DVec2::splat(0.5)];
    assert!(matches!(
        mba.fit(&p, &[]),
        Err(LeeError::MbaLengthMismatch {
            points: 1,
            values: 0
        })
    ));
    assert!(matches!(
        mba.fit(&p, &[DVec3::new(f64::NAN, 0.0, 0.0)]),
        Err(LeeError::MbaNonFiniteData { index: 0 })
    ));
    assert!(matches!(
        mba.fit(&[DVec2::new(1.5, 0.5)], &[DVec3::ONE]),
        Err(LeeError::MbaPointOutsideDomain { index: 0, .. })
    ));
    assert!(matches!(
        mba.fit_scaled(1.5, &p, &[DVec3::ONE]),
        Err(LeeError::InvalidParameter { name: "s", .. })
    ));
    assert!(matches!(
        mba.clone()
            .with_fixed_boundary(true)
            .with_base(MbaBase::Mean)
            .fit(&p, &[DVec3::ONE]),
        Err(LeeError::InvalidParameter { name: "base", .. })
    ));
    assert!(Mba::new(DVec2::ONE, DVec2::ZERO, 4).is_err());
    assert!(Mba::new(DVec2::ZERO, DVec2::ONE, 0).is_err());
    // no data: the zero function
    let f = mba.fit(&[], &[]).unwrap();
    assert_eq!(f.evaluate(DVec2::splat(0.3)), DVec3::ZERO);
}
