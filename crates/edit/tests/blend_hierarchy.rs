//! Bendels & Klein's adaptive refinement made at a coarse level of a hierarchy: the new
//! vertices are added at the input, every level stays reachable, the handle lands exactly
//! and the fixed part does not move (on a generated mesh).

use edit::bendels_klein::{BlendOptions, BlendSession, RefineOptions, Regions};
use edit::HierarchyEdit;
use glam::{DMat4, DVec3};
use halfedge::hierarchy::{Hierarchy, HierarchyOptions};
use halfedge::{generators, VertexId};

#[test]
fn refinement_at_a_coarse_level_composes_with_the_hierarchy() {
    let original = generators::icosphere(5);
    let level = 2;
    let mut h = Hierarchy::build(original.clone(), &HierarchyOptions::rounds()).unwrap();
    h.go_to_level(level).unwrap();
    let coarse = h.mesh();
    let handle: Vec<VertexId> = coarse
        .vertices()
        .filter(|&v| coarse.position(v).z > 0.8)
        .collect();
    let fixed: Vec<VertexId> = coarse
        .vertices()
        .filter(|&v| coarse.position(v).z < 0.0)
        .collect();
    let regions = Regions::from_sets(coarse, &handle, &fixed).unwrap();
    let roles = regions.roles().to_vec();
    let ancestors = h.ancestors(level).unwrap();
    let mut session = BlendSession::new(coarse, regions, BlendOptions::default()).unwrap();
    let a = DMat4::from_translation(DVec3::new(0.2, 0.0, 1.5));
    session.apply(h.mesh_mut(), a).unwrap();
    let fine_edge = original.mean_edge_length();
    let report = session
        .refine_in_hierarchy(
            &mut h,
            RefineOptions::default()
                .with_max_edge_length(2.0 * fine_edge)
                .with_max_new_vertices(100_000),
        )
        .unwrap();
    assert!(report.new_vertices > 100, "{report:?}");
    assert!(report.longest_edge <= 2.0 * fine_edge);
    assert_eq!(h.current_level(), Some(level.min(h.coarsest_level())));
    // Every level is reachable, both ways.
    for l in (0..h.n_levels()).chain((0..h.n_levels()).rev()) {
        h.go_to_level(l).unwrap();
        h.mesh().check().unwrap();
    }
    h.go_to_level(0).unwrap();
    let fine = h.mesh();
    assert_eq!(
        fine.n_vertices(),
        original.n_vertices() + report.new_vertices
    );
    for v in original.vertices() {
        let i = original.vertex_index(v);
        let (before, after) = (original.position(v), fine.position(v));
        match roles[ancestors[i] as usize] {
            edit::bendels_klein::Role::Handle => {
                let target = a.transform_point3(before);
                assert!((after - target).length() < 1e-9, "handle vertex {v} missed");
            }
            edit::bendels_klein::Role::Fixed => assert_eq!(after, before, "fixed vertex {v} moved"),
            edit::bendels_klein::Role::Deformable => {}
        }
    }
    // The session described the coarse mesh before the refinement.
    h.go_to_level(level.min(h.coarsest_level())).unwrap();
    assert!(session.apply(h.mesh_mut(), a).is_err());
}

#[test]
fn a_handle_rotated_at_a_coarse_level_lands_exactly() {
    // Dragged twice (as a user does), then refined: the handle's fine vertices are the
    // last transform of their originals, the fixed part did not move.
    let original = generators::icosphere(5);
    let level = 3;
    let mut h = Hierarchy::build(original.clone(), &HierarchyOptions::qem()).unwrap();
    h.go_to_level(level).unwrap();
    let coarse = h.mesh();
    let pick = |f: &dyn Fn(DVec3) -> bool| -> Vec<VertexId> {
        coarse
            .vertices()
            .filter(|&v| f(coarse.position(v)))
            .collect()
    };
    let handle = pick(&|p| p.x > 0.7);
    let fixed = pick(&|p| p.x < -0.2);
    let regions = Regions::from_sets(coarse, &handle, &fixed).unwrap();
    let roles = regions.roles().to_vec();
    let ancestors = h.ancestors(level).unwrap();
    let mut session = BlendSession::new(coarse, regions, BlendOptions::default()).unwrap();
    let turn = |angle: f64| {
        DMat4::from_translation(DVec3::X)
            * DMat4::from_rotation_y(angle)
            * DMat4::from_translation(-DVec3::X)
    };
    for angle in [0.3, 0.6] {
        session.apply(h.mesh_mut(), turn(angle)).unwrap();
        session.mark(&mut h).unwrap();
    }
    h.refine_to(0).unwrap();
    let a = turn(0.6);
    let mut handle_vertices = 0;
    for v in original.vertices() {
        let (before, after) = (original.position(v), h.mesh().position(v));
        match roles[ancestors[original.vertex_index(v)] as usize] {
            edit::bendels_klein::Role::Handle => {
                handle_vertices += 1;
                let error = (after - a.transform_point3(before)).length();
                assert!(error < 1e-9, "handle vertex {v} off by {error}");
            }
            edit::bendels_klein::Role::Fixed => assert_eq!(after, before),
            edit::bendels_klein::Role::Deformable => {}
        }
    }
    assert!(handle_vertices > 100);
    // The fine vertices of the deformable region interpolate the blend's motion: no
    // face turns over where the handle's motion meets the rest.
    let normal = |m: &halfedge::Mesh, f| {
        let [p, q, r] = m.triangle(f).map(|v| m.position(v));
        (q - p).cross(r - p)
    };
    let flipped = original
        .faces()
        .filter(|&f| normal(&original, f).dot(normal(h.mesh(), f)) <= 0.0)
        .count();
    assert_eq!(flipped, 0);
}
