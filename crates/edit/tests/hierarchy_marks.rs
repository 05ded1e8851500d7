//! Edits made at a coarse level of a hierarchy with the marks each method gives
//! through the `HierarchyEdit` trait (`SubMesh::apply_with_marks`, `AreaSession`, `Ffd`,
//! `BlendSession`), refined back to the input: the part moved at full strength
//! is the exact image of its original fine vertices, and nothing outside the edit's
//! region moves (issue 12, items 2, 3 and 6), on a generated bumpy sphere.

use edit::deform::{
    AttachOptions, Axis, Ffd, LatticeFrame, Propagation, SubMesh, SubmeshEdit, Variation,
};
use edit::lee::{AreaSession, EditingArea, SessionOptions};
use edit::{HierarchyEdit, HierarchyMarks, Vertices};
use glam::{DAffine3, DQuat, DVec3};
use halfedge::hierarchy::{DetailMode, Hierarchy, HierarchyOptions};
use halfedge::{Mesh, VertexId};

const LEVEL: usize = 3;

/// Applies `edit` to the hierarchy's mesh and gives the hierarchy the edit's marks.
fn apply_marked(
    sub: &SubMesh,
    h: &mut Hierarchy,
    edit: &SubmeshEdit,
    propagation: Propagation,
) -> edit::Result<()> {
    let applied = sub.apply_with_marks(h.mesh_mut(), edit, propagation)?;
    applied.mark(h)
}

/// The marks `edit` would give, worked out on a copy of `mesh`.
fn marks_of(
    sub: &SubMesh,
    mesh: &Mesh,
    edit: &SubmeshEdit,
    propagation: Propagation,
) -> HierarchyMarks {
    let mut copy = mesh.clone();
    let applied = sub.apply_with_marks(&mut copy, edit, propagation).unwrap();
    applied.hierarchy_marks(mesh).unwrap()
}

/// An icosphere with smooth bumps, so that its detail coefficients are not radial.
fn bumpy_sphere() -> Mesh {
    testkit::meshes::bumpy_sphere(5, 0.06)
}

fn hierarchy(mode: DetailMode) -> (Mesh, Hierarchy) {
    let original = bumpy_sphere();
    let options = HierarchyOptions::rounds().with_detail_mode(mode);
    let mut h = Hierarchy::build(original.clone(), &options).unwrap();
    h.go_to_level(LEVEL).unwrap();
    (original, h)
}

/// The coarse vertices above `height` (a cap).
fn cap(mesh: &Mesh, height: f64) -> Vec<VertexId> {
    mesh.vertices()
        .filter(|&v| mesh.position(v).z > height)
        .collect()
}

fn diagonal(mesh: &Mesh) -> f64 {
    let (lo, hi) = mesh
        .positions()
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    (hi - lo).length()
}

/// Refines `h` to the input and returns, over the input vertices whose ancestor at
/// `LEVEL` is in `part`, the largest distance from `map` of their original position
/// (over the diagonal), and the number of input vertices whose ancestor is not in
/// `region` that moved at all.
fn refine_and_measure(
    original: &Mesh,
    mut h: Hierarchy,
    part: &[bool],
    map: DAffine3,
    region: &[bool],
) -> (f64, usize, Mesh) {
    let ancestors = h.ancestors(LEVEL).unwrap();
    h.go_to_level(0).unwrap();
    let fine = h.into_mesh();
    fine.check().unwrap();
    let diagonal = diagonal(original);
    let (mut worst, mut outside_moved) = (0.0f64, 0usize);
    for v in original.vertices() {
        let i = original.vertex_index(v);
        let a = ancestors[i] as usize;
        let (before, after) = (original.position(v), fine.position(v));
        if part[a] {
            worst = worst.max(after.distance(map.transform_point3(before)) / diagonal);
        }
        if !region[a] && after.to_array().map(f64::to_bits) != before.to_array().map(f64::to_bits) {
            outside_moved += 1;
        }
    }
    (worst, outside_moved, fine)
}

fn mask(mesh: &Mesh, vertices: impl IntoIterator<Item = u32>) -> Vec<bool> {
    let mut m = vec![false; mesh.vertex_slots()];
    for i in vertices {
        m[i as usize] = true;
    }
    m
}

fn rotation_about(point: DVec3, axis: DVec3, angle: f64) -> DAffine3 {
    DAffine3::from_translation(point)
        * DAffine3::from_quat(DQuat::from_axis_angle(axis, angle))
        * DAffine3::from_translation(-point)
}

