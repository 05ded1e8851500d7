//! Selecting vertices (module `selection`) and picking along rays (module `bvh`), on
//! generated meshes: every query against a brute-force answer or an analytic one, and
//! bad arguments as typed errors.

use glam::DVec3;
use halfedge::bvh::{Bvh, Ray};
use halfedge::selection::Selection;
use halfedge::{generators, Error, Mesh, VertexId};

/// A unit sphere with an isolated vertex far above it (as scans carry unreferenced
/// points).
fn sphere_with_loose_point() -> (Mesh, VertexId) {
    let mut mesh = generators::icosphere(3);
    let loose = mesh.add_vertex(DVec3::new(0.0, 0.0, 10.0));
    (mesh, loose)
}

/// A copy of `mesh` with one edge collapsed, and the vertex that went away.
fn with_a_removed_vertex(mesh: &Mesh) -> (Mesh, VertexId) {
    let mut copy = mesh.clone();
    let e = copy
        .halfedges()
        .find(|&h| copy.is_collapse_ok(h).is_ok())
        .unwrap();
    let removed = copy.from_vertex(e);
    copy.collapse(e).unwrap();
    (copy, removed)
}

/// Two spheres side by side and a small one: three components.
fn three_spheres() -> Mesh {
    let a = generators::icosphere(2);
    let mut b = generators::icosphere(2);
    for p in b.positions_mut() {
        *p += DVec3::new(3.0, 0.0, 0.0);
    }
    let mut c = generators::icosphere(1);
    for p in c.positions_mut() {
        *p = *p * 0.2 + DVec3::new(0.0, 2.0, 0.0);
    }
    generators::disjoint_union(&[&a, &b, &c]).unwrap()
}

#[test]
fn nearest_and_extreme_vertices_match_brute_force_and_skip_isolated_vertices() {
    let (mesh, loose) = sphere_with_loose_point();
    for k in 0..50 {
        let t = k as f64 * 0.7;
        let q = DVec3::new(t.cos() * 1.3, (2.1 * t).sin(), (0.3 * t).cos() * 0.9);
        let expected = mesh
            .vertices()
            .filter(|&v| v != loose)
            .min_by(|&a, &b| {
                mesh.position(a)
                    .distance(q)
                    .total_cmp(&mesh.position(b).distance(q))
            })
            .unwrap();
        let got = mesh.nearest_vertex(q).unwrap().unwrap();
        assert_eq!(
            mesh.position(got).distance(q),
            mesh.position(expected).distance(q)
        );
        let d = q.normalize();
        let tip = mesh.extreme_vertex(d).unwrap().unwrap();
        let best = mesh
            .vertices()
            .filter(|&v| v != loose)
            .map(|v| mesh.position(v).dot(d))
            .fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(mesh.position(tip).dot(d), best);
    }
    // The loose point is nearest to itself, and the highest point, but never chosen.
    assert_ne!(
        mesh.nearest_vertex(DVec3::new(0.0, 0.0, 10.0)).unwrap(),
        Some(loose)
    );
    assert_ne!(mesh.extreme_vertex(DVec3::Z).unwrap(), Some(loose));
    // Errors and empty answers.
    assert!(matches!(
        mesh.nearest_vertex(DVec3::NAN),
        Err(Error::InvalidArgument(_))
    ));
    assert!(matches!(
        mesh.extreme_vertex(DVec3::ZERO),
        Err(Error::InvalidArgument(_))
    ));
    assert!(matches!(
        mesh.extreme_vertex(DVec3::new(f64::INFINITY, 0.0, 0.0)),
        Err(Error::InvalidArgument(_))
    ));
    let empty = Mesh::new();
    assert_eq!(empty.nearest_vertex(DVec3::ZERO).unwrap(), None);
    assert_eq!(empty.extreme_vertex(DVec3::X).unwrap(), None);
}

#[test]
fn euclidean_ball_is_exactly_the_vertices_within_the_radius() {
    let (mesh, loose) = sphere_with_loose_point();
    let centre = DVec3::new(0.3, 0.8, 0.4);
    for radius in [0.0, 0.2, 0.7, 1.5, 3.0, 20.0] {
        let ball = mesh.select_ball(centre, radius).unwrap();
        let expected: Vec<VertexId> = mesh
            .vertices()
            .filter(|&v| v != loose && mesh.position(v).distance(centre) <= radius)
            .collect();
        assert_eq!(ball.vertices(&mesh), expected, "radius {radius}");
        assert_eq!(ball.len(), expected.len());
        assert!(!ball.contains(&mesh, loose));
    }
    assert!(mesh.select_ball(centre, -1.0).is_err());
    assert!(mesh.select_ball(centre, f64::NAN).is_err());
    assert!(mesh.select_ball(DVec3::INFINITY, 1.0).is_err());
}

