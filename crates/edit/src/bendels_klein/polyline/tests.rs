use glam::{DMat3, DMat4, DVec2, DVec3};

use super::*;
use crate::bendels_klein::affine_power::{embed_affine2, scalar_power, AffinePower};
use crate::bendels_klein::blend::{blend_ratio, RefineOptions};
use crate::bendels_klein::error::{BendelsKleinError, RegionKind, Site};
use crate::bendels_klein::regions::Role;
use crate::bendels_klein::shape::ShapeFunction;

/// The curve of the paper's Fig. 2: 14 points, gently waving along x.
fn fig2_points(n: usize) -> Vec<DVec2> {
    (0..n)
        .map(|i| {
            let x = i as f64 * 13.0 / (n - 1) as f64;
            DVec2::new(x, 0.3 * (0.9 * x).sin())
        })
        .collect()
}

/// Rotation by `deg` about `pivot`, then a translation.
fn rigid2(deg: f64, pivot: DVec2, shift: DVec2) -> DMat3 {
    DMat3::from_translation(pivot + shift)
        * DMat3::from_angle(deg.to_radians())
        * DMat3::from_translation(-pivot)
}

fn blend_reference(alpha: f64, a: DMat3, p: DVec2) -> DVec2 {
    scalar_power(alpha, embed_affine2(a))
        .unwrap()
        .transform_point3(p.extend(0.0))
        .truncate()
}

#[test]
fn fig2_fixed_bit_for_bit_handle_exact_deformable_blended() {
    let curve = Polyline::open(fig2_points(14)).unwrap();
    let regions = CurveRegions::from_spans(
        &curve,
        &[Span::new(4, 8)],
        &[Span::new(0, 2), Span::new(10, 13)],
    )
    .unwrap();
    assert_eq!(regions.count(Role::Deformable), 2); // v3 and v9
    let a = rigid2(35.0, DVec2::new(6.0, 0.0), DVec2::new(0.5, 2.0));
    for distance in [CurveDistance::ArcLength, CurveDistance::Euclidean] {
        let options = PolylineOptions {
            distance,
            shape: ShapeFunction::Smoothstep,
        };
        let mut session = PolylineSession::new(&curve, &regions, options).unwrap();
        session.apply(a).unwrap();
        for (i, (&p, &o)) in session.points().iter().zip(curve.points()).enumerate() {
            match regions.roles()[i] {
                Role::Fixed => assert_eq!(
                    p.to_array().map(f64::to_bits),
                    o.to_array().map(f64::to_bits)
                ),
                Role::Handle => assert_eq!(p, a.transform_point2(o), "handle point {i}"),
                Role::Deformable => {
                    let alpha = session.alpha()[i];
                    assert!(alpha > 0.0 && alpha < 1.0, "α of v{i} is {alpha}");
                    assert!((p - blend_reference(alpha, a, o)).length() < 1e-12);
                }
            }
        }
        // v3 is one segment from the fixed v2 and one from the handle v4: halfway, as
        // is v9 (arc length); α = f(1/2) = 1/2 for smoothstep.
        if distance == CurveDistance::ArcLength {
            let d = |i: usize, j: usize| curve.points()[i].distance(curve.points()[j]);
            let x3 = d(2, 3) / (d(2, 3) + d(3, 4));
            assert!((session.alpha()[3] - ShapeFunction::Smoothstep.eval(x3)).abs() < 1e-15);
        }
    }
}

#[test]
fn fig2_dense_alpha_is_monotone_along_the_deformable_part() {
    // 141 points: fixed 0..=20 and 110..=140, handle 50..=80, deformable between.
    let curve = Polyline::open(fig2_points(141)).unwrap();
    let regions = CurveRegions::from_spans(
        &curve,
        &[Span::new(50, 80)],
        &[Span::new(0, 20), Span::new(110, 140)],
    )
    .unwrap();
    for shape in [
        ShapeFunction::Linear,
        ShapeFunction::Smoothstep,
        ShapeFunction::Smootherstep,
    ] {
        let options = PolylineOptions {
            distance: CurveDistance::ArcLength,
            shape,
        };
        let session = PolylineSession::new(&curve, &regions, options).unwrap();
        let alpha = session.alpha();
        // Rising from the left fixed part to the handle, falling after it.
        for i in 21..50 {
            assert!(alpha[i] > alpha[i - 1], "α not increasing at {i}");
        }
        for i in 81..110 {
            assert!(alpha[i] < alpha[i - 1], "α not decreasing at {i}");
        }
        assert_eq!(alpha[20], 0.0);
        assert_eq!(alpha[50], 1.0);
    }
}

