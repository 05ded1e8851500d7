//! One binding for everything derived from a mesh (issue 13): a sub-mesh, an FFD
//! attachment, an editing area (and its Lee session) and a blend session made at one level
//! of a hierarchy refuse, with the one error `Stale` (each family's `Stale` variant), to
//! act on the mesh at another level, leaving it unchanged; back at their level (by the
//! hierarchy's own walk) they work again. Regions of a mesh or of a polyline are refused
//! on another one of the same size. On generated meshes, so this runs anywhere.

use edit::bendels_klein::polyline::{
    CurveRegions, Polyline, PolylineOptions, PolylineSession, Span,
};
use edit::bendels_klein::{
    BendelsKleinError, BlendOptions, BlendSession, FastMarching, MarchSource, Regions, Role,
};
use edit::deform::{
    AttachOptions, DeformError, Ffd, LatticeFrame, Propagation, SubMesh, SubmeshEdit,
};
use edit::lee::{AreaSession, EditingArea, SessionOptions};
use edit::Vertices;
use glam::{DMat4, DVec2, DVec3};
use halfedge::hierarchy::{Hierarchy, HierarchyOptions};
use halfedge::{generators, Mesh, VertexData, VertexId};
use testkit::check::slot_position_bits as bits;

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

/// Asserts that `use_it` refuses with `Stale` on level 1, changing nothing, and works
/// again at level 2.
fn stale_elsewhere(h: &mut Hierarchy, mut use_it: impl FnMut(&mut Mesh) -> edit::Result<()>) {
    h.go_to_level(1).unwrap();
    let before = bits(h.mesh());
    let e = use_it(h.mesh_mut()).unwrap_err();
    assert!(e.as_stale().is_some(), "{e}");
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
    let pull = SubmeshEdit::Pull {
        offset: DVec3::new(0.1, 0.0, 0.0),
    };
    stale_elsewhere(&mut h, |mesh| {
        sub.apply(mesh, &pull, Propagation::NONE)?;
        Ok(())
    });
}

#[test]
fn an_ffd_attached_at_one_level_refuses_another() {
    let mut h = hierarchy_at_2();
    let mut ffd = Ffd::covering(
        h.mesh(),
        Vertices::All,
        LatticeFrame::WORLD,
        ([3, 3], [5, 5]),
        ([3, 3], [5, 5]),
        0.1,
        AttachOptions::default(),
    )
    .unwrap();
    ffd.translate(DVec3::new(0.0, 0.05, 0.0)).unwrap();
    stale_elsewhere(&mut h, |mesh| Ok(ffd.deform(mesh)?));
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
    let mut session = AreaSession::new(mesh, area, &SessionOptions::default()).unwrap();
    session.set_primitive(mesh, &[tip]).unwrap();
    stale_elsewhere(&mut h, |mesh| {
        Ok(session.drag(mesh, DVec3::new(0.1, 0.0, 0.0))?)
    });
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
    stale_elsewhere(&mut h, |mesh| Ok(session.apply(mesh, a)?));
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
    let pull = SubmeshEdit::Pull {
        offset: DVec3::new(0.1, 0.0, 0.0),
    };
    assert!(matches!(
        sub.apply(&mut other, &pull, Propagation::NONE),
        Err(DeformError::Stale(_))
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
        marching
            .distances_from_points(mesh, &[top], Some(&active))
            .map_err(edit::Error::from)?;
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
        Err(BendelsKleinError::Stale(_))
    ));
    // A mask made at level 1 does not fit the solver made at level 2.
    let other_mask = halfedge::VertexData::filled(mesh, true);
    assert!(matches!(
        marching.distances(&[MarchSource::point(0)], Some(&other_mask)),
        Err(BendelsKleinError::Stale(_))
    ));
    h.go_to_level(2).unwrap();
    assert_eq!(distances.get(h.mesh(), top).copied().unwrap(), 0.0);
}

/// Regions made for one mesh are refused by a blend session on another mesh with as many
/// vertices (the binding, not a slot count, decides), and so are roles made for it; on
/// the mesh itself, and on a clone of it, they are taken.
#[test]
fn regions_of_another_mesh_of_the_same_size_are_refused() {
    let mesh = generators::icosphere(3);
    let mut other = generators::icosphere(3);
    for p in other.positions_mut() {
        *p *= 1.5;
    }
    assert_eq!(mesh.vertex_slots(), other.vertex_slots());
    let pick = |f: &dyn Fn(DVec3) -> bool| -> Vec<VertexId> {
        mesh.vertices().filter(|&v| f(mesh.position(v))).collect()
    };
    let regions = Regions::from_sets(&mesh, &pick(&|p| p.z > 0.6), &pick(&|p| p.z < -0.2)).unwrap();
    assert!(matches!(
        BlendSession::new(&other, regions.clone(), BlendOptions::default()),
        Err(BendelsKleinError::Stale(_))
    ));
    BlendSession::new(&mesh, regions.clone(), BlendOptions::default()).unwrap();
    BlendSession::new(&mesh.clone(), regions.clone(), BlendOptions::default()).unwrap();
    let roles = VertexData::new(&mesh, regions.roles().to_vec()).unwrap();
    assert!(matches!(
        Regions::from_roles(&other, roles.clone()),
        Err(BendelsKleinError::Stale(_))
    ));
    Regions::from_roles(&mesh, roles).unwrap();
}

/// Regions made for one polyline are refused by a session on another polyline of the same
/// length (even with the same points), and on the polyline itself after a point was
/// inserted; moving a point keeps them.
#[test]
fn curve_regions_of_another_polyline_of_the_same_length_are_refused() {
    let points: Vec<DVec2> = (0..14).map(|i| DVec2::new(i as f64, 0.0)).collect();
    let mut curve = Polyline::open(points.clone()).unwrap();
    let twin = Polyline::open(points).unwrap();
    assert_eq!(curve, twin, "same points, another polyline");
    let regions = CurveRegions::from_spans(&curve, &[Span::new(4, 8)], &[Span::new(0, 2)]).unwrap();
    assert!(matches!(
        PolylineSession::new(&twin, &regions, PolylineOptions::default()),
        Err(BendelsKleinError::Stale(_))
    ));
    assert!(matches!(
        PolylineSession::new(&twin, &regions, PolylineOptions::default()),
        Err(e) if e.to_string().contains("the curve regions")
    ));
    PolylineSession::new(&curve, &regions, PolylineOptions::default()).unwrap();
    curve.set_point(10, DVec2::new(10.0, 1.0)).unwrap();
    PolylineSession::new(&curve, &regions, PolylineOptions::default()).unwrap();
    curve.insert_point(14, DVec2::new(14.0, 0.0)).unwrap();
    assert!(matches!(
        PolylineSession::new(&curve, &regions, PolylineOptions::default()),
        Err(BendelsKleinError::Stale(_))
    ));
    let roles = vec![Role::Deformable; 15];
    assert!(
        CurveRegions::from_roles(&curve, roles).is_err(),
        "no handle"
    );
}