#[test]
fn edge_distances_follow_grid_lines_and_bound_the_euclidean_distance() {
    // A 20 × 20 grid of unit cells: along a grid line the edge path is straight.
    let mesh = generators::grid(20, 20, 20.0, 20.0);
    let corner = mesh.vertex_at(0).unwrap();
    let d = mesh.edge_distances(&[corner], f64::INFINITY).unwrap();
    for i in 0..=20 {
        assert_eq!(d[i], i as f64, "along the x axis");
        assert_eq!(d[i * 21], i as f64, "along the y axis");
    }
    // The grid's diagonals run from (i, j) to (i+1, j+1): the diagonal is walked along them.
    assert!((d[10 + 10 * 21] - 10.0 * 2f64.sqrt()).abs() < 1e-9);
    for v in mesh.vertices() {
        let e = mesh.position(v).distance(mesh.position(corner));
        assert!(d[mesh.vertex_index(v)] >= e - 1e-12);
        // From the corner a path mixes axis and diagonal edges: at most 8.3 % longer
        // than the straight line (at slope √2 − 1).
        assert!(d[mesh.vertex_index(v)] <= 1.09 * e + 1e-12);
    }
    // The walk stops at the radius; the ball holds exactly the vertices within it.
    let centre = mesh.vertex_at(10 + 10 * 21).unwrap();
    let limited = mesh.edge_distances(&[centre], 3.0).unwrap();
    let full = mesh.edge_distances(&[centre], f64::INFINITY).unwrap();
    for (a, b) in limited.iter().zip(&full) {
        if *b <= 3.0 {
            assert_eq!(a, b);
        } else {
            assert!(a.is_infinite());
        }
    }
    let ball = mesh.select_edge_ball(&[centre], 3.0).unwrap();
    assert_eq!(ball.len(), full.iter().filter(|&&d| d <= 3.0).count());
    assert!(ball.contains(&mesh, centre));
    // Several seeds: the distance to the nearest one.
    let other = mesh.vertex_at(20).unwrap();
    let two = mesh
        .edge_distances(&[corner, other], f64::INFINITY)
        .unwrap();
    let from_other = mesh.edge_distances(&[other], f64::INFINITY).unwrap();
    for i in 0..two.len() {
        assert_eq!(two[i], d[i].min(from_other[i]));
    }
    // Errors: a negative radius, a removed vertex.
    assert!(mesh.edge_distances(&[corner], -1.0).is_err());
    let (collapsed, removed) = with_a_removed_vertex(&mesh);
    assert!(matches!(
        collapsed.edge_distances(&[removed], 1.0),
        Err(Error::InvalidHandle(_))
    ));
    assert!(collapsed.select_edge_ball(&[removed], 1.0).is_err());
    assert!(collapsed.select_linked(&[removed]).is_err());
}

#[test]
fn components_are_listed_largest_first_and_select_linked_gives_each_one() {
    let mut mesh = three_spheres();
    mesh.add_vertex(DVec3::new(9.0, 9.0, 9.0));
    let components = mesh.components();
    assert_eq!(components.len(), 4);
    let faces: Vec<usize> = components.iter().map(|c| c.faces).collect();
    assert_eq!(faces, [320, 320, 80, 0]);
    // The first two are the unit spheres at x = 0 and x = 3 (equal sizes: by index).
    assert!(components[0].centroid.length() < 1e-9);
    assert!((components[1].centroid - DVec3::new(3.0, 0.0, 0.0)).length() < 1e-9);
    assert!((components[2].centroid - DVec3::new(0.0, 2.0, 0.0)).length() < 1e-9);
    assert_eq!(components[3].centroid, DVec3::new(9.0, 9.0, 9.0));
    let area = 4.0 * std::f64::consts::PI;
    assert!((components[0].area - area).abs() < 0.1 * area);
    let mut seen = vec![false; mesh.vertex_slots()];
    for c in &components {
        let linked = mesh.select_linked(&[c.vertex]).unwrap();
        assert_eq!(linked.len(), c.vertices);
        for v in linked.vertices(&mesh) {
            assert!(!std::mem::replace(&mut seen[mesh.vertex_index(v)], true));
        }
    }
    assert!(seen.iter().all(|&s| s));
    // A selection across two components links both.
    let two = mesh
        .select_linked(&[components[0].vertex, components[2].vertex])
        .unwrap();
    assert_eq!(two.len(), components[0].vertices + components[2].vertices);
}