#[test]
fn fig3_euclidean_alpha_turns_back_where_arc_length_does_not() {
    // Out along y = 0, up x = 8, across, and down x = 11 to the handle at the end: on
    // the way up the curve moves away from the handle, so the Euclidean ratio falls.
    let mut points: Vec<DVec2> = (0..=8).map(|i| DVec2::new(i as f64, 0.0)).collect();
    points.extend((1..=8).map(|i| DVec2::new(8.0, i as f64)));
    points.extend((9..=11).map(|i| DVec2::new(i as f64, 8.0)));
    points.extend((0..=7).rev().map(|i| DVec2::new(11.0, i as f64)));
    let curve = Polyline::open(points).unwrap();
    let n = curve.len();
    let regions =
        CurveRegions::from_spans(&curve, &[Span::new(n - 3, n - 1)], &[Span::new(0, 2)]).unwrap();
    let arc = PolylineSession::new(&curve, &regions, PolylineOptions::default()).unwrap();
    for i in 4..n - 3 {
        assert!(arc.alpha()[i] > arc.alpha()[i - 1]);
    }
    let euclid = PolylineSession::new(
        &curve,
        &regions,
        PolylineOptions {
            distance: CurveDistance::Euclidean,
            shape: ShapeFunction::Linear,
        },
    )
    .unwrap();
    let a = euclid.alpha();
    assert!(
        (4..n - 3).any(|i| a[i] < a[i - 1]),
        "Euclidean α should fall somewhere along the hairpin"
    );
    // Euclidean distances are the distances to the parts' segments.
    let p = curve.points();
    for i in 3..n - 3 {
        let seg = |a: usize, b: usize| {
            crate::bendels_klein::distance::euclidean::point_segment_distance(
                p[i].extend(0.0),
                p[a].extend(0.0),
                p[b].extend(0.0),
            )
        };
        assert_eq!(
            euclid.handle_distances()[i],
            seg(n - 3, n - 2).min(seg(n - 2, n - 1))
        );
        assert_eq!(euclid.fixed_distances()[i], seg(0, 1).min(seg(1, 2)));
    }
}

#[test]
fn three_d_polyline_blends_4x4_transforms() {
    let points: Vec<DVec3> = (0..60)
        .map(|i| {
            let t = i as f64 * 0.1;
            DVec3::new(t.cos() * 3.0, t.sin() * 3.0, 0.2 * t)
        })
        .collect();
    let curve = Polyline::open(points).unwrap();
    let regions =
        CurveRegions::from_spans(&curve, &[Span::new(40, 59)], &[Span::new(0, 9)]).unwrap();
    let mut session = PolylineSession::new(&curve, &regions, PolylineOptions::default()).unwrap();
    let a = DMat4::from_translation(DVec3::new(0.0, 0.0, 2.0))
        * DMat4::from_axis_angle(DVec3::new(1.0, 1.0, 0.0).normalize(), 0.8)
        * DMat4::from_scale(DVec3::splat(1.3));
    session.apply(a).unwrap();
    for (i, (&p, &o)) in session.points().iter().zip(curve.points()).enumerate() {
        match session.roles()[i] {
            Role::Fixed => assert_eq!(p, o),
            Role::Handle => assert_eq!(p, a.transform_point3(o)),
            Role::Deformable => {
                let expected = scalar_power(session.alpha()[i], a)
                    .unwrap()
                    .transform_point3(o);
                assert!((p - expected).length() < 1e-11);
            }
        }
    }
}

