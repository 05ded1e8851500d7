//! Hostile use of the hierarchy calls that landed after the first hostile campaign
//! (issue 14): affine marks, ancestors, `edit_input`, `constrain_to_labels`,
//! `build_cancellable`. Every call returns a typed error or a finite result, and a
//! refused call leaves the hierarchy as it was.

use std::ops::ControlFlow;
use std::panic::{catch_unwind, AssertUnwindSafe};

use glam::{DAffine3, DVec3};
use halfedge::hierarchy::{Hierarchy, HierarchyOptions};
use halfedge::{generators, Error, Mesh};

fn survive<T>(name: &str, f: impl FnOnce() -> T) -> T {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|_| panic!("{name}: panicked"))
}

fn hierarchy() -> Hierarchy {
    Hierarchy::build(generators::icosphere(3), &HierarchyOptions::rounds()).unwrap()
}

/// Level, positions and connectivity: what a refused call must not change.
fn state(h: &Hierarchy) -> (Option<usize>, Vec<[u64; 3]>, usize, usize) {
    let m = h.mesh();
    (
        h.current_level(),
        m.positions()
            .iter()
            .map(|p| p.to_array().map(f64::to_bits))
            .collect(),
        m.n_vertices(),
        m.n_faces(),
    )
}

#[test]
fn new_hierarchy_calls_survive_hostile_arguments() {
    let mut cases = 0;
    // Marks with vertices of another mesh, non-finite and huge maps.
    let other = generators::icosphere(5);
    let foreign = other.vertices().last().unwrap();
    for t in [
        DAffine3::from_translation(DVec3::splat(f64::NAN)),
        DAffine3::from_scale(DVec3::splat(f64::INFINITY)),
    ] {
        cases += 2;
        let mut h = hierarchy();
        h.go_to_level(2).unwrap();
        let v = h.mesh().vertices().next().unwrap();
        let before = state(&h);
        assert!(survive("mark nan", || h.mark_affine(&[v], t)).is_err());
        assert!(survive("set mark nan", || h.set_affine_mark(&[v], t)).is_err());
        assert_eq!(state(&h), before);
    }
    cases += 1;
    let mut h = hierarchy();
    h.go_to_level(2).unwrap();
    let before = state(&h);
    assert!(survive("mark foreign", || h
        .mark_affine(&[foreign], DAffine3::IDENTITY))
    .is_err());
    assert_eq!(state(&h), before);
    survive("mark none", || h.mark_affine(&[], DAffine3::IDENTITY)).unwrap();
    // Huge finite marks: refining must give finite positions or refuse unchanged.
    for s in [1e300, 1e-300, f64::MAX] {
        cases += 1;
        let mut h = hierarchy();
        h.go_to_level(1).unwrap();
        let part: Vec<_> = h
            .mesh()
            .vertices()
            .filter(|&v| h.mesh().position(v).x > 0.3)
            .collect();
        let t = DAffine3::from_scale(DVec3::splat(s));
        for &v in &part {
            let p = h.mesh().position(v);
            let q = t.transform_point3(p);
            if q.is_finite() {
                h.mesh_mut().set_position(v, q);
            }
        }
        survive("mark huge", || h.mark_affine(&part, t)).unwrap();
        let before = state(&h);
        match survive("refine huge", || h.refine_to(0)) {
            Ok(()) => {
                h.mesh().check().unwrap();
                let bad = h
                    .mesh()
                    .positions()
                    .iter()
                    .filter(|p| !p.is_finite())
                    .count();
                assert_eq!(
                    bad, 0,
                    "mark scaled by {s}: Ok with {bad} non-finite positions"
                );
            }
            Err(_) => assert_eq!(state(&h), before, "scale {s}: refused but changed"),
        }
    }
    // Levels out of range.
    cases += 2;
    let h = hierarchy();
    assert!(survive("ancestors", || h.ancestors(usize::MAX)).is_err());
    assert!(survive("ancestors past", || h.ancestors(h.coarsest_level() + 1)).is_err());
    // edit_input refused: by the closure, by a broken or NaN mesh.
    cases += 3;
    let mut h = hierarchy();
    h.go_to_level(1).unwrap();
    let before = state(&h);
    let r = survive("edit_input err", || {
        h.edit_input(|_| -> Result<(), String> { Err("no".into()) })
    });
    assert!(r.is_err());
    assert_eq!(state(&h), before);
    let r = survive("edit_input nan", || {
        h.edit_input(|m| -> Result<(), Error> {
            let v = m.vertices().next().unwrap();
            m.set_position(v, DVec3::NAN);
            Ok(())
        })
    });
    assert!(r.is_err(), "edit_input accepted a NaN position");
    assert_eq!(state(&h), before);
    let r = survive("edit_input empty", || {
        h.edit_input(|m| -> Result<(), Error> {
            *m = Mesh::new();
            Ok(())
        })
    });
    // An empty input is a valid (empty) hierarchy; it must be a consistent one.
    match r {
        Ok(()) => h.mesh().check().unwrap(),
        Err(_) => assert_eq!(state(&h), before),
    }
    let mut h = hierarchy();
    h.go_to_level(1).unwrap();
    // No labels to constrain to.
    cases += 1;
    let before = state(&h);
    assert!(survive("constrain", || h.constrain_to_labels()).is_err());
    assert_eq!(state(&h), before);
    // Cancelled builds and NaN inputs.
    cases += 2;
    let r = survive("cancel", || {
        Hierarchy::build_cancellable(
            generators::icosphere(3),
            &HierarchyOptions::rounds(),
            &mut |_| ControlFlow::Break(()),
        )
    });
    assert!(r.is_err(), "a cancelled build returned Ok");
    let mut nan = generators::icosphere(2);
    nan.positions_mut()[3] = DVec3::new(1e308, f64::NAN, 0.0);
    let r = survive("cancellable nan", || {
        Hierarchy::build_cancellable(nan, &HierarchyOptions::rounds(), &mut |_| {
            ControlFlow::Continue(())
        })
    });
    assert!(r.is_err());
    eprintln!("hierarchy: {cases} hostile cases");
}

