//! The hierarchy's state machine: walks, edits behind its back, labels and marks.

use glam::DVec3;
use proptest::prelude::*;

use super::*;
use crate::error::Error;
use crate::generators;
use crate::handle::{HalfedgeId, VertexId};
use crate::mesh::Mesh;

// ---------------------------------------------------------------------------------------
// The hierarchy machine.

pub(super) use crate::hierarchy::{Hierarchy, HierarchyOptions};

/// One step of the hierarchy machine.
#[derive(Clone, Debug)]
pub(super) enum HOp {
    SplitNext,
    CollapseNext,
    GoToLevel(u32),
    Seek(u32),
    /// `split_edge` on the mesh behind the hierarchy's back.
    SplitEdge(u32),
    /// A collapse on the mesh behind its back.
    Collapse(u32),
    /// An ear on a boundary edge behind its back.
    AddEar(u32),
    Collect,
    /// The mesh is replaced by its clone.
    CloneMesh,
    /// The mesh is replaced by an unrelated one.
    SwapMesh(u8),
    /// The hierarchy is replaced by its clone.
    CloneHierarchy,
    /// A vertex moved by a vector of length 10^|e|, either way.
    Move(u32, i16),
    /// Every position scaled by 10^e.
    Scale(i16),
    /// Sub-mesh labels attached here.
    AttachLabels,
    /// The label attribute removed from the mesh.
    RemoveLabels,
    /// An attribute of another type in the place of the removed labels.
    OtherAttribute,
    /// A vertex marked (composed when the flag is set) with a translation of 10^e, or
    /// (composed, odd e) with the field `p (1 + 10^e) + 10^e y`.
    Mark(u32, i16, bool),
    /// The ancestors of a level (some out of range).
    Ancestors(u32),
    /// `edit_input` moving an input vertex, or refusing in the closure.
    EditInput(u32, bool),
    /// A bookmark of where the hierarchy is.
    Bookmark,
    /// Back to one of the bookmarks taken so far (some no longer fit).
    ReturnTo(u32),
    /// `unfold_refinement` where the hierarchy is.
    Unfold,
}

pub(super) fn hop() -> impl Strategy<Value = HOp> {
    prop_oneof![
        16 => Just(HOp::SplitNext),
        10 => Just(HOp::CollapseNext),
        6 => any::<u32>().prop_map(HOp::GoToLevel),
        4 => any::<u32>().prop_map(HOp::Seek),
        1 => any::<u32>().prop_map(HOp::SplitEdge),
        1 => any::<u32>().prop_map(HOp::Collapse),
        1 => any::<u32>().prop_map(HOp::AddEar),
        1 => Just(HOp::Collect),
        1 => Just(HOp::CloneMesh),
        1 => any::<u8>().prop_map(HOp::SwapMesh),
        2 => Just(HOp::CloneHierarchy),
        4 => (any::<u32>(), -308i16..=308).prop_map(|(v, e)| HOp::Move(v, e)),
        2 => prop_oneof![306i16..=308, -320i16..=-300, -3i16..=3].prop_map(HOp::Scale),
        2 => Just(HOp::AttachLabels),
        1 => Just(HOp::RemoveLabels),
        1 => Just(HOp::OtherAttribute),
        2 => (any::<u32>(), -320i16..=308, any::<bool>()).prop_map(|(v, e, c)| HOp::Mark(v, e, c)),
        1 => any::<u32>().prop_map(HOp::Ancestors),
        1 => (any::<u32>(), any::<bool>()).prop_map(|(v, ok)| HOp::EditInput(v, ok)),
        2 => Just(HOp::Bookmark),
        2 => any::<u32>().prop_map(HOp::ReturnTo),
        1 => Just(HOp::Unfold),
    ]
}

pub(super) fn hierarchy_mesh(kind: u8) -> Mesh {
    match kind % 3 {
        0 => generators::icosphere(2),
        1 => generators::grid(9, 7, 1.0, 0.8),
        _ => generators::subdivide(&test_mesh(2)),
    }
}

pub(super) fn live_positions_finite(m: &Mesh) -> bool {
    m.vertices().all(|v| m.position(v).is_finite())
}

