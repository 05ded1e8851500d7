//! Edits made at a coarse level come back at full resolution as they were made: local-frame
//! detail that turns with its neighbourhood, regions that stay exact, marked affine parts
//! that land exactly ([`DetailMode::LocalFrame`], the default). On generated meshes, so
//! they run anywhere.

use glam::{DAffine3, DQuat, DVec3};
use halfedge::hierarchy::{DetailMode, Hierarchy, HierarchyOptions};
use halfedge::{Mesh, VertexId};
use testkit::check::crossing_edges;
use testkit::meshes::bumpy_capsule;

fn diagonal(mesh: &Mesh) -> f64 {
    let (lo, hi) = mesh.bounding_box().unwrap();
    (hi - lo).length()
}

/// A rotation by 40° about an axis through `(1.2, 0.1, 0)` (the arm's end turns).
fn arm_rotation() -> DAffine3 {
    let pivot = DVec3::new(1.2, 0.1, 0.0);
    DAffine3::from_translation(pivot)
        * DAffine3::from_quat(DQuat::from_axis_angle(
            DVec3::new(0.2, 0.3, 1.0).normalize(),
            0.7,
        ))
        * DAffine3::from_translation(-pivot)
}

/// Builds a hierarchy of `mesh`, goes to `level`, and applies `t` to the live vertices
/// with x > 1.2 (marking them when `mark`). Returns the hierarchy (at the coarse level)
/// and the moved vertices.
fn rotate_arm_at(
    mesh: &Mesh,
    options: &HierarchyOptions,
    level: usize,
    t: DAffine3,
    mark: bool,
) -> (Hierarchy, Vec<VertexId>) {
    let mut h = Hierarchy::build(mesh.clone(), options).unwrap();
    h.go_to_level(level).unwrap();
    let part: Vec<VertexId> = h
        .mesh()
        .vertices()
        .filter(|&v| h.mesh().position(v).x > 1.2)
        .collect();
    for &v in &part {
        let p = h.mesh().position(v);
        h.mesh_mut().set_position(v, t.transform_point3(p));
    }
    if mark {
        h.mark_affine(&part, t).unwrap();
    }
    (h, part)
}

/// Faces whose normal in `a` points against their normal in `b`.
fn flips(a: &Mesh, b: &Mesh) -> usize {
    a.faces()
        .filter(|&f| {
            let n = |m: &Mesh| {
                let [x, y, z] = m.triangle(f).map(|v| m.position(v));
                (y - x).cross(z - x)
            };
            n(a).dot(n(b)) < 0.0
        })
        .count()
}

fn rms(a: &Mesh, b: &Mesh) -> f64 {
    let n = a.n_vertices() as f64;
    (a.vertices()
        .map(|v| (a.position(v) - b.position(v)).length_squared())
        .sum::<f64>()
        / n)
        .sqrt()
}

#[test]
fn a_marked_rigid_part_lands_exactly_and_the_rest_stays_bit_for_bit() {
    let mesh = bumpy_capsule();
    let diag = diagonal(&mesh);
    let t = arm_rotation();
    let level = 3;
    let (mut h, part) = rotate_arm_at(&mesh, &HierarchyOptions::rounds(), level, t, true);
    let ancestors = h.ancestors(level).unwrap();
    let mut in_part = vec![false; mesh.vertex_slots()];
    for &v in &part {
        in_part[h.mesh().vertex_index(v)] = true;
    }
    h.refine_to(0).unwrap();
    h.mesh().check().unwrap();
    let (mut moved, mut still) = (0, 0);
    for v in mesh.vertices() {
        let i = mesh.vertex_index(v);
        let (before, after) = (mesh.position(v), h.mesh().position(v));
        if in_part[ancestors[i] as usize] {
            moved += 1;
            let error = (after - t.transform_point3(before)).length() / diag;
            assert!(
                error <= 1e-9,
                "vertex {v} of the marked part is off by {error}"
            );
        } else {
            still += 1;
            assert_eq!(
                after.to_array().map(f64::to_bits),
                before.to_array().map(f64::to_bits),
                "vertex {v} outside the edited region moved"
            );
        }
    }
    assert!(moved > 500 && still > 5000, "{moved} {still}");
}

