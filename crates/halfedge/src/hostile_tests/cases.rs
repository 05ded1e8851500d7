//! The named cases: targeted record and split refusals, the machines' coverage, overflow.

use glam::DVec3;
use proptest::prelude::*;

use super::hierarchy::*;
use super::*;
use crate::collapse::CollapseRecord;
use crate::error::Error;
use crate::generators;
use crate::handle::{HalfedgeId, VertexId};
use crate::mesh::Mesh;

/// The machines reach every outcome they are meant to test: splits accepted in and out of
/// order and refused for each reason, refused collapses and steps, overflows, labels.
#[test]
fn the_machines_reach_every_case() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::new(config(1));
    let mut kernel = Stats::default();
    for case in 0..300u32 {
        let ops = proptest::collection::vec(op(), 1..120)
            .new_tree(&mut runner)
            .unwrap()
            .current();
        run_kernel(test_mesh(case as u8), &ops, &mut kernel).unwrap();
    }
    for what in [
        "collapse accepted",
        "collapse refused",
        "split of the last record accepted",
        "split out of order accepted",
        "split refused: another mesh",
        "split refused: already split",
        "split refused: freed by garbage collection",
        "split refused: a link changed",
        "split refused: the fingerprint differs",
        "split refused: a later collapse waits",
        "split_edge accepted",
        "split_edge refused",
        "ear added",
        "add_triangle refused",
    ] {
        assert!(kernel.get(what) > 0, "never: {what} ({kernel:?})");
    }
    let mut hierarchy = Stats::default();
    for case in 0..200u32 {
        let ops = proptest::collection::vec(hop(), 1..60)
            .new_tree(&mut runner)
            .unwrap()
            .current();
        run_hierarchy(case as u8, case % 2 == 1, &ops, &mut hierarchy).unwrap();
    }
    for what in [
        "step accepted",
        "split refused",
        "collapse refused",
        "overflow refused",
        "other refusal",
        "mark accepted",
        "edit_input refused",
        "return_to accepted",
        "return_to refused",
    ] {
        assert!(hierarchy.get(what) > 0, "never: {what} ({hierarchy:?})");
    }
    eprintln!("kernel: {kernel:?}\nhierarchy: {hierarchy:?}");
}

/// A coarse edit so large that the refined positions would overflow is refused, and the
/// mesh is left as it was.
#[test]
fn translations_that_overflow_are_refused() {
    let mut h = Hierarchy::build(
        generators::icosphere(2),
        &HierarchyOptions::rounds().with_target_faces(40),
    )
    .unwrap();
    for p in h.mesh_mut().positions_mut() {
        *p *= 1.5e308;
    }
    let before = raw(h.mesh());
    let e = h.split_next().unwrap_err();
    assert!(matches!(e, Error::Overflow(_)), "{e}");
    assert!(raw(h.mesh()) == before);
    h.mesh().check().unwrap();
}

// ---------------------------------------------------------------------------------------
// The cases of issue 14, one by one.

/// A legal collapse of an edge leaving `v`.
fn collapse_at(mesh: &mut Mesh, v: VertexId) -> CollapseRecord {
    let h = mesh
        .outgoing_halfedges(v)
        .find(|&h| mesh.is_collapse_ok(h).is_ok())
        .expect("a legal collapse");
    mesh.collapse(h).unwrap()
}

/// `vertex_split(r)` is refused with a reason containing `why`, and changes nothing.
fn assert_refused(mesh: &mut Mesh, r: &CollapseRecord, why: &str) {
    let before = raw(mesh);
    match mesh.vertex_split(r) {
        Err(Error::SplitRefused(reason)) => assert!(reason.contains(why), "{reason}"),
        other => panic!("expected a refusal ({why}), got {other:?}"),
    }
    assert!(raw(mesh) == before, "the refusal changed the mesh");
    mesh.check().unwrap();
}

