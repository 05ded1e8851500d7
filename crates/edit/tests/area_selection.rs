//! Editing areas (Lee 1999 §3.2) and their embedding (§4) on real meshes: picks joined
//! by shortest paths, disk checks with typed errors, the harmonic and mean-value maps.

use edit::lee::LeeError;
use edit::lee::{
    AreaSide, BoundaryMapping, EditingArea, Embedding, EmbeddingOptions, EmbeddingSolver,
    EmbeddingWeights,
};
use glam::{DVec2, DVec3};
use halfedge::{FaceId, Mesh, VertexId};
use testkit::regions::{nose, vertex};

/// Ring distance (breadth-first) of every vertex slot from `seed`.
fn rings(mesh: &Mesh, seed: VertexId) -> Vec<u32> {
    let mut ring = vec![u32::MAX; mesh.vertex_slots()];
    ring[mesh.vertex_index(seed)] = 0;
    let mut queue = std::collections::VecDeque::from([seed]);
    while let Some(v) = queue.pop_front() {
        let r = ring[mesh.vertex_index(v)];
        for w in mesh.adjacent_vertices(v) {
            if ring[mesh.vertex_index(w)] == u32::MAX {
                ring[mesh.vertex_index(w)] = r + 1;
                queue.push_back(w);
            }
        }
    }
    ring
}

