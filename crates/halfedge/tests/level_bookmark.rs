//! `Hierarchy::bookmark` / `return_to`: an undo of a level change is exact (edit at a
//! coarse level, walk to the input, come back, undo the edit: refining gives the input
//! bit for bit), the walk redone after coming back is the first one bit for bit, and
//! bookmarks that no longer fit are refused with nothing changed.

use glam::{DAffine3, DVec3};
use halfedge::hierarchy::{Hierarchy, HierarchyOptions, Method};
use halfedge::{generators, Mesh, VertexId};

fn bits(positions: &[DVec3]) -> Vec<[u64; 3]> {
    positions
        .iter()
        .map(|p| p.to_array().map(f64::to_bits))
        .collect()
}

/// A bumpy sphere, large enough for the threaded refinement (over 4,096 splits).
fn sphere() -> Mesh {
    let mut mesh = generators::icosphere(5);
    for p in mesh.positions_mut() {
        let n = *p;
        *p = n * (1.0 + 0.05 * (5.0 * n.x).sin() * (4.0 * n.y + 1.0).sin());
    }
    mesh
}

fn options(method: Method) -> HierarchyOptions {
    match method {
        Method::Qem => HierarchyOptions::qem(),
        _ => HierarchyOptions::rounds(),
    }
    .with_target_faces(400)
}

/// The coarse edit: the vertices with `x > 0.2` lifted by a ramp (not a map the marks
/// describe, so refinement interpolates through the copies of the positions before the
/// edit), the cap `x > 0.6` rotated rigidly (an affine mark), all of it the edit's region.
fn edit_at_level(h: &mut Hierarchy) {
    let rotation = DAffine3::from_translation(DVec3::new(0.8, 0.0, 0.0))
        * DAffine3::from_rotation_y(0.3)
        * DAffine3::from_translation(DVec3::new(-0.8, 0.0, 0.0));
    let mesh = h.mesh();
    let moved: Vec<VertexId> = mesh
        .vertices()
        .filter(|&v| mesh.position(v).x > 0.2)
        .collect();
    let cap: Vec<VertexId> = mesh
        .vertices()
        .filter(|&v| mesh.position(v).x > 0.6)
        .collect();
    let mesh = h.mesh_mut();
    for &v in &moved {
        let p = mesh.position(v);
        let q = if p.x > 0.6 {
            rotation.transform_point3(p)
        } else {
            p + DVec3::new(0.0, 0.0, 0.3 * (p.x - 0.2))
        };
        mesh.set_position(v, q);
    }
    h.mark_region(&moved).unwrap();
    h.mark_affine(&cap, rotation).unwrap();
}

#[test]
fn a_level_change_undone_by_its_bookmark_is_exact() {
    for method in [Method::Rounds, Method::Qem] {
        let input = sphere();
        let mut h = Hierarchy::build(input.clone(), &options(method)).unwrap();
        h.go_to_level(2).unwrap();
        let before_edit = h.mesh().positions().to_vec();
        edit_at_level(&mut h);
        let edited = h.bookmark();

        h.go_to_level(0).unwrap();
        let first = bits(h.mesh().positions());
        assert_ne!(
            first,
            bits(input.positions()),
            "{method:?}: the edit moved nothing"
        );

        // Back at the edited level, exactly as it was.
        h.return_to(&edited).unwrap();
        assert_eq!(h.applied(), edited.applied());
        assert_eq!(bits(h.mesh().positions()), bits(edited.positions()));
        h.mesh().check().unwrap();
        // The walk redone: the first one, bit for bit (marks and the positions before the
        // edit came back too).
        h.go_to_level(0).unwrap();
        assert_eq!(bits(h.mesh().positions()), first, "{method:?}: walk redone");

        // The edit undone at its level: refining gives the input bit for bit.
        h.return_to(&edited).unwrap();
        h.mesh_mut().positions_mut().copy_from_slice(&before_edit);
        h.clear_marks();
        h.go_to_level(0).unwrap();
        assert_eq!(
            bits(h.mesh().positions()),
            bits(input.positions()),
            "{method:?}: edit undone"
        );
        h.mesh().check().unwrap();
    }
}