#[test]
fn the_largest_component_and_its_extreme_vertex_skip_loose_parts() {
    // The small sphere sits highest (y up to 2.2): the mesh's top vertex is on it, the
    // largest component's is on the unit sphere at x = 0.
    let mesh = three_spheres();
    let top = mesh.extreme_vertex(DVec3::Y).unwrap().unwrap();
    assert!(mesh.position(top).y > 2.0);
    let largest = mesh.select_largest_component();
    assert_eq!(largest.len(), mesh.components()[0].vertices);
    let tip = largest.extreme_vertex(&mesh, DVec3::Y).unwrap().unwrap();
    assert!(largest.contains(&mesh, tip));
    assert!((mesh.position(tip) - DVec3::Y).length() < 1e-9);
    // The same as the brute force over the component.
    let best = largest
        .vertices(&mesh)
        .into_iter()
        .map(|v| mesh.position(v).y)
        .fold(f64::NEG_INFINITY, f64::max);
    assert_eq!(mesh.position(tip).y, best);
    // A vertex whose position is not finite is never the answer.
    let mut broken = mesh.clone();
    broken.set_position(tip, DVec3::new(0.0, f64::NAN, 0.0));
    let far = broken.vertices().next().unwrap();
    broken.set_position(far, DVec3::splat(f64::INFINITY));
    let body = broken.select_largest_component();
    let other = body.extreme_vertex(&broken, DVec3::Y).unwrap().unwrap();
    assert!(other != tip && other != far && broken.position(other).is_finite());
    for v in [
        broken.extreme_vertex(DVec3::Y).unwrap().unwrap(),
        broken.nearest_vertex(DVec3::splat(1e300)).unwrap().unwrap(),
    ] {
        assert!(broken.position(v).is_finite());
    }
    // Bad directions and stale selections are refused; an empty mesh has an empty one.
    assert!(largest.extreme_vertex(&mesh, DVec3::ZERO).is_err());
    assert!(largest
        .extreme_vertex(&generators::icosphere(1), DVec3::Y)
        .is_err());
    // The middle of an open patch is farthest from its boundary; a closed mesh has none.
    let grid = generators::grid(10, 10, 1.0, 1.0);
    let middle = grid.farthest_from_boundary().unwrap().unwrap();
    let p = grid.position(middle);
    assert!((p.x - 0.5).abs() <= 0.1 && (p.y - 0.5).abs() <= 0.1, "{p}");
    assert_eq!(mesh.farthest_from_boundary().unwrap(), None);
    let empty = Mesh::new();
    assert_eq!(empty.farthest_from_boundary().unwrap(), None);
    let none = empty.select_largest_component();
    assert!(none.is_empty());
    assert_eq!(none.extreme_vertex(&empty, DVec3::Y).unwrap(), None);
}

#[test]
fn grow_and_shrink_move_the_selection_border_ring_by_ring() {
    let mesh = generators::grid(20, 20, 20.0, 20.0);
    let centre = mesh.vertex_at(10 + 10 * 21).unwrap();
    let mut s = Selection::from_vertices(&mesh, &[centre]).unwrap();
    s.grow(&mesh, 3).unwrap();
    // Three rings on this grid: the vertices at most three edges away.
    let hops = |v: VertexId| -> usize {
        let (dx, dy) = (
            mesh.vertex_index(v) as i64 % 21 - 10,
            mesh.vertex_index(v) as i64 / 21 - 10,
        );
        // Edges go along x, along y and along the (+1, +1) diagonal.
        if dx * dy > 0 {
            dx.abs().max(dy.abs()) as usize
        } else {
            (dx.abs() + dy.abs()) as usize
        }
    };
    let expected: Vec<VertexId> = mesh.vertices().filter(|&v| hops(v) <= 3).collect();
    assert_eq!(s.vertices(&mesh), expected);
    // Shrinking takes the rings back off, one at a time.
    let grown = s.clone();
    s.shrink(&mesh, 2).unwrap();
    let expected: Vec<VertexId> = mesh.vertices().filter(|&v| hops(v) <= 1).collect();
    assert_eq!(s.vertices(&mesh), expected);
    s.grow(&mesh, 2).unwrap();
    assert_eq!(s, grown);
    s.shrink(&mesh, 10).unwrap();
    assert!(s.is_empty());
    // The mesh's own boundary is not a selection border: the whole grid does not shrink.
    let mut all = mesh.select_linked(&[centre]).unwrap();
    all.shrink(&mesh, 1).unwrap();
    assert_eq!(all.len(), mesh.n_vertices());
    // A selection of another mesh is refused and left unchanged, also when that mesh
    // has the same number of vertices (the selection is bound to its mesh); a clone of
    // its mesh is the same mesh.
    let before = s.clone();
    for other in [
        generators::icosphere(1),
        generators::grid(20, 20, 20.0, 20.0),
    ] {
        assert!(matches!(s.grow(&other, 1), Err(Error::Stale(_))));
        assert!(matches!(s.shrink(&other, 1), Err(Error::Stale(_))));
        assert!(s.linked(&other).is_err());
        assert!(!s.contains(&other, other.vertex_at(0).unwrap()) || s.is_empty());
        assert_eq!(s, before);
    }
    let mut copy = s.clone();
    copy.grow(&mesh.clone(), 1).unwrap();
    assert!(Selection::from_mask(&mesh, vec![true; 3]).is_err());
    let (collapsed, removed) = with_a_removed_vertex(&mesh);
    assert!(Selection::from_vertices(&collapsed, &[removed]).is_err());
    let mut t = Selection::empty(&collapsed);
    assert!(t.insert(&collapsed, removed).is_err());
    assert!(!grown.contains(&collapsed, removed));
}