/// Frontiers of other meshes, hostile planes and labels for `label_sides_with`: typed
/// errors, the mesh unchanged.
#[test]
fn label_sides_with_survives_hostile_arguments() {
    let mut cases = 0;
    let other = generators::icosphere(4);
    let foreign = other.frontier_from_plane(DVec3::ZERO, DVec3::Z).unwrap();
    for (p, n) in [
        (DVec3::ZERO, DVec3::ZERO),
        (DVec3::splat(f64::NAN), DVec3::Z),
        (DVec3::ZERO, DVec3::splat(f64::INFINITY)),
        (DVec3::splat(1e308), DVec3::Z),
    ] {
        cases += 1;
        let mesh = generators::icosphere(2);
        assert!(
            survive("plane", || mesh.frontier_from_plane(p, n)).is_err(),
            "{p} {n}"
        );
    }
    for (left, right) in [
        (Some(1), Some(2)),
        (Some(1), None),
        (None, None),
        (Some(u32::MAX), Some(1)),
        (Some(3), Some(3)),
    ] {
        cases += 2;
        let mut mesh = generators::icosphere(2);
        let positions = mesh.positions().to_vec();
        let r = survive("foreign frontier", || {
            mesh.label_sides_with(&foreign, left, right)
        });
        assert!(r.is_err(), "a frontier of another mesh was accepted");
        assert_eq!(mesh.positions(), &positions[..]);
        mesh.check().unwrap();
        let own = mesh.frontier_from_plane(DVec3::ZERO, DVec3::Z).unwrap();
        let ok = survive("own frontier", || mesh.label_sides_with(&own, left, right)).is_ok();
        let valid = left.is_some() && left != Some(u32::MAX) && left != right;
        assert_eq!(ok, valid, "{left:?} {right:?}");
        mesh.check().unwrap();
    }
    eprintln!("labels: {cases} hostile cases");
}
