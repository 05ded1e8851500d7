//! One binding for everything derived from a mesh (issue 13): a sub-mesh, an FFD
//! attachment, an editing area (and its Lee session) and a blend session made at one level
//! of a hierarchy refuse, with the one error `EditError::Stale`, to act on the mesh at
//! another level, leaving it unchanged; back at their level (by the hierarchy's own walk)
//! they work again. On a generated mesh, so this runs anywhere.

use edit::area::{EditingArea, EditingSession, SessionOptions};
use edit::blend::{BlendOptions, BlendSession};
use edit::ffd::{AttachOptions, Ffd, Frame};
use edit::regions::Regions;
use edit::selection::Vertices;
use edit::submesh::{Edit, Propagation, SubMesh};
use edit::EditError;
use glam::{DMat4, DVec3};
use halfedge::{generators, Hierarchy, HierarchyOptions, Mesh, VertexId};

/// A hierarchy of a subdivided icosphere stretched along x, at level 2.
fn hierarchy_at_2() -> Hierarchy {
    let mut mesh = generators::icosphere(4);
    for p in mesh.positions_mut() {
        p.x *= 2.0;
    }
    let mut h = Hierarchy::build(mesh, &HierarchyOptions::rounds()).unwrap();
    h.go_to_level(2).unwrap();
    h
}

fn bits(mesh: &Mesh) -> Vec<[u64; 3]> {
    mesh.positions()
        .iter()
        .map(|p| p.to_array().map(f64::to_bits))
        .collect()
}

/// Asserts that `use_it` refuses with `Stale` on level 1, changing nothing, and works
/// again at level 2.
fn stale_elsewhere(h: &mut Hierarchy, mut use_it: impl FnMut(&mut Mesh) -> edit::Result<()>) {
    h.go_to_level(1).unwrap();
    let before = bits(h.mesh());
    let e = use_it(h.mesh_mut()).unwrap_err();
    assert!(matches!(e, EditError::Stale(_)), "{e}");
    assert!(e.to_string().contains("was made for"), "{e}");
    assert_eq!(bits(h.mesh()), before, "a refused use changed the mesh");
    h.go_to_level(2).unwrap();
    use_it(h.mesh_mut()).unwrap();
}

#[test]
fn a_sub_mesh_made_at_one_level_refuses_another() {
    let mut h = hierarchy_at_2();
    let mesh = h.mesh();
    let inside: Vec<bool> = (0..mesh.vertex_slots())
        .map(|i| mesh.vertex_at(i).is_some_and(|v| mesh.position(v).x > 1.0))
        .collect();
    let sub = SubMesh::from_mask(
        mesh,
        &halfedge::VertexData::new(mesh, (inside).to_vec()).unwrap(),
    )
    .unwrap();
    let pull = Edit::Pull {
        offset: DVec3::new(0.1, 0.0, 0.0),
    };
    stale_elsewhere(&mut h, |mesh| {
        sub.apply(mesh, &pull, Propagation::NONE).map(|_| ())
    });
}

#[test]
fn an_ffd_attached_at_one_level_refuses_another() {
    let mut h = hierarchy_at_2();
    let mut ffd = Ffd::covering(
        h.mesh(),
        Vertices::All,
        Frame::WORLD,
        ([3, 3], [5, 5]),
        ([3, 3], [5, 5]),
        0.1,
        AttachOptions::default(),
    )
    .unwrap();
    ffd.translate(DVec3::new(0.0, 0.05, 0.0)).unwrap();
    stale_elsewhere(&mut h, |mesh| ffd.deform(mesh));
}

#[test]
fn an_editing_area_and_its_session_refuse_another_level() {
    let mut h = hierarchy_at_2();
    let mesh = h.mesh();
    let tip = mesh
        .vertices()
        .max_by(|&a, &b| mesh.position(a).x.total_cmp(&mesh.position(b).x))
        .unwrap();
    let area = EditingArea::disk_around(mesh, tip, 40).unwrap();
    let mut session = EditingSession::new(mesh, area, &SessionOptions::default()).unwrap();
    session.set_primitive(mesh, &[tip]).unwrap();
    stale_elsewhere(&mut h, |mesh| session.drag(mesh, DVec3::new(0.1, 0.0, 0.0)));
}

