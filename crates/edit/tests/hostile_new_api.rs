//! Hostile arguments to the entry points that landed after the first hostile campaign
//! (issue 14): polyline and image edits, geodesic balls, selections, the BVH and
//! `Mesh::from_arrays`. Every case must return a typed error or a finite result, never
//! panic, never allocate without bound, and leave its session unchanged when it refuses.

use std::panic::{catch_unwind, AssertUnwindSafe};

use edit::bendels_klein::geodesic_ball;
use edit::bendels_klein::image::{test_pattern, ImageOptions, ImageSession, Mask, Raster};
use edit::bendels_klein::polyline::{
    CurveRegions, Polyline, PolylineOptions, PolylineSession, Span,
};
use edit::bendels_klein::Regions;
use edit::bendels_klein::{BlendOptions, BlendSession, RefineOptions};
use edit::HierarchyEdit;
use glam::{DMat3, DMat4, DVec2, DVec3};
use halfedge::bvh::{Bvh, Ray};
use halfedge::hierarchy::{Hierarchy, HierarchyOptions};
use halfedge::selection::Selection;
use halfedge::{generators, Mesh, VertexId};

/// Runs `f`, turning a panic into a failure message naming the case.
fn survive<T>(name: &str, f: impl FnOnce() -> T) -> T {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|_| panic!("{name}: panicked"))
}

const HOSTILE: [f64; 7] = [
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    1e308,
    -1e308,
    f64::MAX,
    1e-310,
];

fn curve2() -> Polyline<DVec2> {
    Polyline::open((0..12).map(|i| DVec2::new(f64::from(i), 0.0)).collect()).unwrap()
}

fn polyline_session() -> PolylineSession<DVec2> {
    let c = curve2();
    let r = CurveRegions::from_spans(&c, &[Span::new(9, 11)], &[Span::new(0, 2)]).unwrap();
    PolylineSession::new(&c, &r, PolylineOptions::default()).unwrap()
}

/// Polylines of 0, 1 and repeated points, hostile picks, transforms and refinements.
#[test]
fn polyline_entry_points_survive_hostile_arguments() {
    let mut cases = 0;
    for n in [0usize, 1, 2] {
        cases += 1;
        let pts = vec![DVec2::new(1.0, 2.0); n];
        let open = survive("open", || Polyline::open(pts.clone()));
        assert_eq!(open.is_ok(), n > 0, "open polyline of {n} points");
        assert!(survive("closed", || Polyline::closed(pts)).is_err());
    }
    // Repeated points: distances are zero along the curve, weights must stay finite.
    let rep = Polyline::open(vec![DVec2::ONE; 6]).unwrap();
    if let Ok(r) = CurveRegions::from_spans(&rep, &[Span::single(5)], &[Span::single(0)]) {
        for opts in [
            PolylineOptions::default(),
            PolylineOptions::default()
                .with_distance(edit::bendels_klein::polyline::CurveDistance::Euclidean),
        ] {
            cases += 1;
            if let Ok(mut s) = survive("repeated", || PolylineSession::new(&rep, &r, opts)) {
                assert!(s.alpha().iter().all(|a| a.is_finite()), "repeated: alpha");
                let t = DMat3::from_translation(DVec2::new(1.0, 0.0));
                if s.apply(t).is_ok() {
                    assert!(s.points().iter().all(|p| p.is_finite()), "repeated: points");
                }
            }
        }
    }
    for x in HOSTILE {
        cases += 2;
        let c = curve2();
        assert!(survive("nearest", || c.nearest(DVec2::new(x, 0.0))).is_err() || x.is_finite());
        let _ = survive("between", || {
            Span::between(&c, DVec2::new(x, 0.0), DVec2::ZERO)
        });
        for a in [
            DMat3::from_translation(DVec2::new(x, 0.0)),
            DMat3::from_scale(DVec2::splat(x)),
            DMat3::from_angle(x),
        ] {
            cases += 1;
            let mut s = polyline_session();
            let before = s.points().to_vec();
            match survive("apply", || s.apply(a)) {
                Ok(()) => assert!(
                    s.points().iter().all(|p| p.is_finite()),
                    "polyline apply {a:?}: Ok with non-finite points"
                ),
                Err(_) => assert_eq!(s.points(), &before[..], "apply {a:?}: refused but changed"),
            }
        }
        cases += 1;
        let mut s = polyline_session();
        let before = s.points().to_vec();
        let r = survive("refine", || s.refine(RefineOptions::new(x)));
        if r.is_err() {
            assert_eq!(s.points(), &before[..], "refine {x}: refused but changed");
        }
    }
    // A run-away refinement: doubling 64 times must be refused, not attempted.
    cases += 1;
    let mut s = polyline_session();
    let before = s.points().to_vec();
    let r = survive("refine unbounded", || {
        s.refine(
            RefineOptions::default()
                .with_max_edge_length(1e-300)
                .with_max_new_vertices(usize::MAX),
        )
    });
    assert!(r.is_err(), "an unbounded refinement was accepted: {r:?}");
    assert_eq!(s.points(), &before[..]);
    // Points at the edge of the range: midpoints must not overflow.
    cases += 1;
    let big = Polyline::open(
        (0..6)
            .map(|i| DVec2::new(f64::MAX * if i % 2 == 0 { 1.0 } else { 0.9 }, 0.0))
            .collect(),
    )
    .unwrap();
    let r = CurveRegions::from_spans(&big, &[Span::single(5)], &[Span::single(0)]).unwrap();
    if let Ok(mut s) = PolylineSession::new(&big, &r, PolylineOptions::default()) {
        if s.refine(RefineOptions::new(1.0)).is_ok() {
            assert!(
                s.points().iter().all(|p| p.is_finite()),
                "refine: non-finite midpoint"
            );
        }
    }
    // 3D polylines and their 4×4 transforms.
    let c3 = Polyline::open((0..8).map(|i| DVec3::new(f64::from(i), 0.0, 0.0)).collect()).unwrap();
    let r3 = CurveRegions::from_spans(&c3, &[Span::single(7)], &[Span::single(0)]).unwrap();
    for x in HOSTILE {
        cases += 1;
        let mut s = PolylineSession::new(&c3, &r3, PolylineOptions::default()).unwrap();
        let before = s.points().to_vec();
        match survive("apply 3d", || {
            s.apply(DMat4::from_translation(DVec3::splat(x)))
        }) {
            Ok(()) => assert!(s.points().iter().all(|p| p.is_finite()), "3d apply {x}"),
            Err(_) => assert_eq!(s.points(), &before[..]),
        }
    }
    eprintln!("polyline: {cases} hostile cases");
}