#[test]
fn four_picks_around_spots_snout_become_the_rectangle_corners() {
    four_picks_around_spots_snout_become_the_rectangle_corners_with(&testkit::stand_in::by_shape);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn four_picks_around_spots_snout_become_the_rectangle_corners_on_real_meshes() {
    four_picks_around_spots_snout_become_the_rectangle_corners_with(&testkit::load_shared);
}

fn four_picks_around_spots_snout_become_the_rectangle_corners_with(load: &dyn Fn(&str) -> Mesh) {
    let mesh = load("spot.obj");
    let nose = nose(&mesh);
    let disk = EditingArea::disk_around(&mesh, nose, 300).unwrap();
    let b = disk.boundary();
    let picks: Vec<VertexId> = (0..4).map(|k| b[k * b.len() / 4]).collect();
    let area = EditingArea::from_picks(&mesh, &picks, AreaSide::Vertex(nose)).unwrap();
    assert!(area.contains(&mesh, nose) && !area.is_boundary(&mesh, nose));
    assert!(area.faces().len() < mesh.n_faces() / 4);
    let smaller = EditingArea::from_picks(&mesh, &picks, AreaSide::Smaller).unwrap();
    assert_eq!(smaller.faces().len(), area.faces().len());
    let embedding = Embedding::new(&mesh, &area, &EmbeddingOptions::default()).unwrap();
    let size = embedding.size();
    let corners = [
        DVec2::ZERO,
        DVec2::new(size.x, 0.0),
        size,
        DVec2::new(0.0, size.y),
    ];
    let mut found: Vec<DVec2> = picks
        .iter()
        .map(|&p| embedding.uv()[area.local_index(&mesh, p).unwrap()])
        .collect();
    found.sort_by(|a, b| (a.x + 2.0 * a.y).total_cmp(&(b.x + 2.0 * b.y)));
    let mut expected = corners.to_vec();
    expected.sort_by(|a, b| (a.x + 2.0 * a.y).total_cmp(&(b.x + 2.0 * b.y)));
    assert_eq!(found, expected);
    // the perimeter of the rectangle is the loop's length
    let loop_length: f64 = (0..area.boundary().len())
        .map(|k| {
            let (p, q) = (
                area.boundary()[k],
                area.boundary()[(k + 1) % area.boundary().len()],
            );
            mesh.position(p).distance(mesh.position(q))
        })
        .sum();
    assert!((2.0 * (size.x + size.y) - loop_length).abs() < 1e-9 * loop_length);
    // the far side of the loop is a disk too (spot is a sphere; so is the creature's head,
    // whose eyes are components of their own)
    let tail = mesh
        .vertices()
        .min_by(|&a, &b| mesh.position(a).z.total_cmp(&mesh.position(b).z))
        .unwrap();
    let rest = EditingArea::from_picks(&mesh, &picks, AreaSide::Vertex(tail)).unwrap();
    let head = mesh.select_linked(&[nose]).unwrap();
    let head_faces = mesh
        .faces()
        .filter(|&f| head.contains(&mesh, mesh.triangle(f)[0]))
        .count();
    assert_eq!(rest.faces().len() + area.faces().len(), head_faces);
}

#[test]
fn an_annulus_is_not_a_disk() {
    an_annulus_is_not_a_disk_with(&testkit::stand_in::by_shape);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn an_annulus_is_not_a_disk_on_real_meshes() {
    an_annulus_is_not_a_disk_with(&testkit::load_shared);
}

fn an_annulus_is_not_a_disk_with(load: &dyn Fn(&str) -> Mesh) {
    let mesh = load("spot.obj");
    let ring = rings(&mesh, nose(&mesh));
    let annulus: Vec<FaceId> = mesh
        .faces()
        .filter(|&f| {
            mesh.triangle(f)
                .iter()
                .all(|&v| (3..=6).contains(&ring[mesh.vertex_index(v)]))
        })
        .collect();
    match EditingArea::from_faces(&mesh, &annulus) {
        Err(LeeError::AreaNotDisk {
            boundary_loops: 2,
            components: 1,
            euler: 0,
        }) => {}
        other => panic!("expected an annulus error, got {other:?}"),
    }
}

#[test]
fn an_area_touching_the_bunnys_holes_is_refused() {
    // The bunny's holes matter here, not its shape: the stand-in with holes.
    an_area_touching_the_bunnys_holes_is_refused_with(&testkit::stand_in::by_topology);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn an_area_touching_the_bunnys_holes_is_refused_on_real_meshes() {
    an_area_touching_the_bunnys_holes_is_refused_with(&testkit::load_shared);
}

fn an_area_touching_the_bunnys_holes_is_refused_with(load: &dyn Fn(&str) -> Mesh) {
    let mesh = load("stanford-bunny.obj");
    let on_hole = mesh
        .vertices()
        .find(|&v| mesh.is_boundary_vertex(v) && !mesh.is_isolated(v))
        .unwrap();
    let area = EditingArea::disk_around(&mesh, on_hole, 40);
    assert!(
        matches!(area, Err(LeeError::AreaTouchesMeshBoundary { .. })),
        "{area:?}"
    );
}

#[test]
fn a_handle_and_a_non_separating_loop_are_refused() {
    let mesh = halfedge::generators::torus(2.0, 1.0, 24, 12).unwrap();
    // the torus minus a small disk: one boundary loop but a handle
    let ring = rings(&mesh, mesh.vertex_at(0).unwrap());
    let with_handle: Vec<FaceId> = mesh
        .faces()
        .filter(|&f| {
            mesh.triangle(f)
                .iter()
                .any(|&v| ring[mesh.vertex_index(v)] > 1)
        })
        .collect();
    match EditingArea::from_faces(&mesh, &with_handle) {
        Err(LeeError::AreaNotDisk {
            boundary_loops: 1,
            euler: -1,
            ..
        }) => {}
        other => panic!("expected a handle error, got {other:?}"),
    }
    // a loop around the tube (a meridian) does not cut the torus in two
    let meridian: Vec<VertexId> = [0, 4, 8]
        .iter()
        .map(|&j| mesh.vertex_at(j * 24).unwrap())
        .collect();
    assert!(matches!(
        EditingArea::from_picks(&mesh, &meridian, AreaSide::Smaller),
        Err(LeeError::LoopDoesNotSeparate)
    ));
}

#[test]
fn mean_value_map_of_a_disk_has_no_flipped_triangles() {
    // 3,000 vertices of the bumpy blob around its +x side.
    let mesh = testkit::data("blob.obj");
    let seed = mesh.extreme_vertex(DVec3::X).unwrap().unwrap();
    mean_value_map_has_no_flipped_triangles(&mesh, seed);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn mean_value_map_of_a_bunny_disk_has_no_flipped_triangles() {
    let mesh = testkit::load_shared("stanford-bunny.obj");
    // the back of the bunny, away from its holes
    let seed = vertex(&mesh, 3284);
    mean_value_map_has_no_flipped_triangles(&mesh, seed);
}

/// A disk of 3,000 vertices around `seed`: the mean-value map never folds, the
/// harmonic one folds at most 1 % of the faces.
fn mean_value_map_has_no_flipped_triangles(mesh: &Mesh, seed: VertexId) {
    let mesh = mesh.clone();
    let area = EditingArea::disk_around(&mesh, seed, 3000).unwrap();
    assert!(area.vertices().len() >= 3000);
    let options = EmbeddingOptions::default().with_weights(EmbeddingWeights::MeanValue);
    let embedding = Embedding::new(&mesh, &area, &options).unwrap();
    assert_eq!(embedding.solver(), EmbeddingSolver::Lu);
    assert!(
        embedding.flipped_faces().is_empty(),
        "{} flipped",
        embedding.flipped_faces().len()
    );
    let size = embedding.size();
    for &p in embedding.uv() {
        assert!(p.is_finite());
        assert!(
            p.cmpge(DVec2::splat(-1e-12)).all() && p.cmple(size + 1e-12).all(),
            "{p}"
        );
    }
    // the images of the faces tile the rectangle: their signed areas sum to its area
    let local = |v: VertexId| embedding.uv()[area.local_index(&mesh, v).unwrap()];
    let total: f64 = area
        .faces()
        .iter()
        .map(|&f| {
            let [a, b, c] = mesh.triangle(f).map(local);
            0.5 * (b - a).perp_dot(c - a)
        })
        .sum();
    // the corners of the rectangle are cut where the loop's chord skips them
    assert!(total <= size.x * size.y * (1.0 + 1e-9) && total > 0.98 * size.x * size.y);

    // the paper's cotangent weights: same patch, Cholesky, flips (if any) reported
    let harmonic = Embedding::new(&mesh, &area, &EmbeddingOptions::default()).unwrap();
    assert_eq!(harmonic.solver(), EmbeddingSolver::Cholesky);
    assert!(harmonic.uv().iter().all(|p| p.is_finite()));
    assert!(harmonic.flipped_faces().len() < area.faces().len() / 100);
}

#[test]
fn corners_must_be_distinct_boundary_vertices() {
    corners_must_be_distinct_boundary_vertices_with(&testkit::stand_in::by_shape);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn corners_must_be_distinct_boundary_vertices_on_real_meshes() {
    corners_must_be_distinct_boundary_vertices_with(&testkit::load_shared);
}

fn corners_must_be_distinct_boundary_vertices_with(load: &dyn Fn(&str) -> Mesh) {
    let mesh = load("spot.obj");
    let nose = nose(&mesh);
    let area = EditingArea::disk_around(&mesh, nose, 200).unwrap();
    let b = area.boundary().to_vec();
    let options = |boundary| EmbeddingOptions::default().with_boundary(boundary);
    assert!(matches!(
        Embedding::new(&mesh, &area, &options(BoundaryMapping::Corners([b[0], b[3], nose, b[9]]))),
        Err(LeeError::CornerNotOnBoundary { vertex }) if vertex == nose
    ));
    assert!(matches!(
        Embedding::new(
            &mesh,
            &area,
            &options(BoundaryMapping::Corners([b[0], b[3], b[0], b[9]]))
        ),
        Err(LeeError::RepeatedCorner { .. })
    ));
    let fixed = EmbeddingOptions::default()
        .with_aspect_ratio(2.0)
        .with_boundary(BoundaryMapping::OneCorner(b[5]));
    let embedding = Embedding::new(&mesh, &area, &fixed).unwrap();
    assert!((embedding.size().x / embedding.size().y - 2.0).abs() < 1e-12);
    assert_eq!(
        embedding.uv()[area.local_index(&mesh, b[5]).unwrap()],
        DVec2::ZERO
    );
}