/// A smooth bend of the arm: points with x > 0.5 turn about the z axis through
/// `(0.5, 0, 0)` by an angle that grows smoothly from 0 to 45° at x = 3 (the identity,
/// bit for bit, for x ≤ 0.5).
fn bend(p: DVec3) -> DVec3 {
    if p.x <= 0.5 {
        return p;
    }
    let s = ((p.x - 0.5) / 2.5).min(1.0);
    let angle = 45f64.to_radians() * s * s * (3.0 - 2.0 * s);
    let pivot = DVec3::new(0.5, 0.0, 0.0);
    pivot + DQuat::from_rotation_z(angle) * (p - pivot)
}

#[test]
fn local_frames_turn_the_detail_with_a_bent_part() {
    // A bend made at a coarse level, compared with the same bend made at full resolution:
    // local frames turn the detail with it, the paper's translations do not.
    let mesh = bumpy_capsule();
    let diag = diagonal(&mesh);
    let mut full = mesh.clone();
    for p in full.positions_mut() {
        *p = bend(*p);
    }
    let refine = |mode| {
        let options = HierarchyOptions::rounds().with_detail_mode(mode);
        let mut h = Hierarchy::build(mesh.clone(), &options).unwrap();
        h.go_to_level(4).unwrap();
        for p in h.mesh_mut().positions_mut() {
            *p = bend(*p);
        }
        h.refine_to(0).unwrap();
        h.mesh().check().unwrap();
        h.into_mesh()
    };
    let full_flips = flips(&full, &mesh);
    // Made at every level down to a 15th of the faces, no more flips than at full
    // resolution (measured: none; the RMS doubles per level, 1e-4 to 8e-4 of the diagonal).
    for level in 1..=4 {
        let mut h = Hierarchy::build(mesh.clone(), &HierarchyOptions::rounds()).unwrap();
        h.go_to_level(level).unwrap();
        for p in h.mesh_mut().positions_mut() {
            *p = bend(*p);
        }
        h.refine_to(0).unwrap();
        let (flipped, error) = (flips(h.mesh(), &mesh), rms(h.mesh(), &full) / diag);
        assert!(
            flipped <= full_flips && error < 1e-3,
            "level {level}: {flipped} flips (full resolution {full_flips}), RMS {error}"
        );
    }
    let local = refine(DetailMode::LocalFrame);
    let paper = refine(DetailMode::Translation);
    let (local_rms, paper_rms) = (rms(&local, &full) / diag, rms(&paper, &full) / diag);
    let (local_flips, paper_flips) = (flips(&local, &mesh), flips(&paper, &mesh));
    assert!(
        local_rms < 0.2 * paper_rms,
        "RMS to the full-resolution edit: local frames {local_rms}, translations {paper_rms}"
    );
    assert!(local_rms < 1e-3, "RMS {local_rms}");
    assert!(
        local_flips <= full_flips && local_flips < paper_flips,
        "flips: local {local_flips}, paper {paper_flips}, full resolution {full_flips}"
    );
    // Deep inside the part every neighbourhood turned rigidly: the detail is exact.
    let deep = mesh
        .vertices()
        .filter(|&v| mesh.position(v).x > 3.2)
        .map(|v| (local.position(v) - full.position(v)).length() / diag)
        .fold(0.0, f64::max);
    assert!(deep < 1e-9, "deep inside, off the rigid image by {deep}");
    // The part x ≤ 0.5 did not move at the coarse level: nothing collapsed into it moves.
    for v in mesh.vertices() {
        if mesh.position(v).x < 0.0 {
            assert_eq!(local.position(v), mesh.position(v));
        }
    }
}

#[test]
fn an_undone_edit_refines_bit_identically() {
    // Positions edited and put back: the hierarchy no longer knows they are clean, but
    // every survivor is where it left it, so every split restores its record exactly.
    let mesh = bumpy_capsule();
    for options in [HierarchyOptions::rounds(), HierarchyOptions::qem()] {
        let mut h = Hierarchy::build(mesh.clone(), &options.with_target_faces(400)).unwrap();
        let saved = h.mesh().positions().to_vec();
        for p in h.mesh_mut().positions_mut() {
            *p *= 2.0;
        }
        h.mesh_mut().positions_mut().copy_from_slice(&saved);
        h.refine_to(0).unwrap();
        for v in mesh.vertices() {
            assert_eq!(
                h.mesh().position(v).to_array().map(f64::to_bits),
                mesh.position(v).to_array().map(f64::to_bits)
            );
        }
    }
}