#[test]
fn a_submesh_rotated_at_a_coarse_level_lands_exactly_and_nothing_else_moves() {
    let (original, mut h) = hierarchy(DetailMode::LocalFrame);
    let sub = SubMesh::from_vertices(h.mesh(), &cap(h.mesh(), 0.55)).unwrap();
    let inside = sub.mask().to_vec();
    let (point, angle) = (DVec3::new(0.0, 0.0, 0.55), 0.5);
    let edit = SubmeshEdit::Rotate {
        axis: Axis::new(point, DVec3::X).unwrap(),
        angle,
        bounded: false,
    };
    let unmarked = {
        let mut h = h.clone();
        sub.apply(h.mesh_mut(), &edit, Propagation::NONE).unwrap();
        h
    };
    apply_marked(&sub, &mut h, &edit, Propagation::NONE).unwrap();
    let map = rotation_about(point, DVec3::X, angle);
    let (worst, outside_moved, _) = refine_and_measure(&original, h, &inside, map, &inside);
    assert!(
        worst <= 1e-9,
        "the rotated cap missed its image by {worst:e}"
    );
    assert_eq!(outside_moved, 0, "vertices outside the sub-mesh moved");
    // Without the marks the local frames only follow the rotation approximately.
    let (loose, _, _) = refine_and_measure(&original, unmarked, &inside, map, &inside);
    assert!(loose > 1e-6, "unmarked rotation landed too ({loose:e})");
}

#[test]
fn a_coarse_scale_lands_with_its_reseating_and_a_pull_lands_exactly() {
    for edit in [
        SubmeshEdit::Scale {
            centre: DVec3::new(0.1, 0.0, 0.8),
            factor: 0.7,
        },
        SubmeshEdit::Pull {
            offset: DVec3::new(0.05, -0.1, 0.2),
        },
    ] {
        let (original, mut h) = hierarchy(DetailMode::LocalFrame);
        let sub = SubMesh::from_vertices(h.mesh(), &cap(h.mesh(), 0.6)).unwrap();
        let inside = sub.mask().to_vec();
        let before = h.mesh().positions().to_vec();
        let marks = marks_of(&sub, h.mesh(), &edit, Propagation::NONE);
        assert_eq!(marks.affine_parts().len(), 1);
        assert_eq!(marks.affine_parts()[0].0.len(), sub.len());
        let map = marks.affine_parts()[0].1;
        apply_marked(&sub, &mut h, &edit, Propagation::NONE).unwrap();
        // The map given to the hierarchy is what the edit did at the coarse level.
        for &i in sub.vertex_indices() {
            let (p, q) = (before[i as usize], h.mesh().positions()[i as usize]);
            assert!(q.distance(map.transform_point3(p)) < 1e-12, "{edit:?}");
        }
        let (worst, outside_moved, _) = refine_and_measure(&original, h, &inside, map, &inside);
        assert!(worst <= 1e-9, "{edit:?} missed its image by {worst:e}");
        assert_eq!(
            outside_moved, 0,
            "{edit:?} moved vertices outside the sub-mesh"
        );
    }
}

#[test]
fn a_coarse_twist_along_its_axis_comes_back_as_the_same_twist_of_the_input() {
    // A twist whose angle ramps along z is a map of space: the sub-mesh is marked with it,
    // so the fine vertices of its clusters are exactly where the same twist of the input
    // puts them (ramp and rigid end), and nothing beyond the collars moves.
    let (original, mut h) = hierarchy(DetailMode::LocalFrame);
    let sub = SubMesh::from_vertices(h.mesh(), &cap(h.mesh(), 0.3)).unwrap();
    let axis = Axis::new(DVec3::ZERO, DVec3::Z).unwrap();
    let edit = SubmeshEdit::Twist {
        axis: Some(axis),
        angle: 1.0,
        variation: Variation::Along {
            start: 0.3,
            end: 0.7,
        },
    };
    let propagation = Propagation::linear(2);
    let collars = sub.collars(h.mesh(), 2).unwrap().concat();
    let region = mask(
        h.mesh(),
        sub.vertex_indices().iter().copied().chain(collars),
    );
    let inside = sub.mask().to_vec();
    let ancestors = h.ancestors(LEVEL).unwrap();
    let marks = marks_of(&sub, h.mesh(), &edit, propagation);
    assert!(marks.affine_parts().is_empty());
    assert_eq!(marks.field_parts().len(), 1);
    assert_eq!(marks.field_parts()[0].0.len(), sub.len());
    apply_marked(&sub, &mut h, &edit, propagation).unwrap();
    let (_, outside_moved, fine) =
        refine_and_measure(&original, h, &inside, DAffine3::IDENTITY, &region);
    assert_eq!(outside_moved, 0, "vertices beyond the collars moved");
    // The same twist of the input, on the input vertices the sub-mesh's clusters hold.
    let mut full_res = original.clone();
    let fine_inside: Vec<VertexId> = original
        .vertices()
        .filter(|&v| inside[ancestors[original.vertex_index(v)] as usize])
        .collect();
    SubMesh::from_vertices(&full_res, &fine_inside)
        .unwrap()
        .apply(&mut full_res, &edit, Propagation::NONE)
        .unwrap();
    let worst = fine_inside
        .iter()
        .map(|&v| fine.position(v).distance(full_res.position(v)))
        .fold(0.0, f64::max);
    assert!(worst <= 1e-12, "{worst:e} from the full-resolution twist");
    let turned = fine_inside
        .iter()
        .filter(|&&v| fine.position(v) != original.position(v))
        .count();
    assert!(
        turned > fine_inside.len() / 3,
        "{turned} of {}",
        fine_inside.len()
    );
}

