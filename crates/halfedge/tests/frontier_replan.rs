//! Sub-mesh labels made to hold at every level by re-planning only the records near the
//! frontier (`Hierarchy::constrain_to_labels`, issue 13): no edge of any level joins two
//! labels, the records away from the frontier are the old ones, the levels keep their
//! face counts, the hierarchy stays exact. Generated meshes in the default tier, every
//! shared mesh in the real-mesh tier.

use std::collections::HashSet;

use glam::DVec3;
use halfedge::hierarchy::{Hierarchy, HierarchyOptions};
use halfedge::{Mesh, VertexId};
use testkit::check::{crossing_edges, position_bits as bits};
use testkit::meshes::bumpy_capsule;

/// What identifies a record: the collapsed halfedge and the two positions it recorded.
fn record_keys(h: &Hierarchy) -> HashSet<(String, [u64; 3], [u64; 3])> {
    h.records()
        .iter()
        .map(|r| {
            (
                format!("{:?}", r.v0v1),
                r.p0.to_array().map(f64::to_bits),
                r.p1.to_array().map(f64::to_bits),
            )
        })
        .collect()
}

/// The plane through the middle of `mesh` across its longest axis.
fn middle_plane(mesh: &Mesh) -> (DVec3, DVec3) {
    let (lo, hi) = mesh.bounding_box().unwrap();
    let axis = (hi - lo).max_position();
    let normal = DVec3::from_array(std::array::from_fn(|k| f64::from(u8::from(k == axis))));
    (0.5 * (lo + hi), normal)
}

/// Labels the two sides of the plane `(point, normal)` at level 0 of `h` (the hierarchy
/// is walked there first) and attaches them.
fn label_sides_of(h: &mut Hierarchy, (point, normal): (DVec3, DVec3)) {
    h.go_to_level(0).unwrap();
    let m = h.mesh_mut();
    let frontier = m.frontier_from_plane(point, normal).unwrap();
    let (labels, _) = m.label_sides(&frontier, 3, 4).unwrap();
    h.attach_labels(labels).unwrap();
}

/// Every property the re-planned hierarchy must have, against the hierarchy it came from
/// (`before`, at level 0 with the same labels) and a full constrained build of the same
/// input (`rebuilt`). Returns the share of the new records that are old ones.
fn check_replanned(name: &str, h: &mut Hierarchy, before: &Hierarchy, rebuilt: &Hierarchy) -> f64 {
    let attribute = h.label_attribute().unwrap();
    // No record joins two labels.
    h.go_to_level(0).unwrap();
    let input = bits(h.mesh());
    let labels = h.mesh().attribute_values(attribute).unwrap().to_vec();
    for r in h.records() {
        let l = |v: VertexId| labels[h.mesh().vertex_index(v)];
        assert_eq!(l(r.v0), l(r.v1), "{name}: a record joins two labels");
    }
    // No edge joins two labels at any level; every level is a valid mesh.
    for level in 0..h.n_levels() {
        h.go_to_level(level).unwrap();
        h.mesh().check().unwrap();
        assert_eq!(crossing_edges(h.mesh()), 0, "{name}: level {level}");
    }
    // Coarsest and back is bit for bit.
    h.go_to_level(0).unwrap();
    assert_eq!(bits(h.mesh()), input, "{name}: refined back inexactly");
    // Every record is the one its collapse would make: the kernel's checked split, which
    // compares what the split relies on with what the collapse recorded, takes them all.
    let mut coarse = h.clone();
    coarse.go_to_level(coarse.coarsest_level()).unwrap();
    let records = coarse.records().to_vec();
    let mut mesh = coarse.into_mesh();
    for r in records.iter().rev() {
        mesh.vertex_split(r)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
    }
    mesh.check().unwrap();
    // The levels keep about their face counts (the band along the frontier is simplified
    // again), as a full constrained build would.
    let coarsest = *h.level_face_counts().last().unwrap();
    let old = *before.level_face_counts().last().unwrap();
    let full = *rebuilt.level_face_counts().last().unwrap();
    assert!(
        coarsest as f64 <= 1.25 * full.max(old) as f64 + 50.0,
        "{name}: coarsest {coarsest} faces against {old} before and {full} for a full build"
    );
    assert_eq!(h.level_face_counts()[0], before.level_face_counts()[0]);
    // Most records are the old ones: only the band along the frontier was planned again.
    let old_keys = record_keys(before);
    let kept = record_keys(h).intersection(&old_keys).count();
    kept as f64 / h.records().len().max(1) as f64
}