#[test]
fn a_dragged_vertex_marked_as_translated_lands_exactly() {
    // One coarse vertex dragged on its own and marked with its translation: after
    // refinement its fine self and every fine vertex collapsed into it are the originals
    // translated by the drag, and nothing else moved.
    let mesh = bumpy_capsule();
    let level = 4;
    let mut h = Hierarchy::build(mesh.clone(), &HierarchyOptions::rounds()).unwrap();
    h.go_to_level(level).unwrap();
    // The coarse vertex with the most fine descendants.
    let ancestors = h.ancestors(level).unwrap();
    let mut count = vec![0usize; mesh.vertex_slots()];
    for v in mesh.vertices() {
        count[ancestors[mesh.vertex_index(v)] as usize] += 1;
    }
    let v = h
        .mesh()
        .vertices()
        .max_by_key(|&v| count[h.mesh().vertex_index(v)])
        .unwrap();
    let drag = DVec3::new(0.8, 0.3, -0.2);
    let p = h.mesh().position(v);
    h.mesh_mut().set_position(v, p + drag);
    h.mark_affine(&[v], DAffine3::from_translation(drag))
        .unwrap();
    let iv = h.mesh().vertex_index(v) as u32;
    h.refine_to(0).unwrap();
    h.mesh().check().unwrap();
    let mut carried = 0;
    for w in mesh.vertices() {
        let (before, after) = (mesh.position(w), h.mesh().position(w));
        if ancestors[mesh.vertex_index(w)] == iv {
            carried += 1;
            let error = (after - (before + drag)).length() / drag.length();
            assert!(error < 1e-12, "descendant {w} off the drag by {error}");
        } else {
            assert_eq!(after, before, "vertex {w} moved");
        }
    }
    assert!(carried > 4, "{carried} descendants");
}

#[test]
fn marks_are_checked_and_dropped_when_walking_coarser() {
    let mesh = bumpy_capsule();
    let mut h = Hierarchy::build(mesh.clone(), &HierarchyOptions::rounds()).unwrap();
    h.go_to_level(2).unwrap();
    let v = h.mesh().vertices().next().unwrap();
    let nan = DAffine3::from_translation(DVec3::new(f64::NAN, 0.0, 0.0));
    assert!(h.mark_affine(&[v], nan).is_err());
    let mut paper = Hierarchy::build(
        mesh.clone(),
        &HierarchyOptions::rounds()
            .with_target_faces(1000)
            .with_detail_mode(DetailMode::Translation),
    )
    .unwrap();
    let w = paper.mesh().vertices().next().unwrap();
    assert!(paper.mark_affine(&[w], DAffine3::IDENTITY).is_err());
    // A mark that does not describe the motion falls back to the local frame: a vertex
    // marked with a translation but not moved stays exactly where it was.
    h.mark_affine(&[v], DAffine3::from_translation(DVec3::X))
        .unwrap();
    let q = h.mesh().position(v);
    h.mesh_mut().set_position(v, q + DVec3::Y * 1e-3);
    h.mesh_mut().set_position(v, q);
    h.refine_to(0).unwrap();
    for w in mesh.vertices() {
        assert_eq!(h.mesh().position(w), mesh.position(w));
    }
}

/// Everything a walk may change, to compare before and after a refused one.
fn state(h: &Hierarchy) -> (usize, Vec<[u64; 3]>, usize, usize, Vec<u32>) {
    let mesh = h.mesh();
    let mut ends: Vec<u32> = mesh
        .halfedges()
        .map(|e| mesh.vertex_index(mesh.to_vertex(e)) as u32)
        .collect();
    ends.sort_unstable();
    (
        h.applied(),
        mesh.positions()
            .iter()
            .map(|p| p.to_array().map(f64::to_bits))
            .collect(),
        mesh.n_faces(),
        mesh.n_vertices(),
        ends,
    )
}

#[test]
fn a_refused_walk_leaves_everything_where_it_started() {
    // A foreign collapse at a coarse level, an edit: the walk to the input is refused
    // part-way, and everything is back where the walk started.
    let mesh = bumpy_capsule();
    for options in [HierarchyOptions::rounds(), HierarchyOptions::qem()] {
        let mut h = Hierarchy::build(mesh.clone(), &options.with_target_faces(2000)).unwrap();
        h.go_to_level(2).unwrap();
        for p in h.mesh_mut().positions_mut() {
            *p *= 1.1;
        }
        let m = h.mesh_mut();
        let e = m
            .halfedges()
            .find(|&e| m.is_collapse_ok(e).is_ok())
            .unwrap();
        m.collapse(e).unwrap();
        let before = state(&h);
        let level = h.current_level();
        assert!(
            h.refine_to(0).is_err(),
            "a split went through a foreign collapse"
        );
        assert!(
            state(&h) == before,
            "the refused walk changed the hierarchy"
        );
        assert_eq!(h.current_level(), level);
        h.mesh().check().unwrap();
        assert!(h.go_to_level(h.coarsest_level()).is_err());
        assert!(state(&h) == before);
    }
}