#[test]
fn a_split_after_split_edge_in_its_neighbourhood_is_refused() {
    // On the kept edge v1 → vl: the links the collapse wrote change.
    let mut mesh = generators::icosphere(1);
    let v = mesh.vertices().nth(20).unwrap();
    let r = collapse_at(&mut mesh, v);
    mesh.split_edge(r.v1vl.unwrap(), DVec3::ZERO).unwrap();
    assert_refused(&mut mesh, &r, "link");
    // On the middle one of the three edges the collapse moved from v0 to v1 (counter-
    // clockwise after v1 → vl): only the fingerprint sees it.
    let mut mesh = generators::icosphere(1);
    assert_eq!(mesh.valence(v), 6);
    let r = collapse_at(&mut mesh, v);
    let moved = mesh.ccw_rotated(mesh.ccw_rotated(r.v1vl.unwrap()));
    mesh.split_edge(moved, DVec3::ZERO).unwrap();
    assert_refused(&mut mesh, &r, "neighbourhood");
    // Far away: the record still fits, and the split gives v0 its ring back.
    let mut mesh = generators::icosphere(2);
    let v = mesh.vertices().next().unwrap();
    let ring0 = ring(&mesh, v);
    let r = collapse_at(&mut mesh, v);
    let far = mesh
        .halfedges()
        .find(|&h| mesh.position(mesh.from_vertex(h)).distance(r.p0) > 1.0)
        .unwrap();
    mesh.split_edge(far, DVec3::ZERO).unwrap();
    mesh.vertex_split(&r).unwrap();
    mesh.check().unwrap();
    assert_eq!(ring(&mesh, v), ring0);
}

#[test]
fn out_of_order_splits_are_refused_and_name_the_record_to_split_first() {
    let mut mesh = generators::icosphere(1);
    let v = mesh.vertices().nth(15).unwrap();
    let a = collapse_at(&mut mesh, v);
    let b = collapse_at(&mut mesh, a.v1);
    assert_refused(&mut mesh, &a, "");
    mesh.vertex_split(&b).unwrap();
    mesh.vertex_split(&a).unwrap();
    mesh.check().unwrap();
    // Even where the collapses do not meet: a split made out of order could strand the
    // later record (issue 29: 67 of 29,213 pairs on an icosphere), so splits undo public
    // collapses in reverse order, and the refusal names the record to split first.
    let mut mesh = generators::icosphere(2);
    let original = raw(&mesh);
    let v = mesh.vertices().next().unwrap();
    let a = collapse_at(&mut mesh, v);
    let far = mesh
        .vertices()
        .find(|&w| mesh.position(w).distance(a.p0) > 1.5)
        .unwrap();
    let b = collapse_at(&mut mesh, far);
    let e = mesh.vertex_split(&a).unwrap_err().to_string();
    assert!(e.contains(&format!("{} → {}", b.v0, b.v1)), "{e}");
    mesh.vertex_split(&b).unwrap();
    mesh.vertex_split(&a).unwrap();
    mesh.check().unwrap();
    let restored = raw(&mesh);
    assert_eq!(
        (&restored.he, &restored.vertex_conn, &restored.face_conn),
        (&original.he, &original.vertex_conn, &original.face_conn)
    );
}

#[test]
fn no_accepted_split_strands_a_record_still_waiting() {
    // Every pair of collapses k then j on an icosphere (issue 29, 6c): the split of k is
    // accepted only when j is no longer waiting, and whatever was accepted, every record
    // still waiting can be split afterwards (in reverse order), giving the input back.
    let base = generators::icosphere(1);
    let original = raw(&base);
    let edges: Vec<HalfedgeId> = base.halfedges().collect();
    let mut pairs = 0;
    for &k in &edges {
        let mut after_k = base.clone();
        let Ok(rk) = after_k.collapse(k) else {
            continue;
        };
        for &j in edges.iter().step_by(7) {
            let mut mesh = after_k.clone();
            let Ok(rj) = mesh.collapse(j) else { continue };
            pairs += 1;
            let before = raw(&mesh);
            assert!(mesh.vertex_split(&rk).is_err(), "k split while j waits");
            assert_eq!(raw(&mesh), before, "a refused split changed the mesh");
            mesh.vertex_split(&rj).unwrap();
            mesh.vertex_split(&rk).unwrap();
            mesh.check().unwrap();
            let back = raw(&mesh);
            assert_eq!(
                (&back.he, &back.vertex_conn, &back.face_conn),
                (&original.he, &original.vertex_conn, &original.face_conn)
            );
        }
    }
    assert!(pairs > 500, "{pairs} pairs");
}

#[test]
fn a_record_names_one_collapse_event_only() {
    // Issue 29, 6b: collapse h -> r1, split r1, collapse h -> r2: r1 names the first
    // collapse, which was undone; it is refused (nothing changes) and r2 is accepted.
    let mut mesh = generators::icosphere(2);
    let original = raw(&mesh);
    let h = mesh
        .halfedges()
        .find(|&h| mesh.is_collapse_ok(h).is_ok())
        .unwrap();
    let r1 = mesh.collapse(h).unwrap();
    mesh.vertex_split(&r1).unwrap();
    let r2 = mesh.collapse(h).unwrap();
    let before = raw(&mesh);
    let e = mesh.vertex_split(&r1).unwrap_err().to_string();
    assert!(e.contains("earlier collapse"), "{e}");
    assert_eq!(raw(&mesh), before);
    mesh.vertex_split(&r2).unwrap();
    mesh.check().unwrap();
    let back = raw(&mesh);
    assert_eq!(
        (&back.he, &back.vertex_conn, &back.face_conn),
        (&original.he, &original.vertex_conn, &original.face_conn)
    );
    // And once r2 is split, r1 and r2 are both refused as already split.
    assert_refused(&mut mesh, &r1, "already split");
    assert_refused(&mut mesh, &r2, "already split");
}