#[test]
fn a_walk_back_by_seek_makes_the_records_again() {
    // What the bookmark is for: the same undo by a walk coarser collapses the edited
    // fine mesh again, and refining after the edit is undone no longer gives the input.
    let input = sphere();
    let mut h = Hierarchy::build(input.clone(), &options(Method::Rounds)).unwrap();
    h.go_to_level(2).unwrap();
    let before_edit = h.mesh().positions().to_vec();
    edit_at_level(&mut h);
    let edited = h.bookmark();
    h.go_to_level(0).unwrap();
    h.seek(edited.applied()).unwrap();
    // The edit undone at its level (the walk's own positions are overwritten).
    h.mesh_mut().positions_mut().copy_from_slice(&before_edit);
    h.clear_marks();
    h.go_to_level(0).unwrap();
    assert_ne!(bits(h.mesh().positions()), bits(input.positions()));
}

#[test]
fn bookmarks_that_no_longer_fit_are_refused_and_nothing_changes() {
    let input = sphere();
    let mut h = Hierarchy::build(input, &options(Method::Rounds)).unwrap();
    h.go_to_level(2).unwrap();
    let bookmark = h.bookmark();

    // Another hierarchy (a clone has its own records' identity).
    let mut clone = h.clone();
    clone.go_to_level(0).unwrap();
    let state = (clone.applied(), bits(clone.mesh().positions()));
    assert!(clone.return_to(&bookmark).is_err());
    assert_eq!((clone.applied(), bits(clone.mesh().positions())), state);

    // Records made again: an edit at the input carried coarser.
    h.go_to_level(0).unwrap();
    for p in h.mesh_mut().positions_mut() {
        p.y += 0.01 * p.x;
    }
    h.go_to_level(1).unwrap();
    let state = (h.applied(), bits(h.mesh().positions()));
    let err = h.return_to(&bookmark).unwrap_err();
    assert!(err.to_string().contains("made again"), "{err}");
    assert_eq!((h.applied(), bits(h.mesh().positions())), state);
    h.mesh().check().unwrap();

    // A fresh bookmark from there fits.
    let fresh = h.bookmark();
    h.go_to_level(3).unwrap();
    h.return_to(&fresh).unwrap();
    assert_eq!(h.applied(), fresh.applied());
    assert_eq!(bits(h.mesh().positions()), bits(fresh.positions()));
}

#[test]
fn a_bookmark_at_a_finer_level_is_reached_by_walking() {
    let input = sphere();
    let mut h = Hierarchy::build(input.clone(), &options(Method::Rounds)).unwrap();
    h.go_to_level(0).unwrap();
    let at_input = h.bookmark();
    h.go_to_level(3).unwrap();
    h.return_to(&at_input).unwrap();
    assert_eq!(h.applied(), 0);
    assert_eq!(bits(h.mesh().positions()), bits(input.positions()));
}

#[test]
fn records_above_the_bookmark_made_again_since_are_made_again_after_it() {
    // Bookmark at level 1, edit there, walk coarser (the records above level 1 take the
    // edit), back to the bookmark. Walking coarser again must make those records again
    // from the bookmark's positions: a translation of the whole coarse level then comes
    // back as the bookmark's positions translated (local frames carry it exactly, up to
    // rounding), not with the undone edit in its detail.
    let input = sphere();
    let mut h = Hierarchy::build(input, &options(Method::Rounds)).unwrap();
    h.go_to_level(1).unwrap();
    let bookmark = h.bookmark();
    for p in h.mesh_mut().positions_mut() {
        p.z += 0.05 * p.x;
    }
    h.go_to_level(3).unwrap();
    h.return_to(&bookmark).unwrap();
    assert_eq!(bits(h.mesh().positions()), bits(bookmark.positions()));
    h.go_to_level(3).unwrap();
    let shift = DVec3::new(0.1, -0.2, 0.3);
    for p in h.mesh_mut().positions_mut() {
        *p += shift;
    }
    h.go_to_level(1).unwrap();
    let mesh = h.mesh();
    let worst = mesh
        .vertices()
        .map(|v| {
            let i = mesh.vertex_index(v);
            (mesh.position(v) - (bookmark.positions()[i] + shift)).length()
        })
        .fold(0.0f64, f64::max);
    assert!(worst < 1e-12, "off by {worst}");
}