#[test]
fn closed_polygon_spans_wrap_and_both_ways_count() {
    // A circle of 40 points; the handle wraps around index 0.
    let points: Vec<DVec2> = (0..40)
        .map(|i| {
            let t = i as f64 / 40.0 * std::f64::consts::TAU;
            DVec2::new(t.cos(), t.sin())
        })
        .collect();
    let curve = Polyline::closed(points).unwrap();
    let regions =
        CurveRegions::from_spans(&curve, &[Span::new(38, 2)], &[Span::new(15, 25)]).unwrap();
    assert_eq!(regions.count(Role::Handle), 5);
    let session = PolylineSession::new(&curve, &regions, PolylineOptions::default()).unwrap();
    // Symmetric about the x axis: point k and point 40 − k have the same weight.
    for k in 3..15 {
        let (a, b) = (session.alpha()[k], session.alpha()[40 - k]);
        assert!((a - b).abs() < 1e-12, "{k}: {a} vs {b}");
    }
    // d_handle of point 3 is one chord, of point 14 twelve chords.
    let chord = curve.points()[0].distance(curve.points()[1]);
    assert!((session.handle_distances()[3] - chord).abs() < 1e-12);
    assert!((session.handle_distances()[14] - 12.0 * chord).abs() < 1e-12);
    assert!((session.fixed_distances()[14] - chord).abs() < 1e-12);
    // Picking: the points nearest to two positions, forward on a polygon.
    let span = Span::between(&curve, DVec2::new(0.9, -0.3), DVec2::new(0.9, 0.3)).unwrap();
    assert_eq!(span, Span::new(38, 2));
}

#[test]
fn out_of_reach_parts_give_the_documented_weights() {
    // Open: deformable tails beyond the handle follow it; beyond the fixed part stay.
    let curve = Polyline::open(fig2_points(20)).unwrap();
    let regions =
        CurveRegions::from_spans(&curve, &[Span::new(12, 14)], &[Span::new(4, 6)]).unwrap();
    let mut session = PolylineSession::new(&curve, &regions, PolylineOptions::default()).unwrap();
    let a = DMat3::from_translation(DVec2::new(0.0, 3.0));
    session.apply(a).unwrap();
    for i in 0..4 {
        assert_eq!(session.alpha()[i], 0.0);
        assert_eq!(session.points()[i], curve.points()[i]);
    }
    for i in 15..20 {
        assert_eq!(session.alpha()[i], 1.0);
        assert!((session.points()[i] - a.transform_point2(curve.points()[i])).length() < 1e-12);
    }
}

#[test]
fn bad_input_is_refused_with_typed_errors() {
    assert!(matches!(
        Polyline::<DVec2>::open(vec![]),
        Err(BendelsKleinError::EmptyPolyline)
    ));
    assert!(matches!(
        Polyline::closed(vec![DVec2::ZERO, DVec2::X]),
        Err(BendelsKleinError::TooFewPoints { points: 2 })
    ));
    assert!(matches!(
        Polyline::open(vec![DVec2::ZERO, DVec2::new(f64::NAN, 0.0)]),
        Err(BendelsKleinError::NonFinitePoint { index: 1 })
    ));
    let curve = Polyline::open(fig2_points(14)).unwrap();
    assert!(matches!(
        curve.nearest(DVec2::new(f64::INFINITY, 0.0)),
        Err(BendelsKleinError::NonFinitePoint { .. })
    ));
    let spans = |h: Span, f: Span| CurveRegions::from_spans(&curve, &[h], &[f]);
    assert!(matches!(
        spans(Span::new(4, 14), Span::new(0, 1)),
        Err(BendelsKleinError::OutOfRange {
            last: 14,
            len: 14,
            ..
        })
    ));
    assert!(matches!(
        spans(Span::new(8, 4), Span::new(0, 1)),
        Err(BendelsKleinError::SpanWrapsOpen { .. })
    ));
    assert!(matches!(
        spans(Span::new(4, 8), Span::new(8, 12)),
        Err(BendelsKleinError::Overlap {
            site: Site::Point(8)
        })
    ));
    assert!(matches!(
        spans(Span::new(4, 8), Span::new(9, 12)),
        Err(BendelsKleinError::HandleTouchesFixed {
            handle: Site::Point(8),
            fixed: Site::Point(9)
        })
    ));
    assert!(matches!(
        CurveRegions::from_spans(&curve, &[], &[Span::new(0, 2)]),
        Err(BendelsKleinError::EmptyRegion(RegionKind::Handle))
    ));
    assert!(matches!(
        CurveRegions::from_spans(&curve, &[Span::single(5)], &[]),
        Err(BendelsKleinError::EmptyRegion(RegionKind::Fixed))
    ));
    assert!(matches!(
        CurveRegions::from_roles(&curve, vec![Role::Fixed; 3]),
        Err(BendelsKleinError::RoleCount {
            roles: 3,
            points: 14
        })
    ));
    // Regions of another polyline, longer or of the same length, are stale.
    for n in [20, 14] {
        let other = Polyline::open(fig2_points(n)).unwrap();
        let regions =
            CurveRegions::from_spans(&other, &[Span::new(4, 8)], &[Span::new(0, 2)]).unwrap();
        assert!(matches!(
            PolylineSession::new(&curve, &regions, PolylineOptions::default()),
            Err(BendelsKleinError::Stale(_))
        ));
    }
}