fn image_session() -> ImageSession {
    let image = test_pattern(24, 20).unwrap();
    let handle = Mask::polygon(
        24,
        20,
        &[
            DVec2::new(9.0, 7.0),
            DVec2::new(15.0, 7.0),
            DVec2::new(15.0, 13.0),
            DVec2::new(9.0, 13.0),
        ],
    )
    .unwrap();
    let fixed = Mask::border(24, 20, 2).unwrap();
    ImageSession::new(image, handle, fixed, ImageOptions::default()).unwrap()
}

/// Pictures of 0×N, huge declared sizes, hostile polygons and transforms.
#[test]
fn image_entry_points_survive_hostile_arguments() {
    let mut cases = 0;
    // Huge declared sizes are refused before allocating (each of these would need
    // gigabytes).
    for (w, h) in [
        (100_000, 100_000),
        (u32::MAX, 2),
        (2, u32::MAX),
        (u32::MAX, u32::MAX),
        (65_536, 65_536),
    ] {
        cases += 5;
        assert!(
            survive("filled", || Raster::filled(w, h, &[0, 0, 0, 0])).is_err(),
            "filled {w}×{h}"
        );
        assert!(
            survive("pattern", || test_pattern(w, h)).is_err(),
            "test_pattern {w}×{h}"
        );
        assert!(
            survive("mask", || Mask::empty(w, h)).is_err(),
            "Mask::empty {w}×{h}"
        );
        assert!(
            survive("border", || Mask::border(w, h, 1)).is_err(),
            "Mask::border {w}×{h}"
        );
        let tri = [DVec2::ZERO, DVec2::X, DVec2::Y];
        assert!(
            survive("polygon", || Mask::polygon(w, h, &tri)).is_err(),
            "Mask::polygon {w}×{h}"
        );
    }
    // 0×N and 1×N pictures: no grid cell, a typed error.
    for (w, h) in [(0, 0), (0, 7), (7, 0), (1, 5), (5, 1)] {
        cases += 1;
        let image = survive("pattern small", || test_pattern(w, h)).unwrap();
        let m = Mask::empty(w, h).unwrap();
        let b = survive("border small", || Mask::border(w, h, u32::MAX)).unwrap();
        let r = survive("session small", || {
            ImageSession::new(image, m, b, ImageOptions::default())
        });
        assert!(r.is_err(), "a {w}×{h} picture was accepted");
    }
    // Hostile polygons.
    for x in HOSTILE {
        cases += 1;
        let poly = [DVec2::new(x, 0.0), DVec2::new(5.0, x), DVec2::new(-x, 9.0)];
        if let Ok(m) = survive("polygon hostile", || Mask::polygon(16, 16, &poly)) {
            assert_eq!(m.bits().len(), 256);
        }
    }
    for step in [0, 1, u32::MAX] {
        cases += 1;
        let s = image_session();
        let opts = ImageOptions::default().with_grid_step(step);
        let r = survive("grid step", || {
            ImageSession::new(
                s.source().clone(),
                s.handle_mask().clone(),
                s.fixed_mask().clone(),
                opts,
            )
        });
        assert_eq!(r.is_ok(), step > 0, "grid step {step}");
    }
    for x in HOSTILE {
        for a in [
            DMat3::from_translation(DVec2::new(x, 0.0)),
            DMat3::from_scale(DVec2::splat(x)),
            DMat3::from_angle(x),
        ] {
            cases += 1;
            let mut s = image_session();
            let before = s.deformed_grid().to_vec();
            match survive("image apply", || s.apply(a)) {
                Ok(()) => {
                    assert!(
                        s.deformed_grid().iter().all(|p| p.is_finite()),
                        "image apply {a:?}: Ok with a non-finite grid"
                    );
                    let _ = survive("image render", || s.render());
                }
                Err(_) => assert_eq!(s.deformed_grid(), &before[..], "image apply {a:?}: changed"),
            }
        }
    }
    // Render into a picture of another size.
    cases += 1;
    let s = image_session();
    let mut out = Raster::filled(3, 3, &[0, 0, 0]).unwrap();
    assert!(survive("render_into", || s.render_into(&mut out)).is_err());
    eprintln!("image: {cases} hostile cases");
}