#[test]
fn a_blend_session_refuses_another_level() {
    let mut h = hierarchy_at_2();
    let mesh = h.mesh();
    let pick = |f: &dyn Fn(DVec3) -> bool| -> Vec<VertexId> {
        mesh.vertices().filter(|&v| f(mesh.position(v))).collect()
    };
    let regions = Regions::from_sets(mesh, &pick(&|p| p.x > 1.5), &pick(&|p| p.x < 0.0)).unwrap();
    let mut session = BlendSession::new(mesh, regions, BlendOptions::default()).unwrap();
    let a = DMat4::from_translation(DVec3::new(0.0, 0.1, 0.0));
    stale_elsewhere(&mut h, |mesh| session.apply(mesh, a));
}

#[test]
fn a_binding_follows_the_mesh_not_its_size() {
    // The same vertex slot count is no proof: a clone with other connectivity, or another
    // mesh of the same size, is refused.
    let mesh = generators::icosphere(3);
    let inside = vec![true; mesh.vertex_slots()];
    let sub = SubMesh::from_mask(
        &mesh,
        &halfedge::VertexData::new(&mesh, (inside).to_vec()).unwrap(),
    )
    .unwrap();
    let mut other = generators::icosphere(3);
    let pull = Edit::Pull {
        offset: DVec3::new(0.1, 0.0, 0.0),
    };
    assert!(matches!(
        sub.apply(&mut other, &pull, Propagation::NONE),
        Err(EditError::Stale(_))
    ));
    let mut same = mesh.clone();
    sub.apply(&mut same, &pull, Propagation::NONE).unwrap();
}

/// Per-vertex data is a `VertexData` bound to its mesh: a fast-marching solver, its
/// distances, a selection and a blend session's weights made at one level are refused
/// at another (the solver and the selection with `Stale`, the data by its own check),
/// and fit again back at their level.
#[test]
fn per_vertex_data_made_at_one_level_refuses_another() {
    use edit::distance::FastMarching;
    let mut h = hierarchy_at_2();
    let marching = FastMarching::new(h.mesh());
    let top = h.mesh().extreme_vertex(DVec3::Z).unwrap().unwrap();
    let distances = marching
        .distances_from_points(h.mesh(), &[top], None)
        .unwrap();
    let normals = h.mesh().vertex_normals();
    let mut cap = h.mesh().select_ball(h.mesh().position(top), 0.5).unwrap();
    let active = halfedge::VertexData::filled(h.mesh(), true);
    stale_elsewhere(&mut h, |mesh| {
        distances.check(mesh)?;
        normals.check(mesh)?;
        cap.clone().grow(mesh, 1)?;
        marching.distances_from_points(mesh, &[top], Some(&active))?;
        Ok(())
    });
    // Each refuses on its own, not only the first of the chain.
    h.go_to_level(1).unwrap();
    let mesh = h.mesh();
    assert!(normals.check(mesh).is_err());
    assert!(normals.get(mesh, top).is_err());
    assert!(matches!(cap.grow(mesh, 1), Err(halfedge::Error::Stale(_))));
    assert!(matches!(
        marching.distances_from_points(mesh, &[top], None),
        Err(EditError::Stale(_))
    ));
    // A mask made at level 1 does not fit the solver made at level 2.
    let other_mask = halfedge::VertexData::filled(mesh, true);
    assert!(matches!(
        marching.distances(&[edit::distance::Source::point(0)], Some(&other_mask)),
        Err(EditError::Stale(_))
    ));
    h.go_to_level(2).unwrap();
    assert_eq!(distances.get(h.mesh(), top).copied().unwrap(), 0.0);
}