#[test]
fn refused_transforms_leave_the_session_unchanged() {
    let curve = Polyline::open(fig2_points(14)).unwrap();
    let regions = CurveRegions::from_spans(&curve, &[Span::new(4, 8)], &[Span::new(0, 2)]).unwrap();
    let mut session = PolylineSession::new(&curve, &regions, PolylineOptions::default()).unwrap();
    let a = rigid2(20.0, DVec2::ZERO, DVec2::new(1.0, 1.0));
    session.apply(a).unwrap();
    let before = session.points().to_vec();
    let mirror = DMat3::from_scale(DVec2::new(-1.0, 1.0));
    assert!(matches!(
        session.apply(mirror),
        Err(BendelsKleinError::NoRealLogarithm(_))
    ));
    let half_turn = DMat3::from_angle(std::f64::consts::PI);
    assert!(session.apply(half_turn).is_err());
    let mut projective = DMat3::IDENTITY;
    projective.x_axis.z = 0.5;
    assert!(matches!(
        session.apply(projective),
        Err(BendelsKleinError::NotAffine(_))
    ));
    let mut nan = a;
    nan.z_axis.x = f64::NAN;
    assert!(session.apply(nan).is_err());
    assert_eq!(session.points(), &before[..]);
    assert_eq!(session.transform(), a);
    assert!(session.refine(RefineOptions::new(0.0)).is_err());
    assert!(session.refine(RefineOptions::new(f64::NAN)).is_err());
    assert_eq!(session.points(), &before[..]);
    session.reset();
    assert_eq!(session.points(), curve.points());
}

#[test]
fn shape_changes_reweight_without_new_distances() {
    let curve = Polyline::open(fig2_points(60)).unwrap();
    let regions =
        CurveRegions::from_spans(&curve, &[Span::new(30, 35)], &[Span::new(0, 5)]).unwrap();
    let mut session = PolylineSession::new(&curve, &regions, PolylineOptions::default()).unwrap();
    let a = DMat3::from_translation(DVec2::new(0.0, 2.0));
    session.apply(a).unwrap();
    let smooth = session.points()[15];
    let d = session.handle_distances().to_vec();
    session.set_shape(ShapeFunction::Linear);
    assert_eq!(session.handle_distances(), &d[..]);
    let x = blend_ratio(session.fixed_distances()[15], d[15]);
    assert!((session.alpha()[15] - x).abs() < 1e-15);
    assert_ne!(session.points()[15], smooth);
    // A translation blends linearly: the point moves by α t.
    assert!(
        (session.points()[15] - (curve.points()[15] + DVec2::new(0.0, 2.0 * x))).length() < 1e-12
    );
}