/// Builds `mesh` with `options`, labels the two sides of `plane` at level 0, and checks
/// `constrain_to_labels` against the old hierarchy and a full constrained build.
/// Returns the share of records kept and the number of edges that joined the two labels
/// over all levels before.
fn replan_halves(
    name: &str,
    mesh: Mesh,
    plane: (DVec3, DVec3),
    options: &HierarchyOptions,
) -> (f64, usize) {
    let mut h = Hierarchy::build(mesh, options).unwrap();
    label_sides_of(&mut h, plane);
    let before = h.clone();
    // The crossing the constraint removes is there before.
    let mut probe = h.clone();
    let crossed: usize = (1..probe.n_levels())
        .map(|level| {
            probe.go_to_level(level).unwrap();
            crossing_edges(probe.mesh())
        })
        .sum();
    let mut rebuilt = h.clone();
    rebuilt.edit_input(|_| Ok::<(), String>(())).unwrap();
    h.constrain_to_labels().unwrap();
    assert_eq!(h.current_level(), Some(0));
    (check_replanned(name, &mut h, &before, &rebuilt), crossed)
}

#[test]
fn labels_hold_at_every_level_after_replanning_and_the_rest_is_kept() {
    for (method, options) in [
        ("rounds", HierarchyOptions::rounds().with_target_faces(300)),
        ("qem", HierarchyOptions::qem().with_target_faces(300)),
    ] {
        let mesh = bumpy_capsule();
        let plane = middle_plane(&mesh);
        let (kept, crossed) = replan_halves(method, mesh, plane, &options);
        assert!(crossed > 0, "{method}: the labels were never crossed");
        assert!(kept > 0.6, "{method}: only {kept:.2} of the records kept");
    }
}

#[test]
fn labels_defined_at_a_coarse_level_after_an_edit_hold_at_every_level() {
    // Positions edited at the input (the records' details no longer describe them), then
    // a frontier defined at level 2: the replay places and recomputes what it keeps.
    let mesh = bumpy_capsule();
    let mut h = Hierarchy::build(mesh, &HierarchyOptions::rounds().with_target_faces(300)).unwrap();
    h.go_to_level(0).unwrap();
    for p in h.mesh_mut().positions_mut() {
        p.y += 0.05 * p.x.sin();
    }
    h.go_to_level(2).unwrap();
    let m = h.mesh_mut();
    let f = m
        .frontier_from_plane(DVec3::new(0.5, 0.0, 0.0), DVec3::X)
        .unwrap();
    let (labels, _) = m.label_sides(&f, 3, 4).unwrap();
    h.attach_labels(labels).unwrap();
    let at_2 = bits(h.mesh());
    let mut copy = h.clone();
    copy.seek(0).unwrap();
    let input = bits(copy.mesh());
    h.constrain_to_labels().unwrap();
    assert_eq!(h.current_level(), Some(2));
    let size = h.mesh().n_vertices() as f64 / at_2.len() as f64;
    assert!(
        (0.9..1.1).contains(&size),
        "level 2 is {size} times its size"
    );
    for level in 0..h.n_levels() {
        h.go_to_level(level).unwrap();
        h.mesh().check().unwrap();
        assert_eq!(crossing_edges(h.mesh()), 0, "level {level}");
    }
    h.go_to_level(0).unwrap();
    assert_eq!(bits(h.mesh()), input, "the input (with the edit) is kept");
}