pub(super) fn run_hierarchy(
    kind: u8,
    qem: bool,
    ops: &[HOp],
    stats: &mut Stats,
) -> std::result::Result<(), TestCaseError> {
    let options = if qem {
        HierarchyOptions::qem()
    } else {
        HierarchyOptions::rounds().with_max_normal_deviation(90f64.to_radians())
    };
    let mut h = Hierarchy::build(hierarchy_mesh(kind), &options.with_target_faces(20)).unwrap();
    let n_records = h.records().len() as u32 + 1;
    let n_levels = h.n_levels() as u32;
    let mut bookmarks: Vec<crate::hierarchy::LevelBookmark> = Vec::new();
    for op in ops {
        let before = raw(h.mesh());
        let single = |r: crate::error::Result<bool>,
                      h: &Hierarchy,
                      stats: &mut Stats|
         -> std::result::Result<(), TestCaseError> {
            match r {
                Ok(_) => {
                    stats.count("step accepted");
                    prop_assert!(
                        live_positions_finite(h.mesh()),
                        "a step made a position non-finite"
                    )
                }
                Err(e) => {
                    stats.count(match e {
                        Error::SplitRefused(_) => "split refused",
                        Error::CollapseRefused { .. } => "collapse refused",
                        Error::Overflow(_) => "overflow refused",
                        _ => "other refusal",
                    });
                    prop_assert!(
                        matches!(
                            e,
                            Error::SplitRefused(_)
                                | Error::CollapseRefused { .. }
                                | Error::Overflow(_)
                                | Error::InvalidArgument(_)
                        ),
                        "{e}"
                    );
                    prop_assert!(
                        raw(h.mesh()) == before,
                        "a refused step changed the mesh: {e}"
                    );
                }
            }
            Ok(())
        };
        match *op {
            HOp::SplitNext => {
                let r = h.split_next();
                single(r, &h, stats)?;
            }
            HOp::CollapseNext => {
                let r = h.collapse_next();
                single(r, &h, stats)?;
            }
            HOp::GoToLevel(k) => {
                if h.go_to_level((k % (n_levels + 1)) as usize).is_ok() {
                    prop_assert!(live_positions_finite(h.mesh()));
                }
            }
            HOp::Seek(k) => {
                if h.seek((k % (n_records + 1)) as usize).is_ok() {
                    prop_assert!(live_positions_finite(h.mesh()));
                }
            }
            HOp::SplitEdge(k) => {
                let mesh = h.mesh_mut();
                let hs: Vec<HalfedgeId> = mesh.halfedges().collect();
                let Some(e) = pick(&hs, k) else { continue };
                let p =
                    0.5 * (mesh.position(mesh.from_vertex(e)) + mesh.position(mesh.to_vertex(e)));
                let _ = mesh.split_edge(e, p);
            }
            HOp::Collapse(k) => {
                let mesh = h.mesh_mut();
                let hs: Vec<HalfedgeId> = mesh
                    .halfedges()
                    .filter(|&e| mesh.is_collapse_ok(e).is_ok())
                    .collect();
                let Some(e) = pick(&hs, k) else { continue };
                mesh.collapse(e).unwrap();
            }
            HOp::AddEar(k) => {
                let mesh = h.mesh_mut();
                let boundary: Vec<HalfedgeId> = mesh
                    .halfedges()
                    .filter(|&e| mesh.is_boundary_halfedge(e))
                    .collect();
                let Some(e) = pick(&boundary, k) else {
                    continue;
                };
                let (a, b) = (mesh.from_vertex(e), mesh.to_vertex(e));
                let c = mesh.add_vertex(0.5 * mesh.position(a) + 0.5 * mesh.position(b) + DVec3::Z);
                let _ = mesh.add_triangle(a, b, c);
            }
            HOp::Collect => h.mesh_mut().garbage_collection(),
            HOp::CloneMesh => {
                let copy = h.mesh().clone();
                *h.mesh_mut() = copy;
            }
            HOp::SwapMesh(k) => *h.mesh_mut() = test_mesh(k),
            HOp::CloneHierarchy => h = h.clone(),
            HOp::Move(k, e) => {
                let mesh = h.mesh_mut();
                let vs: Vec<VertexId> = mesh.vertices().collect();
                let Some(v) = pick(&vs, k) else { continue };
                let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
                let d = DVec3::new(1.0, -0.5, 0.25) * sign * 10f64.powi(i32::from(e.abs()));
                let p = mesh.position(v) + d;
                if p.is_finite() {
                    mesh.set_position(v, p);
                }
            }
            HOp::Scale(e) => {
                let s = 10f64.powi(i32::from(e));
                for p in h.mesh_mut().positions_mut() {
                    let q = *p * s;
                    if q.is_finite() {
                        *p = q;
                    }
                }
            }
            HOp::AttachLabels => {
                if let Ok(a) = h.mesh_mut().label_attribute() {
                    h.mesh_mut().attribute_values_mut(a).unwrap().fill(1);
                    h.attach_labels(a).unwrap();
                }
            }
            HOp::RemoveLabels => {
                if let Some(a) = h.label_attribute() {
                    // A second removal is refused (the handle is stale), changing nothing.
                    let _refused_when_removed_already = h.mesh_mut().remove_attribute(a);
                }
            }
            HOp::OtherAttribute => {
                let _ = h.mesh_mut().add_vertex_attribute("other", 0.5f64);
            }
            HOp::Mark(k, e, compose) => {
                let vs: Vec<VertexId> = h.mesh().vertices().collect();
                let Some(v) = pick(&vs, k) else { continue };
                let s = 10f64.powi(i32::from(e));
                let t = glam::DAffine3::from_translation(DVec3::X * s);
                let r = match (compose, e % 2 == 0) {
                    (true, true) => h.mark_affine(&[v], t),
                    // a field that overflows for large `s`
                    (true, false) => h.mark_field(&[v], move |p| p * (1.0 + s) + DVec3::Y * s),
                    (false, _) => h.set_affine_mark(&[v], t),
                };
                stats.count(if r.is_ok() {
                    "mark accepted"
                } else {
                    "mark refused"
                });
                prop_assert!(raw(h.mesh()) == before, "a mark changed the mesh");
            }
            HOp::Ancestors(k) => {
                if let Ok(a) = h.ancestors((k % (n_levels + 2)) as usize) {
                    prop_assert_eq!(a.len(), h.mesh().vertex_slots());
                }
            }
            HOp::EditInput(k, ok) => {
                let level = h.current_level();
                let r = h.edit_input(|m| {
                    if !ok {
                        return Err("refused by the closure");
                    }
                    let vs: Vec<VertexId> = m.vertices().collect();
                    if let Some(v) = pick(&vs, k) {
                        m.set_position(v, m.position(v) + DVec3::X * 1e-3);
                    }
                    Ok(())
                });
                match r {
                    Ok(()) => {
                        stats.count("edit_input accepted");
                        prop_assert!(live_positions_finite(h.mesh()));
                    }
                    Err(e) => {
                        stats.count("edit_input refused");
                        prop_assert!(
                            raw(h.mesh()) == before && h.current_level() == level,
                            "a refused edit_input changed the hierarchy: {e}"
                        );
                    }
                }
            }
            HOp::Bookmark => bookmarks.push(h.bookmark()),
            HOp::ReturnTo(k) => {
                if bookmarks.is_empty() {
                    continue;
                }
                let b = &bookmarks[k as usize % bookmarks.len()];
                let applied = h.applied();
                match h.return_to(b) {
                    Ok(()) => {
                        stats.count("return_to accepted");
                        prop_assert_eq!(h.applied(), b.applied());
                        prop_assert!(h.mesh().positions() == b.positions());
                    }
                    // A walk back finer stops where a marked field overflows, as a
                    // walk does.
                    Err(crate::error::Error::Overflow(_)) => stats.count("overflow refused"),
                    Err(e) => {
                        stats.count("return_to refused");
                        prop_assert!(
                            raw(h.mesh()) == before && h.applied() == applied,
                            "a refused return_to changed the hierarchy: {e}"
                        );
                    }
                }
            }
            HOp::Unfold => {
                let finite = live_positions_finite(h.mesh());
                h.unfold_refinement();
                prop_assert!(!finite || live_positions_finite(h.mesh()));
            }
        }
        h.mesh()
            .check()
            .map_err(|e| TestCaseError::fail(format!("after {op:?}: {e}")))?;
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(48))]

    #[test]
    fn hierarchy_walks_with_edits_behind_its_back_never_corrupt_the_mesh(
        kind in 0u8..3,
        qem in any::<bool>(),
        ops in proptest::collection::vec(hop(), 1..60),
    ) {
        run_hierarchy(kind, qem, &ops, &mut Stats::default())?;
    }
}