#[test]
fn a_coarse_lee_drag_lands_its_primitive_and_keeps_the_outside() {
    let (original, mut h) = hierarchy(DetailMode::LocalFrame);
    let coarse = h.mesh();
    let top = coarse
        .vertices()
        .max_by(|&a, &b| coarse.position(a).z.total_cmp(&coarse.position(b).z))
        .unwrap();
    let area = EditingArea::disk_around(coarse, top, 60).unwrap();
    let interior = mask(
        coarse,
        area.interior()
            .iter()
            .map(|&v| coarse.vertex_index(v) as u32),
    );
    let mut session = AreaSession::new(coarse, area, &SessionOptions::default()).unwrap();
    session.set_primitive(coarse, &[top]).unwrap();
    let drag = DVec3::new(0.05, 0.0, 0.25);
    session.drag(h.mesh_mut(), drag).unwrap();
    let marks = session.hierarchy_marks(h.mesh()).unwrap();
    assert_eq!(
        marks.region().len(),
        interior.iter().filter(|&&x| x).count()
    );
    marks.mark(&mut h).unwrap();
    let primitive = mask(h.mesh(), [h.mesh().vertex_index(top) as u32]);
    let (worst, outside_moved, _) = refine_and_measure(
        &original,
        h,
        &primitive,
        DAffine3::from_translation(drag),
        &interior,
    );
    assert!(
        worst <= 1e-9,
        "the primitive missed its target by {worst:e}"
    );
    assert_eq!(outside_moved, 0, "vertices outside the area moved");
}

#[test]
fn a_coarse_ffd_moves_only_the_fine_vertices_of_its_footprint() {
    let (original, mut h) = hierarchy(DetailMode::LocalFrame);
    let coarse = h.mesh();
    let footprint: Vec<VertexId> = cap(coarse, 0.4);
    let frame = LatticeFrame::new(DVec3::new(0.0, 0.0, 0.4), DVec3::X, DVec3::Z).unwrap();
    let mut ffd = Ffd::covering(
        coarse,
        Vertices::List(&footprint),
        frame,
        ([3, 3], [6, 6]),
        ([3, 3], [6, 6]),
        0.05,
        AttachOptions::default(),
    )
    .unwrap();
    ffd.bend(0.6).unwrap();
    ffd.deform(h.mesh_mut()).unwrap();
    let marks = ffd.hierarchy_marks(h.mesh()).unwrap();
    assert!(marks.affine_parts().is_empty());
    let region: Vec<bool> = (0..h.mesh().vertex_slots())
        .map(|i| ffd.parameters(i).is_some())
        .collect();
    assert_eq!(marks.region().len(), ffd.attached());
    marks.mark(&mut h).unwrap();
    let (_, outside_moved, fine) =
        refine_and_measure(&original, h, &region, DAffine3::IDENTITY, &region);
    assert_eq!(outside_moved, 0, "vertices outside the footprint moved");
    assert!(fine.positions() != original.positions());
}