#[test]
fn refinement_inserts_blended_midpoints_until_no_segment_is_long() {
    for distance in [CurveDistance::ArcLength, CurveDistance::Euclidean] {
        let curve = Polyline::open(fig2_points(14)).unwrap();
        let regions = CurveRegions::from_spans(
            &curve,
            &[Span::new(6, 7)],
            &[Span::new(0, 2), Span::new(11, 13)],
        )
        .unwrap();
        let options = PolylineOptions {
            distance,
            shape: ShapeFunction::Smoothstep,
        };
        let mut session = PolylineSession::new(&curve, &regions, options).unwrap();
        let a = DMat3::from_translation(DVec2::new(0.0, 6.0));
        session.apply(a).unwrap();
        let max = 0.5;
        let report = session.refine(RefineOptions::new(max)).unwrap();
        assert!(report.new_vertices > 20, "{report:?}");
        assert!(report.longest_edge <= max);
        let n = session.points().len();
        assert_eq!(n, 14 + report.new_vertices);
        // The fixed points are the originals, in order, bit for bit; every deformable
        // point is the blend of its original.
        let fixed: Vec<DVec2> = (0..n)
            .filter(|&i| session.roles()[i] == Role::Fixed)
            .map(|i| session.points()[i])
            .collect();
        let expected: Vec<DVec2> = [0, 1, 2, 11, 12, 13].map(|i| curve.points()[i]).to_vec();
        assert_eq!(fixed, expected);
        let power = AffinePower::new(embed_affine2(a)).unwrap();
        for i in 0..n {
            let o = session.original_points()[i];
            let p = session.points()[i];
            match session.roles()[i] {
                Role::Handle => assert_eq!(p, a.transform_point2(o)),
                Role::Deformable => {
                    assert_eq!(p, power.transform_point2(session.alpha()[i], o));
                }
                Role::Fixed => {}
            }
        }
        // Arc length: still monotone on the refined curve, and the new points' distances
        // are exact arc lengths.
        if distance == CurveDistance::ArcLength {
            let alpha = session.alpha();
            let h = (0..n)
                .position(|i| session.roles()[i] == Role::Handle)
                .unwrap();
            let f = (0..n)
                .position(|i| i > h && session.roles()[i] == Role::Fixed)
                .unwrap();
            let first_deformable = (0..n)
                .position(|i| session.roles()[i] == Role::Deformable)
                .unwrap();
            for i in first_deformable + 1..h {
                assert!(alpha[i] > alpha[i - 1]);
            }
            for i in h + 3..f {
                assert!(alpha[i] < alpha[i - 1]);
            }
            let o = session.original_points();
            let mut arc = 0.0;
            for i in (first_deformable..h).rev() {
                arc += o[i].distance(o[i + 1]);
                assert!((session.handle_distances()[i] - arc).abs() < 1e-12);
            }
        }
        // A budget stops early.
        let mut capped = PolylineSession::new(
            &curve,
            &regions,
            PolylineOptions {
                distance,
                shape: ShapeFunction::Smoothstep,
            },
        )
        .unwrap();
        capped.apply(a).unwrap();
        let report = capped
            .refine(RefineOptions {
                max_edge_length: max,
                max_new_vertices: 3,
            })
            .unwrap();
        assert_eq!(report.new_vertices, 3);
        assert_eq!(capped.points().len(), 17);
    }
}

#[test]
fn plane_blend_agrees_with_the_space_blend() {
    for (deg, s) in [(10.0, 1.0), (89.0, 0.5), (120.0, 2.0), (-60.0, 1.5)] {
        let a = DMat3::from_translation(DVec2::new(3.0, -1.0))
            * DMat3::from_angle(f64::to_radians(deg))
            * DMat3::from_scale(DVec2::new(s, 1.0 / s.sqrt()));
        let power = AffinePower::new(embed_affine2(a)).unwrap();
        let p = DVec2::new(0.7, -2.3);
        for k in 0..=20 {
            let alpha = k as f64 / 20.0;
            let q = power.transform_point2(alpha, p);
            let r = power.transform_point(alpha, p.extend(0.0));
            assert!((q - r.truncate()).length() < 1e-13);
            assert!(r.z.abs() < 1e-13);
        }
        assert_eq!(power.transform_point2(1.0, p), a.transform_point2(p));
        assert_eq!(power.transform_point2(0.0, p), p);
        // half of A twice is A
        let half = power.matrix(0.5);
        let twice = half * half;
        assert!(
            (twice.transform_point3(p.extend(0.0)).truncate() - a.transform_point2(p)).length()
                < 1e-12
        );
    }
}