#[test]
fn a_record_split_twice_is_refused() {
    let mut mesh = generators::icosphere(1);
    let v = mesh.vertices().nth(3).unwrap();
    let r = collapse_at(&mut mesh, v);
    mesh.vertex_split(&r).unwrap();
    assert_refused(&mut mesh, &r, "already split");
    // Even when v0 was removed again by another collapse.
    let other = mesh
        .outgoing_halfedges(r.v0)
        .find(|&h| h != r.v0v1 && mesh.is_collapse_ok(h).is_ok())
        .unwrap();
    mesh.collapse(other).unwrap();
    assert_refused(&mut mesh, &r, "");
}

#[test]
fn records_of_other_meshes_are_refused() {
    let mut mesh = generators::icosphere(1);
    let v = mesh.vertices().nth(7).unwrap();
    // The same collapse on a clone made before it: the record is not the mesh's.
    let mut clone = mesh.clone();
    let theirs = collapse_at(&mut clone, v);
    let ours = collapse_at(&mut mesh, v);
    assert_refused(&mut mesh, &theirs, "another mesh");
    assert_refused(&mut clone, &ours, "another mesh");
    // A clone made after the collapse shares its history and accepts the record.
    let mut later = mesh.clone();
    later.vertex_split(&ours).unwrap();
    later.check().unwrap();
    // An unrelated mesh of the same shape refuses it.
    let mut unrelated = generators::icosphere(1);
    collapse_at(&mut unrelated, v);
    assert_refused(&mut unrelated, &ours, "another mesh");
}

#[test]
fn records_freed_by_garbage_collection_are_refused() {
    let mut mesh = generators::icosphere(1);
    let v = mesh.vertices().nth(9).unwrap();
    let r = collapse_at(&mut mesh, v);
    mesh.garbage_collection();
    assert_refused(&mut mesh, &r, "garbage_collection");
    // Slots reused by new elements are refused too.
    let h = mesh.halfedges().next().unwrap();
    mesh.split_edge(h, DVec3::ZERO).unwrap();
    assert_refused(&mut mesh, &r, "");
}

#[test]
fn a_split_after_add_triangle_in_its_neighbourhood_is_refused() {
    let mut mesh = generators::grid(4, 4, 1.0, 1.0);
    // A boundary vertex in the middle of the bottom side: collapse an edge into it.
    let v = mesh.vertices().nth(2).unwrap();
    let h = mesh
        .outgoing_halfedges(v)
        .find(|&h| mesh.is_boundary_halfedge(h) && mesh.is_collapse_ok(h).is_ok())
        .unwrap();
    let r = mesh.collapse(h).unwrap();
    // An ear on the boundary edge the collapse moved to v1.
    let b = mesh
        .outgoing_halfedges(r.v1)
        .find(|&k| mesh.is_boundary_halfedge(k))
        .unwrap();
    let (x, y) = (mesh.from_vertex(b), mesh.to_vertex(b));
    let c = mesh.add_vertex(DVec3::new(0.5, -1.0, 0.0));
    mesh.add_triangle(x, y, c).unwrap();
    assert_refused(&mut mesh, &r, "");
}

#[test]
fn a_removed_label_attribute_is_refused_before_the_split() {
    let mut h = Hierarchy::build(
        generators::icosphere(2),
        &HierarchyOptions::rounds().with_target_faces(40),
    )
    .unwrap();
    let labels = h.mesh_mut().label_attribute().unwrap();
    h.attach_labels(labels).unwrap();
    h.coarsen_to(h.coarsest_level()).unwrap();
    h.mesh_mut().remove_attribute(labels).unwrap();
    for replaced in [false, true] {
        if replaced {
            // Its place taken by an attribute of another type.
            h.mesh_mut().add_vertex_attribute("x", 0.5f64).unwrap();
        }
        let before = raw(h.mesh());
        let applied = h.applied();
        assert!(matches!(h.split_next(), Err(Error::InvalidArgument(_))));
        assert!(matches!(h.go_to_level(0), Err(Error::InvalidArgument(_))));
        assert!(matches!(h.seek(0), Err(Error::InvalidArgument(_))));
        assert!(raw(h.mesh()) == before);
        assert_eq!(h.applied(), applied);
    }
    h.detach_labels();
    h.refine_to(0).unwrap();
    h.mesh().check().unwrap();
}