#[test]
fn labels_hold_at_every_level() {
    // Three sub-meshes cut by two planes at the input; then a frontier defined at a
    // coarse level, made to hold by re-planning the hierarchy.
    let mesh = bumpy_capsule();
    for options in [HierarchyOptions::rounds(), HierarchyOptions::qem()] {
        let mut fine = mesh.clone();
        let f1 = fine
            .frontier_from_plane(DVec3::new(1.0, 0.0, 0.0), DVec3::X)
            .unwrap();
        fine.label_sides(&f1, 1, 2).unwrap();
        let mut h = Hierarchy::build(fine, &options.clone().with_target_faces(300)).unwrap();
        assert!(h.n_levels() > 4);
        for level in (0..h.n_levels()).rev() {
            h.go_to_level(level).unwrap();
            assert_eq!(crossing_edges(h.mesh()), 0, "{options:?} level {level}");
        }
        // Unconstrained, the same labels are crossed at coarse levels.
        let mut fine = mesh.clone();
        let f1 = fine
            .frontier_from_plane(DVec3::new(1.0, 0.0, 0.0), DVec3::X)
            .unwrap();
        fine.label_sides(&f1, 1, 2).unwrap();
        let mut free = Hierarchy::build(
            fine,
            &options
                .clone()
                .with_target_faces(300)
                .with_respect_labels(false),
        )
        .unwrap();
        let crossed: usize = (1..free.n_levels())
            .map(|level| {
                free.go_to_level(level).unwrap();
                crossing_edges(free.mesh())
            })
            .sum();
        assert!(
            crossed > 0,
            "the unconstrained hierarchy never crossed the labels"
        );

        // A frontier defined at level 2, propagated and made to hold everywhere.
        let mut h =
            Hierarchy::build(mesh.clone(), &options.clone().with_target_faces(300)).unwrap();
        h.go_to_level(2).unwrap();
        let m = h.mesh_mut();
        let f = m
            .frontier_from_plane(DVec3::new(-1.0, 0.0, 0.0), DVec3::X)
            .unwrap();
        let (labels, _) = m.label_sides(&f, 3, 4).unwrap();
        h.attach_labels(labels).unwrap();
        h.constrain_to_labels().unwrap();
        assert_eq!(h.current_level(), Some(2));
        for level in 0..h.n_levels() {
            h.go_to_level(level).unwrap();
            h.mesh().check().unwrap();
            assert_eq!(crossing_edges(h.mesh()), 0, "{options:?} level {level}");
        }
    }
}

/// The largest jump of displacement across one fine edge, over `scale`: how abruptly the
/// motion from `before` to `after` changes between neighbours.
fn largest_jump(mesh: &Mesh, before: &Mesh, after: &Mesh, scale: f64) -> f64 {
    let motion = |v: VertexId| after.position(v) - before.position(v);
    mesh.halfedges()
        .map(|h| {
            let (a, b) = (mesh.from_vertex(h), mesh.to_vertex(h));
            (motion(a) - motion(b)).length() / scale
        })
        .fold(0.0, f64::max)
}

/// Builds a rounds hierarchy of the bumpy capsule at level 3 and lifts the coarse
/// vertices within `radius` of the arm's tip along x by `lift` (unmarked). Returns the
/// hierarchy and the lifted vertices.
fn lift_the_tip(radius: f64, lift: f64) -> (Mesh, Hierarchy, Vec<VertexId>) {
    let mesh = bumpy_capsule();
    let mut h = Hierarchy::build(mesh.clone(), &HierarchyOptions::rounds()).unwrap();
    h.go_to_level(3).unwrap();
    let tip = DVec3::new(3.0, 0.0, 0.0);
    let part: Vec<VertexId> = h
        .mesh()
        .vertices()
        .filter(|&v| h.mesh().position(v).distance(tip) < radius)
        .collect();
    for &v in &part {
        let p = h.mesh().position(v);
        h.mesh_mut().set_position(v, p + DVec3::new(lift, 0.0, 0.0));
    }
    (mesh, h, part)
}