#[test]
fn several_sub_meshes_hold_at_every_level() {
    let mut h = Hierarchy::build(
        bumpy_capsule(),
        &HierarchyOptions::rounds().with_target_faces(300),
    )
    .unwrap();
    h.go_to_level(0).unwrap();
    let m = h.mesh_mut();
    // Two caps cut off the capsule: labels 5 (x > 1.5), 6 (x < -1.5), the rest 7.
    let right = m
        .frontier_from_plane(DVec3::new(1.5, 0.0, 0.0), DVec3::X)
        .unwrap();
    let (labels, _) = m.label_sides(&right, 5, 7).unwrap();
    let left = m
        .frontier_from_plane(DVec3::new(-1.5, 0.0, 0.0), -DVec3::X)
        .unwrap();
    m.label_sides_with(&left, Some(6), None).unwrap();
    h.attach_labels(labels).unwrap();
    h.constrain_to_labels().unwrap();
    let attribute = h.label_attribute().unwrap();
    let counts = |h: &Hierarchy| {
        let values = h.mesh().attribute_values(attribute).unwrap();
        [5, 6, 7].map(|l| {
            h.mesh()
                .vertices()
                .filter(|&v| values[h.mesh().vertex_index(v)] == l)
                .count()
        })
    };
    for level in 0..h.n_levels() {
        h.go_to_level(level).unwrap();
        h.mesh().check().unwrap();
        assert_eq!(crossing_edges(h.mesh()), 0, "level {level}");
        assert!(
            counts(&h).iter().all(|&n| n > 0),
            "level {level}: a sub-mesh vanished: {:?}",
            counts(&h)
        );
    }
}

/// Records of a hierarchy of `mesh` built with `options` (none for a mesh already below
/// the face target).
fn before_records(mesh: &Mesh, options: &HierarchyOptions) -> usize {
    Hierarchy::build(mesh.clone(), options)
        .unwrap()
        .records()
        .len()
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (cargo test --release -- --ignored)"]
fn labels_hold_at_every_level_after_replanning_on_the_shared_meshes() {
    for entry in std::fs::read_dir(testkit::shared_meshes()).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let Ok((mesh, _)) = halfedge::io::read(&path) else {
            continue;
        };
        // A plane through a mesh with boundaries or several parts need not give one
        // closed loop that separates it: the first plane across an axis, at a quarter,
        // half or three quarters of the box, that does is used.
        let (lo, hi) = mesh.bounding_box().unwrap();
        let plane = (0..3)
            .flat_map(|axis| [0.5, 0.25, 0.75].map(|t| (axis, t)))
            .map(|(axis, t)| {
                let normal =
                    DVec3::from_array(std::array::from_fn(|k| f64::from(u8::from(k == axis))));
                (lo + t * (hi - lo), normal)
            })
            .find(|&(point, normal)| {
                let mut probe = mesh.clone();
                probe
                    .frontier_from_plane(point, normal)
                    .and_then(|f| probe.label_sides(&f, 3, 4))
                    .is_ok()
            });
        let Some(plane) = plane else {
            eprintln!("{name}: no plane gives a separating loop, skipped");
            continue;
        };
        for options in [
            HierarchyOptions::rounds().with_target_faces(2000),
            HierarchyOptions::qem().with_target_faces(2000),
        ] {
            let (kept, crossed) = replan_halves(&name, mesh.clone(), plane, &options);
            eprintln!(
                "{name} {:?}: {crossed} crossing edges over the levels before, none after; {kept:.3} of the records kept",
                options.method
            );
            assert!(
                kept > 0.5 || before_records(&mesh, &options) == 0,
                "{name}: only {kept:.2} of the records kept"
            );
        }
    }
}

#[test]
fn one_label_everywhere_keeps_every_record_and_a_refused_replay_changes_nothing() {
    let options = HierarchyOptions::rounds().with_target_faces(300);
    let mut h = Hierarchy::build(bumpy_capsule(), &options).unwrap();
    h.go_to_level(0).unwrap();
    // One label on every vertex: no record joins two labels, so the replay keeps them all.
    let attribute = h.mesh_mut().label_attribute().unwrap();
    for value in h.mesh_mut().attribute_values_mut(attribute).unwrap() {
        *value = 9;
    }
    h.attach_labels(attribute).unwrap();
    let before = h.clone();
    h.constrain_to_labels().unwrap();
    assert_eq!(h.level_face_counts(), before.level_face_counts());
    assert_eq!(record_keys(&h), record_keys(&before));
    // A non-finite position at the input: refused, and the hierarchy is as it was.
    let v = h.mesh().vertices().next().unwrap();
    h.mesh_mut().set_position(v, DVec3::new(f64::NAN, 0.0, 0.0));
    let state = (bits(h.mesh()), h.level_face_counts().to_vec(), h.applied());
    assert!(h.constrain_to_labels().is_err());
    assert_eq!(
        (bits(h.mesh()), h.level_face_counts().to_vec(), h.applied()),
        state
    );
}