#[test]
fn a_hierarchy_refuses_cleanly_after_split_edge_behind_its_back() {
    // Every edge of the coarsest mesh in turn.
    let built = Hierarchy::build(
        generators::icosphere(2),
        &HierarchyOptions::rounds().with_target_faces(60),
    )
    .unwrap();
    let edges: Vec<HalfedgeId> = built.mesh().edges().collect();
    let mut refused = 0;
    for e in edges {
        let mut h = built.clone();
        let mesh = h.mesh_mut();
        let p = 0.5 * (mesh.position(mesh.from_vertex(e)) + mesh.position(mesh.to_vertex(e)));
        mesh.split_edge(e, p).unwrap();
        loop {
            let before = raw(h.mesh());
            match h.split_next() {
                Ok(true) => h.mesh().check().unwrap(),
                Ok(false) => break,
                Err(err) => {
                    assert!(matches!(err, Error::SplitRefused(_)), "{err}");
                    assert!(raw(h.mesh()) == before);
                    refused += 1;
                    break;
                }
            }
        }
        h.mesh().check().unwrap();
    }
    assert!(refused > 0);
}

#[test]
fn a_hierarchy_of_non_finite_positions_is_refused() {
    let mut mesh = generators::icosphere(1);
    let v = mesh.vertices().nth(4).unwrap();
    mesh.set_position(v, DVec3::new(0.0, f64::NAN, 0.0));
    let e = Hierarchy::build(mesh, &HierarchyOptions::rounds()).unwrap_err();
    assert!(
        matches!(e, Error::NonFiniteCoordinate { vertex: 4, .. }),
        "{e}"
    );
}

/// Coordinates near the largest `f64`: a midpoint or a quadric's optimum of two of them
/// overflows, and such a collapse is refused; every level keeps finite positions (the
/// hierarchy machine found a QEM build that did not).
#[test]
fn huge_coordinates_never_give_an_overflowed_placement() {
    for options in [HierarchyOptions::rounds(), HierarchyOptions::qem()] {
        let mut mesh = generators::icosphere(2);
        for p in mesh.positions_mut() {
            *p *= 1.5e308;
        }
        let mut h = Hierarchy::build(mesh, &options.with_target_faces(20)).unwrap();
        for level in (0..h.n_levels()).rev() {
            h.go_to_level(level).unwrap();
            assert!(live_positions_finite(h.mesh()), "level {level}");
            h.mesh().check().unwrap();
        }
    }
}

#[test]
fn an_attribute_handle_of_another_mesh_is_refused_as_stale() {
    // Issue 29, 6a: `a.attribute(attr_of_b, v)` panicked with "attribute was removed".
    // Two meshes with attributes in the same column and of the same type: a handle of
    // one never reads or writes the other's values, whatever the column.
    let mut a = generators::icosphere(1);
    let mut b = generators::icosphere(1);
    let of_a = a.add_vertex_attribute("w", 1.0f64).unwrap();
    let of_b = b.add_vertex_attribute("w", 2.0f64).unwrap();
    let v = a.vertices().next().unwrap();
    for result in [a.attribute(of_b, v).copied(), b.attribute(of_a, v).copied()] {
        let e = result.unwrap_err();
        assert!(matches!(e, Error::Stale(_)), "{e}");
        assert!(e.to_string().contains("attribute handle"), "{e}");
    }
    assert!(a.attribute_values_mut(of_b).is_err());
    assert!(a.remove_attribute(of_b).is_err());
    assert_eq!(*a.attribute(of_a, v).unwrap(), 1.0);
    assert!(!a.has_attribute(of_b));
    // A clone has the attributes of its original: their handles work on it, and the
    // clone's own new attributes are refused by the original.
    let mut clone = a.clone();
    assert_eq!(*clone.attribute(of_a, v).unwrap(), 1.0);
    let of_clone = clone.add_vertex_attribute("x", 3u8).unwrap();
    let mut dup = a.clone();
    let of_dup = dup.add_vertex_attribute("x", 4u8).unwrap();
    assert!(a.attribute(of_clone, v).is_err());
    assert!(
        clone.attribute(of_dup, v).is_err(),
        "same column and type, other mesh"
    );
    // An element handle that is not of the mesh is an invalid handle, not a panic.
    let w = generators::icosphere(3).vertices().last().unwrap();
    assert!(matches!(a.attribute(of_a, w), Err(Error::InvalidHandle(_))));
}
