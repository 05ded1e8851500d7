//! Reaching the face target: rounds keep the paper's planarity criterion while it
//! works and widen their bounds only when they stall short of the target; every build
//! says how it ended (`Hierarchy::build_outcome`). On generated meshes.

use halfedge::hierarchy::StopReason;
use halfedge::hierarchy::{Hierarchy, HierarchyOptions};
use halfedge::{generators, Mesh};
use testkit::check::snapshot;
use testkit::data_dir;

/// The bumpy sphere of `data/` (20,480 faces): the paper's rounds stall near 100 faces.
fn blob() -> Mesh {
    halfedge::io::read(data_dir().join("blob.obj")).unwrap().0
}

#[test]
fn rounds_widen_their_bounds_only_after_they_stall_and_then_reach_the_target() {
    let mesh = blob();
    let before = snapshot(&mesh);
    let paper = Hierarchy::build(
        mesh.clone(),
        &HierarchyOptions::rounds()
            .with_target_faces(40)
            .with_relax_when_stalled(false),
    )
    .unwrap();
    let stalled_at = paper.mesh().n_faces();
    assert!(
        stalled_at > 60,
        "the paper's rounds should stall above 40 faces here"
    );
    let outcome = paper.build_outcome();
    assert!(!outcome.target_reached());
    let StopReason::Stalled {
        refusals: Some(refusals),
    } = outcome.stop
    else {
        panic!("{outcome:?}")
    };
    assert!(refusals.planarity > 0, "{refusals:?}");
    assert!(outcome.relaxations.is_empty());
    let text = outcome.to_string();
    assert!(
        text.contains("short of the target of 40") && text.contains("planarity"),
        "{text}"
    );

    let mut relaxed =
        Hierarchy::build(mesh, &HierarchyOptions::rounds().with_target_faces(40)).unwrap();
    relaxed.mesh().check().unwrap();
    let faces = relaxed.mesh().n_faces();
    assert!((38..=40).contains(&faces), "{faces} faces");
    let outcome = relaxed.build_outcome().clone();
    assert_eq!(outcome.stop, StopReason::TargetReached);
    assert!(outcome.target_reached());
    assert!(!outcome.relaxations.is_empty());
    // The levels before the first stall are the paper's, face for face.
    let first = outcome.relaxations[0];
    assert_eq!(first.faces, stalled_at);
    let n = first.level;
    assert_eq!(
        &relaxed.level_face_counts()[..n],
        &paper.level_face_counts()[..n]
    );
    // Widened bounds only grow, planarity first, within 180° and 90°.
    let mut last = (60f64.to_radians(), 45f64.to_radians());
    for r in &outcome.relaxations {
        assert!(r.max_normal_deviation >= last.0 && r.max_flip_angle >= last.1);
        assert!(r.max_normal_deviation <= std::f64::consts::PI + 1e-12);
        assert!(r.max_flip_angle <= std::f64::consts::FRAC_PI_2 + 1e-12);
        if r.max_flip_angle > 45f64.to_radians() + 1e-9 {
            assert!((r.max_normal_deviation - std::f64::consts::PI).abs() < 1e-9);
        }
        last = (r.max_normal_deviation, r.max_flip_angle);
    }
    assert!(outcome.to_string().contains("widened"), "{outcome}");
    // The hierarchy is a hierarchy like any other: back to the input exactly.
    relaxed.refine_to(0).unwrap();
    assert!(snapshot(relaxed.mesh()) == before);
}

#[test]
fn without_a_target_rounds_stop_at_the_first_stall_as_in_the_paper() {
    let mesh = generators::icosphere(4);
    let default = Hierarchy::build(mesh.clone(), &HierarchyOptions::rounds()).unwrap();
    let paper = Hierarchy::build(
        mesh,
        &HierarchyOptions::rounds().with_relax_when_stalled(false),
    )
    .unwrap();
    assert_eq!(default.level_face_counts(), paper.level_face_counts());
    let outcome = default.build_outcome();
    assert!(matches!(
        outcome.stop,
        StopReason::Exhausted { refusals: Some(_) }
    ));
    assert!(outcome.relaxations.is_empty() && outcome.target_reached());
}

#[test]
fn a_target_within_the_papers_reach_needs_no_widening() {
    let h = Hierarchy::build(
        generators::icosphere(4),
        &HierarchyOptions::rounds().with_target_faces(1000),
    )
    .unwrap();
    let outcome = h.build_outcome();
    assert_eq!(outcome.stop, StopReason::TargetReached);
    assert!(outcome.relaxations.is_empty());
    assert_eq!(
        (outcome.target_faces, outcome.faces),
        (1000, h.mesh().n_faces())
    );
    assert!(outcome
        .to_string()
        .starts_with("reached the target of 1000 faces"));
}

#[test]
fn an_unreachable_target_is_explained() {
    // Twelve small spheres: each can shrink to a few faces, never to nothing.
    let spheres: Vec<Mesh> = (0..12)
        .map(|k| {
            let mut s = generators::icosphere(1);
            for p in s.positions_mut() {
                p.x += 3.0 * k as f64;
            }
            s
        })
        .collect();
    let refs: Vec<&Mesh> = spheres.iter().collect();
    let mesh = generators::disjoint_union(&refs).unwrap();
    for options in [HierarchyOptions::rounds(), HierarchyOptions::qem()] {
        let h = Hierarchy::build(mesh.clone(), &options.clone().with_target_faces(20)).unwrap();
        h.mesh().check().unwrap();
        let outcome = h.build_outcome();
        assert!(h.mesh().n_faces() >= 12 * 4, "{}", h.mesh().n_faces());
        assert!(!outcome.target_reached(), "{outcome}");
        match &outcome.stop {
            StopReason::Stalled { refusals: Some(r) } => {
                assert_eq!(options.method, halfedge::hierarchy::Method::Rounds);
                assert!(r.topology > 0, "{r:?}");
                assert_eq!(r.planarity, 0, "planarity was widened away: {r:?}");
            }
            StopReason::Stalled { refusals: None } => {
                assert_eq!(options.method, halfedge::hierarchy::Method::Qem);
            }
            other => panic!("{other:?}"),
        }
        assert!(outcome.to_string().contains("short of the target of 20"));
    }
    // The level limit is a reason of its own.
    let h = Hierarchy::build(
        mesh,
        &HierarchyOptions::rounds()
            .with_target_faces(20)
            .with_max_levels(2),
    )
    .unwrap();
    assert_eq!(h.build_outcome().stop, StopReason::MaxLevels);
    assert!(h.build_outcome().to_string().contains("raise max_levels"));
}

#[test]
fn an_error_bound_that_forbids_the_target_is_the_reason_given() {
    let h = Hierarchy::build(
        blob(),
        &HierarchyOptions::rounds()
            .with_target_faces(100)
            .with_max_error(1e-4),
    )
    .unwrap();
    let outcome = h.build_outcome();
    assert!(!outcome.target_reached());
    let StopReason::Stalled { refusals: Some(r) } = outcome.stop else {
        panic!("{outcome:?}")
    };
    assert!(r.error_bound > 0, "{r:?}");
    assert!(outcome.to_string().contains("exceeded max_error"));
}