#[test]
fn a_part_pulled_out_on_its_own_comes_back_without_overshoot() {
    // A part of the coarse mesh pulled out on its own (no region declared): everything
    // collapsed into a still coarse vertex stays bit for bit; the fine descendants of
    // the pulled vertices next to still ones take a falling share of the pull (the
    // triangles' interpolation), never more than the pull beyond what turning their
    // detail with the tilted surface adds (measured: 1.7 %; the ring's step, read as a
    // stretch by the local frame alone, carried them 18 % beyond the pull).
    let lift = 0.3;
    let (mesh, mut h, part) = lift_the_tip(1.0, lift);
    let ancestors = h.ancestors(3).unwrap();
    let moved: Vec<bool> = {
        let mut m = vec![false; mesh.vertex_slots()];
        for &v in &part {
            m[h.mesh().vertex_index(v)] = true;
        }
        m
    };
    h.refine_to(0).unwrap();
    let fine = h.into_mesh();
    fine.check().unwrap();
    let (mut partial, mut largest) = (0, 0.0f64);
    for v in mesh.vertices() {
        let i = mesh.vertex_index(v);
        let motion = (fine.position(v) - mesh.position(v)).length() / lift;
        if !moved[ancestors[i] as usize] {
            assert_eq!(fine.position(v), mesh.position(v), "{v} moved");
        }
        largest = largest.max(motion);
        partial += usize::from(motion > 0.05 && motion < 0.95);
    }
    assert!(largest <= 1.05, "a fine vertex moved {largest} of the pull");
    assert!(
        partial > 50,
        "only {partial} fine vertices took a share of the pull"
    );
}

#[test]
fn a_region_mark_lets_unmoved_vertices_share_their_neighbours_motion() {
    // The same pull, with the still ring around the pulled part declared part of the
    // edit's region: the descendants of that ring take a share of the motion too, and
    // the step is spread further; outside the region everything stays bit for bit.
    let lift = 0.3;
    let (mesh, mut h, part) = lift_the_tip(1.0, lift);
    let ring: Vec<VertexId> = {
        let coarse = h.mesh();
        let mut ring: Vec<VertexId> = part
            .iter()
            .flat_map(|&v| coarse.adjacent_vertices(v))
            .filter(|w| !part.contains(w))
            .collect();
        ring.sort();
        ring.dedup();
        ring
    };
    assert!(!ring.is_empty());
    let region: Vec<VertexId> = part.iter().chain(&ring).copied().collect();
    h.mark_region(&region).unwrap();
    let ancestors = h.ancestors(3).unwrap();
    let in_region: Vec<bool> = {
        let mut m = vec![false; mesh.vertex_slots()];
        for &v in &region {
            m[h.mesh().vertex_index(v)] = true;
        }
        m
    };
    let ring_index: Vec<usize> = ring.iter().map(|&v| h.mesh().vertex_index(v)).collect();
    let mut unmarked = {
        let (_, h, _) = lift_the_tip(1.0, lift);
        h
    };
    h.refine_to(0).unwrap();
    unmarked.refine_to(0).unwrap();
    let (fine, plain) = (h.into_mesh(), unmarked.into_mesh());
    fine.check().unwrap();
    let mut ring_descendants_moved = 0;
    for v in mesh.vertices() {
        let i = mesh.vertex_index(v);
        let a = ancestors[i] as usize;
        if !in_region[a] {
            assert_eq!(fine.position(v), mesh.position(v), "{v} outside moved");
        }
        if ring_index.contains(&a) {
            // unmarked, the ring's descendants stay where they were
            assert_eq!(plain.position(v), mesh.position(v));
            ring_descendants_moved += usize::from(fine.position(v) != mesh.position(v));
        }
    }
    assert!(ring_descendants_moved > 0);
    let (spread, step) = (
        largest_jump(&mesh, &mesh, &fine, lift),
        largest_jump(&mesh, &mesh, &plain, lift),
    );
    assert!(
        spread < step,
        "{spread} with the ring in the region, {step} without"
    );
    assert_eq!(flips(&fine, &mesh), 0);
}