#[test]
fn selection_masks_drop_removed_vertices() {
    let mut mesh = generators::icosphere(2);
    let e = mesh.halfedges().next().unwrap();
    let removed = mesh.from_vertex(e);
    let slot = mesh.vertex_index(removed);
    mesh.collapse(e).unwrap();
    let all = Selection::from_mask(&mesh, vec![true; mesh.vertex_slots()]).unwrap();
    assert_eq!(all.len(), mesh.n_vertices());
    assert!(!all.contains(&mesh, removed));
    assert!(!all.mask()[slot]);
    assert_eq!(all.vertices(&mesh), mesh.vertices().collect::<Vec<_>>());
}

#[test]
fn rays_pick_the_nearest_vertex_of_the_face_they_hit_first() {
    let mesh = three_spheres();
    let mut bvh = Bvh::build(&mesh);
    // A ray along +x through the centres hits the first sphere at x = −1.
    let ray = Ray::new(DVec3::new(-5.0, 0.0, 0.0), DVec3::X).unwrap();
    let hit = bvh.intersect(&mesh, &ray).unwrap().unwrap();
    assert!((hit.point.x + 1.0).abs() < 0.05, "{}", hit.point);
    assert!((hit.t - 4.0).abs() < 0.05);
    assert_eq!(
        hit.nearest_vertex,
        mesh.extreme_vertex(-DVec3::X).unwrap().unwrap()
    );
    // From the other side it hits the second sphere.
    let back = Ray::new(DVec3::new(9.0, 0.0, 0.0), -DVec3::X).unwrap();
    let hit = bvh.intersect(&mesh, &back).unwrap().unwrap();
    assert!((hit.point.x - 4.0).abs() < 0.05);
    // Moving the mesh makes the hierarchy stale until it is updated.
    let mut moved = mesh.clone();
    for p in moved.positions_mut() {
        p.y += 10.0;
    }
    assert!(bvh.intersect(&moved, &ray).is_err());
    bvh.update(&moved);
    assert!(bvh.intersect(&moved, &ray).unwrap().is_none());
    let high = Ray::new(DVec3::new(-5.0, 10.0, 0.0), DVec3::X).unwrap();
    assert!(bvh.intersect(&moved, &high).unwrap().is_some());
    // A ray meets a plane in front of it, not behind.
    let p = ray.intersect_plane(DVec3::ZERO, DVec3::X).unwrap();
    assert_eq!(p, DVec3::ZERO);
    assert!(ray
        .intersect_plane(DVec3::new(-9.0, 0.0, 0.0), DVec3::X)
        .is_none());
    assert!(ray.intersect_plane(DVec3::ZERO, DVec3::Y).is_none());
}

/// The real-mesh counterpart: the bunny (holes, 1,113 unreferenced vertices).
#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn bvh_matches_brute_force_on_the_bunny() {
    let mesh = testkit::load_shared("stanford-bunny.obj");
    let bvh = Bvh::build(&mesh);
    assert_eq!(bvh.len(), 69_451);
    let (lo, hi) = mesh.bounding_box().unwrap();
    let centre = 0.5 * (lo + hi);
    let mut hits = 0;
    for k in 0..100 {
        let t = k as f64 * 0.37;
        let origin = centre + (hi - lo).length() * DVec3::new(t.cos(), (1.3 * t).sin(), t.sin());
        let aim = centre + 0.4 * (hi - lo) * DVec3::new((2.0 * t).sin(), (0.7 * t).cos(), 0.0);
        let ray = Ray::new(origin, aim - origin).unwrap();
        let brute = mesh
            .faces()
            .filter_map(|f| {
                let [a, b, c] = mesh.triangle_positions(f);
                halfedge::bvh::ray_triangle(&ray, a, b, c).map(|(t, _, _)| t)
            })
            .fold(f64::INFINITY, f64::min);
        match bvh.intersect(&mesh, &ray).unwrap() {
            Some(hit) => {
                hits += 1;
                assert!((hit.t - brute).abs() <= 1e-9 * brute.max(1.0));
            }
            None => assert!(brute.is_infinite()),
        }
    }
    assert!(hits > 25, "{hits} hits");
}