#[test]
fn marks_are_refused_on_another_level_and_ignored_with_translations() {
    let (_, mut h) = hierarchy(DetailMode::LocalFrame);
    let sub = SubMesh::from_vertices(h.mesh(), &cap(h.mesh(), 0.6)).unwrap();
    let edit = SubmeshEdit::Pull {
        offset: DVec3::new(0.0, 0.0, 0.1),
    };
    let marks = marks_of(&sub, h.mesh(), &edit, Propagation::NONE);
    // Applied to a clone of the hierarchy's mesh (an interactive application's scratch
    // copy), the edit's marks fit the hierarchy.
    let mut scratch = h.mesh().clone();
    let applied = sub
        .apply_with_marks(&mut scratch, &edit, Propagation::NONE)
        .unwrap();
    applied.mark(&mut h.clone()).unwrap();
    h.go_to_level(LEVEL + 1).unwrap();
    assert!(matches!(marks.mark(&mut h), Err(halfedge::Error::Stale(_))));
    assert!(matches!(applied.mark(&mut h), Err(e) if e.as_stale().is_some()));
    assert!(matches!(
        apply_marked(&sub, &mut h, &edit, Propagation::NONE),
        Err(e) if e.as_stale().is_some()
    ));

    // The paper's translations: the edit is made, no mark is given, the refinement is
    // the one of the plain edit, bit for bit.
    let (_, mut h) = hierarchy(DetailMode::Translation);
    let sub = SubMesh::from_vertices(h.mesh(), &cap(h.mesh(), 0.6)).unwrap();
    let mut plain = h.clone();
    sub.apply(plain.mesh_mut(), &edit, Propagation::NONE)
        .unwrap();
    apply_marked(&sub, &mut h, &edit, Propagation::NONE).unwrap();
    plain.go_to_level(0).unwrap();
    h.go_to_level(0).unwrap();
    assert_eq!(h.mesh().positions(), plain.mesh().positions());
}

#[test]
fn the_taper_map_given_to_the_hierarchy_is_the_edit_at_full_strength() {
    let (_, h) = hierarchy(DetailMode::LocalFrame);
    let sub = SubMesh::from_vertices(h.mesh(), &cap(h.mesh(), 0.2)).unwrap();
    let axis = Axis::new(DVec3::new(0.1, 0.0, 0.0), DVec3::new(0.2, 0.1, 1.0)).unwrap();
    let factor = 0.5;
    let edit = SubmeshEdit::Taper {
        axis: Some(axis),
        factor,
        variation: Variation::Uniform,
    };
    let marks = marks_of(&sub, h.mesh(), &edit, Propagation::NONE);
    let (part, map) = &marks.affine_parts()[0];
    assert_eq!(part.len(), sub.len());
    let d = axis.direction();
    for &v in part {
        let p = h.mesh().position(v);
        let q = p - axis.point();
        let expected = axis.point() + q.dot(d) * d + factor * (q - q.dot(d) * d);
        assert!(map.transform_point3(p).distance(expected) < 1e-12);
    }
}

#[test]
fn a_coarse_blend_marks_its_handle_and_moving_region_and_lands_the_handle() {
    use edit::bendels_klein::{BlendOptions, BlendSession};
    use edit::bendels_klein::{Regions, Role};
    let (original, mut h) = hierarchy(DetailMode::LocalFrame);
    let coarse = h.mesh();
    let handle = cap(coarse, 0.7);
    let fixed: Vec<VertexId> = coarse
        .vertices()
        .filter(|&v| coarse.position(v).z < 0.0)
        .collect();
    let regions = Regions::from_sets(coarse, &handle, &fixed).unwrap();
    let roles = regions.roles().to_vec();
    let mut session = BlendSession::new(coarse, regions, BlendOptions::default()).unwrap();
    let map = rotation_about(DVec3::new(0.0, 0.0, 0.7), DVec3::X, 0.4);
    session.apply(h.mesh_mut(), glam::DMat4::from(map)).unwrap();
    let marks = session.hierarchy_marks(h.mesh()).unwrap();
    let moving = roles.iter().filter(|&&r| r != Role::Fixed).count();
    assert_eq!(marks.region().len(), moving);
    assert_eq!(marks.affine_parts().len(), 1);
    assert_eq!(marks.affine_parts()[0].0.len(), handle.len());
    // Made for this level: a walk coarser makes them stale.
    let mut other = h.clone();
    other.go_to_level(LEVEL + 1).unwrap();
    assert!(matches!(
        marks.mark(&mut other),
        Err(halfedge::Error::Stale(_))
    ));
    marks.replace(&mut h).unwrap();
    let part = mask(
        h.mesh(),
        handle.iter().map(|&v| h.mesh().vertex_index(v) as u32),
    );
    let region: Vec<bool> = roles.iter().map(|&r| r != Role::Fixed).collect();
    let (worst, outside_moved, _) = refine_and_measure(&original, h, &part, map, &region);
    assert!(worst <= 1e-9, "the handle missed its image by {worst:e}");
    assert_eq!(outside_moved, 0, "the fixed region moved");
}