/// The vertices of `set` (slot mask of `mesh`) whose neighbours within `rings` rings
/// are all in `set`.
fn inner(mesh: &Mesh, set: &[bool], rings: usize) -> Vec<bool> {
    let mut inner = set.to_vec();
    for _ in 0..rings {
        let before = inner.clone();
        for v in mesh.vertices() {
            let i = mesh.vertex_index(v);
            if before[i]
                && mesh
                    .adjacent_vertices(v)
                    .any(|w| !before[mesh.vertex_index(w)])
            {
                inner[i] = false;
            }
        }
    }
    inner
}

/// Moves the live vertices of `h`'s mesh with x > 2 by `t`; returns them as a slot mask.
fn move_the_far_part(h: &mut Hierarchy, t: DVec3) -> Vec<bool> {
    let mut moved = vec![false; h.mesh().vertex_slots()];
    let part: Vec<VertexId> = h
        .mesh()
        .vertices()
        .filter(|&v| h.mesh().position(v).x > 2.0)
        .collect();
    for v in part {
        let p = h.mesh().position(v);
        moved[h.mesh().vertex_index(v)] = true;
        h.mesh_mut().set_position(v, p + t);
    }
    moved
}

#[test]
fn an_edit_after_an_edit_and_a_walk_coarser_refines_cleanly() {
    // Edit at level 3, walk coarser to 4 (the records collapsed again take the edit in),
    // edit there, refine: the mesh is valid, everything neither edit moved stays, and
    // deep inside both edits (four rings inside each at its level) every fine vertex
    // moved by both translations (each record's splits read the positions its own
    // collapse saw: the level-3 ones for the records below level 3). What the splits
    // interpolate at the edits' borders reaches inwards, falling about a hundredfold
    // per ring (measured at one to six rings: 4e-2, 7e-4, 1e-5, 1e-7, 3e-10 and 0, for
    // a motion of 0.14): the bound is 1e-5 of the motion (an edit lost or counted twice
    // is off by the whole of it).
    let mesh = bumpy_capsule();
    let mut h = Hierarchy::build(mesh.clone(), &HierarchyOptions::rounds()).unwrap();
    h.go_to_level(3).unwrap();
    let (first, second) = (DVec3::new(0.0, 0.1, 0.0), DVec3::new(0.0, 0.0, 0.1));
    let inner3 = {
        let moved = move_the_far_part(&mut h, first);
        inner(h.mesh(), &moved, 4)
    };
    h.go_to_level(4).unwrap();
    let inner4 = {
        let moved = move_the_far_part(&mut h, second);
        inner(h.mesh(), &moved, 4)
    };
    let (a3, a4) = (h.ancestors(3).unwrap(), h.ancestors(4).unwrap());
    h.refine_to(0).unwrap();
    let fine = h.into_mesh();
    fine.check().unwrap();
    let mut deep = 0;
    for v in mesh.vertices() {
        let (i, p) = (mesh.vertex_index(v), mesh.position(v));
        assert!(fine.position(v).is_finite());
        if p.x < 1.0 {
            assert_eq!(fine.position(v), p, "{v} far from both edits moved");
        }
        if inner3[a3[i] as usize] && inner4[a4[i] as usize] {
            let error = (fine.position(v) - p - first - second).length();
            assert!(
                error < 1e-5 * (first + second).length(),
                "{v} at {p} deep inside is off by {error}"
            );
            deep += 1;
        }
    }
    assert!(deep > 100, "{deep}");
    // At the borders (steps, as nothing declared a region) the records below level 3
    // interpolate from the level-3 positions they were collapsed from: 11 faces turn
    // over (62 when those positions are forgotten at the walk coarser and the splits
    // guess from their frames alone).
    let flipped = flips(&fine, &mesh);
    assert!(flipped <= 20, "{flipped} faces turned over");
}

#[test]
fn region_marks_are_checked() {
    let mesh = bumpy_capsule();
    let mut h = Hierarchy::build(mesh.clone(), &HierarchyOptions::rounds()).unwrap();
    h.go_to_level(2).unwrap();
    let dead = mesh
        .vertices()
        .find(|&v| !h.mesh().is_valid_vertex(v))
        .unwrap();
    assert!(h.mark_region(&[dead]).is_err());
    let paper = HierarchyOptions::rounds().with_detail_mode(DetailMode::Translation);
    let mut p = Hierarchy::build(mesh.clone(), &paper).unwrap();
    let v = p.mesh().vertices().next().unwrap();
    assert!(p.mark_region(&[v]).is_err());
}