/// Geodesic balls, selections, the BVH and `from_arrays` with hostile arguments.
#[test]
fn mesh_queries_survive_hostile_arguments() {
    let mut cases = 0;
    let mesh = generators::icosphere(2);
    let other = generators::icosphere(3);
    let foreign = other.vertices().last().unwrap();
    let seed = mesh.vertices().next().unwrap();
    for r in HOSTILE.into_iter().chain([0.0, -1.0]) {
        cases += 4;
        if let Ok((sel, d)) = survive("geodesic_ball", || geodesic_ball(&mesh, &[seed], r)) {
            assert!(sel.len() <= mesh.n_vertices());
            assert!(
                d.iter().all(|x| !x.is_nan()),
                "geodesic_ball {r}: NaN distance"
            );
        }
        let _ = survive("select_ball", || mesh.select_ball(DVec3::ZERO, r));
        let _ = survive("select_edge_ball", || mesh.select_edge_ball(&[seed], r));
        if let Ok(d) = survive("edge_distances", || mesh.edge_distances(&[seed], r)) {
            assert!(d.iter().all(|x| !x.is_nan()));
        }
        for p in [DVec3::splat(r), DVec3::new(r, 0.0, 0.0)] {
            cases += 2;
            let _ = survive("nearest_vertex", || mesh.nearest_vertex(p));
            let _ = survive("extreme_vertex", || mesh.extreme_vertex(p));
            let _ = survive("ray", || Ray::new(p, DVec3::X));
            let _ = survive("ray dir", || Ray::new(DVec3::ZERO, p));
        }
    }
    // Handles of another mesh, empty seeds.
    cases += 5;
    assert!(survive("ball foreign", || geodesic_ball(&mesh, &[foreign], 1.0)).is_err());
    let _ = survive("ball empty", || geodesic_ball(&mesh, &[], 1.0));
    assert!(survive("edge foreign", || mesh.edge_distances(&[foreign], 1.0)).is_err());
    assert!(survive("linked foreign", || mesh.select_linked(&[foreign])).is_err());
    assert!(
        survive("from_vertices foreign", || Selection::from_vertices(
            &mesh,
            &[foreign]
        ))
        .is_err()
    );
    // A selection of another mesh.
    cases += 4;
    let mut sel = Selection::from_vertices(&other, &[foreign]).unwrap();
    assert!(survive("grow foreign", || sel.grow(&mesh, usize::MAX)).is_err());
    assert!(survive("shrink foreign", || sel.shrink(&mesh, usize::MAX)).is_err());
    assert!(survive("insert foreign", || sel.insert(&mesh, seed)).is_err());
    assert!(survive("from_mask", || Selection::from_mask(&mesh, vec![true; 3])).is_err());
    // usize::MAX rings.
    cases += 2;
    let mut sel = Selection::from_vertices(&mesh, &[seed]).unwrap();
    survive("grow max", || sel.grow(&mesh, usize::MAX)).unwrap();
    assert_eq!(sel.len(), mesh.n_vertices());
    survive("shrink max", || sel.shrink(&mesh, usize::MAX)).unwrap();
    // The BVH of another mesh.
    cases += 3;
    let mut bvh = Bvh::build(&mesh);
    let ray = Ray::new(DVec3::new(0.0, 0.0, 5.0), -DVec3::Z).unwrap();
    assert!(survive("bvh foreign", || bvh.intersect(&other, &ray)).is_err());
    assert!(survive("refit foreign", || bvh.refit(&other)).is_err());
    survive("update foreign", || bvh.update(&other));
    assert!(bvh.intersect(&other, &ray).unwrap().is_some());
    // from_arrays: out of range, NaN, empty.
    let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    for (name, pos, tri) in [
        ("empty", &[][..], &[][..]),
        ("no triangle", &p[..], &[][..]),
        ("index past", &p[..], &[[0, 1, u32::MAX]][..]),
        ("repeated", &p[..], &[[0, 0, 1]][..]),
        (
            "nan",
            &[[f64::NAN, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]][..],
            &[[0, 1, 2]][..],
        ),
        (
            "inf",
            &[[f64::INFINITY, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]][..],
            &[[0, 1, 2]][..],
        ),
    ] {
        cases += 1;
        let r = survive(name, || Mesh::from_arrays(pos, tri));
        if let Ok((m, _)) = r {
            m.check().unwrap();
            assert!(
                m.positions().iter().all(|p| p.is_finite()),
                "from_arrays {name}"
            );
        }
    }
    eprintln!("mesh queries: {cases} hostile cases");
}

/// Blend edits at a coarse level of a hierarchy: unbounded refinement budgets and
/// hostile transforms are refused with the hierarchy unchanged.
#[test]
fn blend_in_hierarchy_survives_hostile_arguments() {
    let mut cases = 0;
    let build = || {
        let mut h =
            Hierarchy::build(generators::icosphere(3), &HierarchyOptions::rounds()).unwrap();
        h.go_to_level(1).unwrap();
        let m = h.mesh();
        let pick = |f: &dyn Fn(DVec3) -> bool| -> Vec<VertexId> {
            m.vertices().filter(|&v| f(m.position(v))).collect()
        };
        let regions = Regions::from_sets(m, &pick(&|p| p.z > 0.8), &pick(&|p| p.z < -0.2)).unwrap();
        let s = BlendSession::new(m, regions, BlendOptions::default()).unwrap();
        (h, s)
    };
    let state = |h: &Hierarchy| {
        let m = h.mesh();
        (
            h.current_level(),
            m.positions()
                .iter()
                .map(|p| p.to_array().map(f64::to_bits))
                .collect::<Vec<_>>(),
            m.n_faces(),
        )
    };
    for budget in [usize::MAX, (1 << 22) + 1] {
        cases += 1;
        let (mut h, mut s) = build();
        s.apply(h.mesh_mut(), DMat4::from_translation(DVec3::Z))
            .unwrap();
        s.mark(&mut h).unwrap();
        let before = state(&h);
        let r = survive("refine_in_hierarchy", || {
            s.refine_in_hierarchy(
                &mut h,
                RefineOptions::default()
                    .with_max_edge_length(1e-300)
                    .with_max_new_vertices(budget),
            )
        });
        assert!(
            r.is_err(),
            "budget {budget}: an unbounded refinement was accepted"
        );
        assert_eq!(state(&h), before, "budget {budget}: refused but changed");
    }
    for x in HOSTILE {
        cases += 2;
        let (mut h, mut s) = build();
        let before = state(&h);
        let a = DMat4::from_translation(DVec3::new(x, 0.0, 0.0));
        let apply_marked = |s: &mut BlendSession, h: &mut Hierarchy| -> edit::Result<()> {
            s.apply(h.mesh_mut(), a)?;
            s.mark(h)
        };
        match survive("apply and mark", || apply_marked(&mut s, &mut h)) {
            Ok(()) => {
                assert!(
                    h.mesh().positions().iter().all(|p| p.is_finite()),
                    "apply {x}"
                );
                if survive("walk", || h.refine_to(0)).is_ok() {
                    let bad = h
                        .mesh()
                        .positions()
                        .iter()
                        .filter(|p| !p.is_finite())
                        .count();
                    assert_eq!(
                        bad, 0,
                        "translation {x}: {bad} non-finite after refine_to(0)"
                    );
                }
            }
            Err(_) => assert_eq!(state(&h), before, "apply {x}: refused but changed"),
        }
        let (mut h, s) = build();
        let before = state(&h);
        if survive("refine hostile", || {
            s.refine_in_hierarchy(
                &mut h,
                RefineOptions::default()
                    .with_max_edge_length(x)
                    .with_max_new_vertices(200),
            )
        })
        .is_err()
        {
            assert_eq!(state(&h), before, "refine {x}: refused but changed");
        }
    }
    eprintln!("blend in hierarchy: {cases} hostile cases");
}
