//! Sub-mesh labels (seed paper, section 4.1): frontiers from picks, collars and plane
//! sections; the two sides labelled; errors for loops that do not separate; the Fig. 4
//! rule through vertex splits; labels defined at any level hold at every other.

use std::collections::HashSet;

use glam::DVec3;
use halfedge::hierarchy::{Hierarchy, HierarchyOptions};
use halfedge::labels::{classify_split, LABEL_ATTRIBUTE};
use halfedge::labels::{Frontier, Label, FRONTIER};
use halfedge::{generators, Attribute, Error, FaceId, Mesh, VertexId};
use testkit::{data, load_shared as load};

/// A mesh with an ear to cut off by a plane: the plane (a point near the ear, the
/// normal), how far in x the ear's vertices lie from the point (the other ear is farther),
/// and how many vertices the ear has at least.
struct Ear {
    mesh: Mesh,
    point: DVec3,
    normal: DVec3,
    half_width: f64,
    min_vertices: usize,
}

/// The bunny's left ear (y up), cut at y = 0.16 (real-mesh tier).
fn bunny_ear() -> Ear {
    Ear {
        mesh: load("stanford-bunny.obj"),
        point: DVec3::new(-0.066, 0.16, -0.017),
        normal: DVec3::Y,
        half_width: 0.04,
        min_vertices: 300,
    }
}

/// The left ear of `data/creature.obj` (y up), subdivided twice to the bunny's size
/// (92,160 faces), cut at y = 1.1; the creature's eyes are separate components.
fn creature_ear() -> Ear {
    let creature = data("creature.obj");
    Ear {
        mesh: generators::subdivide(&generators::subdivide(&creature)),
        point: DVec3::new(-0.45, 1.1, -0.1),
        normal: DVec3::Y,
        half_width: 0.45,
        min_vertices: 300,
    }
}

/// No edge joins two different sub-meshes: the frontier separates them.
fn assert_separated(mesh: &Mesh, labels: Attribute<VertexId, Label>) {
    for h in mesh.edges() {
        let a = *mesh.attribute(labels, mesh.from_vertex(h)).unwrap();
        let b = *mesh.attribute(labels, mesh.to_vertex(h)).unwrap();
        assert!(
            a == b || a == FRONTIER || b == FRONTIER,
            "edge {}–{} joins sub-meshes {a} and {b}",
            mesh.from_vertex(h),
            mesh.to_vertex(h)
        );
    }
}

/// Vertices labelled `label`.
fn side(mesh: &Mesh, labels: Attribute<VertexId, Label>, label: Label) -> HashSet<VertexId> {
    mesh.vertices_labelled(labels, label)
        .unwrap()
        .into_iter()
        .collect()
}

/// The smaller of the two labelled sides (1 or 2).
fn smaller_side(mesh: &Mesh, labels: Attribute<VertexId, Label>) -> Label {
    if side(mesh, labels, 1).len() < side(mesh, labels, 2).len() {
        1
    } else {
        2
    }
}

#[test]
fn plane_section_cuts_off_an_ear() {
    plane_section_cuts_off_the_bunny_ear_with(creature_ear);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn plane_section_cuts_off_the_ear_on_the_bunny() {
    plane_section_cuts_off_the_bunny_ear_with(bunny_ear);
}

fn plane_section_cuts_off_the_bunny_ear_with(ear: fn() -> Ear) {
    let Ear {
        mut mesh,
        point,
        normal,
        half_width,
        min_vertices,
    } = ear();
    let frontier = mesh.frontier_from_plane(point, normal).unwrap();
    let max_edge = frontier
        .halfedges()
        .iter()
        .map(|&h| mesh.edge_length(h))
        .fold(0.0, f64::max);
    // The loop follows the section: its vertices are at most an edge from the plane.
    for v in frontier.vertices(&mesh) {
        let d = (mesh.position(v) - point).dot(normal).abs();
        assert!(d <= max_edge, "frontier vertex {v} is {d} from the plane");
    }
    let (labels, counts) = mesh.label_sides(&frontier, 1, 2).unwrap();
    assert_separated(&mesh, labels);
    assert_eq!(counts.frontier_vertices, frontier.halfedges().len());
    let ear = smaller_side(&mesh, labels);
    let ear_vertices = side(&mesh, labels, ear);
    assert!(ear_vertices.len() > min_vertices, "{counts:?}");
    // The ear is above the plane and near the picked point.
    for &v in &ear_vertices {
        let p = mesh.position(v);
        assert!(
            (p - point).dot(normal) > -max_edge,
            "ear vertex {v} below the plane"
        );
        assert!(
            (p.x - point.x).abs() < half_width,
            "ear vertex {v} is on the other ear"
        );
    }
    assert_eq!(
        mesh.find_attribute::<VertexId, Label>(LABEL_ATTRIBUTE)
            .map(|a| format!("{a:?}")),
        Some(format!("{labels:?}"))
    );
    // Faces take their vertices' sub-mesh; faces of the loop only are frontier faces.
    for f in mesh.faces() {
        let label = mesh.face_label(labels, f).unwrap();
        let vertex_labels: Vec<Label> = mesh
            .face_vertices(f)
            .map(|v| *mesh.attribute(labels, v).unwrap())
            .collect();
        if vertex_labels.iter().all(|&l| l == FRONTIER) {
            assert_eq!(label, FRONTIER);
        } else {
            assert!(
                vertex_labels.contains(&label),
                "face {f}: {label} from {vertex_labels:?}"
            );
        }
    }
}

#[test]
fn picked_vertices_make_the_same_cut() {
    picked_vertices_make_the_same_cut_with(creature_ear);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn picked_vertices_make_the_same_cut_on_the_bunny() {
    picked_vertices_make_the_same_cut_with(bunny_ear);
}

fn picked_vertices_make_the_same_cut_with(ear: fn() -> Ear) {
    let Ear {
        mut mesh,
        point,
        normal,
        ..
    } = ear();
    let section = mesh.frontier_from_plane(point, normal).unwrap();
    let ring = section.vertices(&mesh);
    let picks: Vec<VertexId> = (0..4).map(|k| ring[k * ring.len() / 4]).collect();
    let frontier = mesh.frontier_through(&picks).unwrap();
    let (labels, _) = mesh.label_sides(&frontier, 1, 2).unwrap();
    assert_separated(&mesh, labels);
    let ear = side(&mesh, labels, smaller_side(&mesh, labels));
    let (plane_labels, _) = mesh.label_sides(&section, 1, 2).unwrap();
    let plane_ear = side(&mesh, plane_labels, smaller_side(&mesh, plane_labels));
    let common = ear.intersection(&plane_ear).count();
    assert!(
        common as f64 > 0.8 * plane_ear.len() as f64 && ear.len() < 2 * plane_ear.len(),
        "picked loop cut off {} vertices, the plane {}, {common} in common",
        ear.len(),
        plane_ear.len()
    );
}

#[test]
fn a_collar_of_faces_makes_the_same_cut() {
    a_collar_of_faces_makes_the_same_cut_with(creature_ear);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn a_collar_of_faces_makes_the_same_cut_on_the_bunny() {
    a_collar_of_faces_makes_the_same_cut_with(bunny_ear);
}

fn a_collar_of_faces_makes_the_same_cut_with(ear: fn() -> Ear) {
    let Ear {
        mut mesh,
        point,
        normal,
        ..
    } = ear();
    let section = mesh.frontier_from_plane(point, normal).unwrap();
    // The collar: every face touching the section loop.
    let mut collar: Vec<FaceId> = section
        .vertices(&mesh)
        .iter()
        .flat_map(|&v| mesh.adjacent_faces(v).collect::<Vec<_>>())
        .collect();
    collar.sort_by_key(|&f| mesh.face_index(f));
    collar.dedup();
    let frontier = mesh.frontier_from_collar(&collar).unwrap();
    let (labels, counts) = mesh.label_sides(&frontier, 1, 2).unwrap();
    assert_separated(&mesh, labels);
    // The frontier is the collar's border on the ear's side, and the ear is on its left.
    let ear = side(&mesh, labels, 1);
    assert!(counts.left_faces < counts.right_faces);
    let (plane_labels, _) = mesh.label_sides(&section, 1, 2).unwrap();
    let plane_ear = side(&mesh, plane_labels, smaller_side(&mesh, plane_labels));
    assert!(ear.is_subset(&plane_ear) && ear.len() * 10 > plane_ear.len() * 7);
}

#[test]
fn loops_that_do_not_separate_are_refused() {
    // A meridian of a torus does not separate it.
    let mut t = generators::torus(1.0, 0.35, 16, 8).unwrap();
    let picks: Vec<VertexId> = [0usize, 3, 6]
        .iter()
        .map(|&j| t.vertex_at(j * 16).unwrap())
        .collect();
    let meridian = t.frontier_through(&picks).unwrap();
    let err = t.label_sides(&meridian, 1, 2).unwrap_err();
    assert!(
        matches!(err, Error::InvalidFrontier(ref m) if m.contains("does not separate")),
        "{err}"
    );
    assert!(
        t.find_attribute::<VertexId, Label>(LABEL_ATTRIBUTE)
            .is_none(),
        "changed on error"
    );
    // A plane through the hole cuts the torus in two loops around the tube: each of them
    // alone does not separate either.
    let section = t
        .frontier_from_plane(DVec3::new(1.0, 0.0, 0.0), DVec3::Y)
        .unwrap();
    assert!(matches!(
        t.label_sides(&section, 1, 2),
        Err(Error::InvalidFrontier(_))
    ));
    // A collar that does not go around anything.
    let patch: Vec<FaceId> = t.faces().take(6).collect();
    assert!(matches!(
        t.frontier_from_collar(&patch),
        Err(Error::InvalidFrontier(_))
    ));
    // A plane that misses the mesh, and a section that runs into the boundary.
    assert!(matches!(
        t.frontier_from_plane(DVec3::new(0.0, 0.0, 5.0), DVec3::Z),
        Err(Error::InvalidFrontier(_))
    ));
    let grid = generators::grid(8, 8, 1.0, 1.0);
    assert!(matches!(
        grid.frontier_from_plane(DVec3::new(0.5, 0.5, 0.0), DVec3::X),
        Err(Error::InvalidFrontier(_))
    ));
    // Bad arguments.
    let mut sphere = generators::icosphere(2);
    let loop_ = sphere.frontier_from_plane(DVec3::ZERO, DVec3::Z).unwrap();
    assert!(matches!(
        sphere.label_sides(&loop_, 1, 1),
        Err(Error::InvalidArgument(_))
    ));
    assert!(matches!(
        sphere.label_sides(&loop_, FRONTIER, 1),
        Err(Error::InvalidArgument(_))
    ));
    assert!(matches!(
        sphere.frontier_from_plane(DVec3::ZERO, DVec3::ZERO),
        Err(Error::InvalidArgument(_))
    ));
    assert!(Frontier::new(&sphere, loop_.halfedges()[..3].to_vec()).is_err());
    // The equator of a sphere separates it into halves.
    let (labels, counts) = sphere.label_sides(&loop_, 1, 2).unwrap();
    assert!(
        counts.left_faces > 100 && counts.right_faces > 100,
        "{counts:?}"
    );
    assert_separated(&sphere, labels);
}

#[test]
fn figure_4_rule_for_a_split_vertex() {
    // A 6 × 6 grid: sub-mesh 1 left of x = 0.5, sub-mesh 2 right of it, the column
    // x = 0.5 is the frontier.
    let mut mesh = generators::grid(6, 6, 1.0, 1.0);
    let labels = mesh.label_attribute().unwrap();
    let column = |p: DVec3| ((p.x * 6.0).round() as i32) - 3;
    let vertices: Vec<VertexId> = mesh.vertices().collect();
    for &v in &vertices {
        *mesh.attribute_mut(labels, v).unwrap() = match column(mesh.position(v)) {
            c if c < 0 => 1,
            0 => FRONTIER,
            _ => 2,
        };
    }
    let at = |m: &Mesh, i: usize, j: usize| m.vertex_at(i + 7 * j).unwrap();
    // (b) a frontier vertex collapsed into the next frontier vertex comes back on the
    // frontier (it has neighbours in both sub-meshes).
    // (c) a vertex of sub-mesh 1 collapsed into a frontier vertex comes back in 1.
    // (d) a vertex of sub-mesh 2 collapsed into a frontier vertex comes back in 2.
    for ((i0, j0), (i1, j1), expected) in [
        ((3, 3), (3, 2), FRONTIER),
        ((2, 3), (3, 3), 1),
        ((4, 3), (3, 3), 2),
    ] {
        let (v0, v1) = (at(&mesh, i0, j0), at(&mesh, i1, j1));
        let h = mesh.find_halfedge(v0, v1).unwrap();
        let before = *mesh.attribute(labels, v0).unwrap();
        let record = mesh.collapse(h).unwrap();
        mesh.vertex_split(&record).unwrap();
        *mesh.attribute_mut(labels, v0).unwrap() = 12345;
        classify_split(&mut mesh, labels, v0).unwrap();
        assert_eq!(*mesh.attribute(labels, v0).unwrap(), expected);
        assert_eq!(before, expected);
    }
}

#[test]
fn labels_defined_at_a_coarse_level_propagate_to_the_fine_mesh() {
    labels_defined_at_a_coarse_level_propagate_to_the_fine_mesh_with(creature_ear);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn labels_defined_at_a_coarse_level_propagate_to_the_fine_mesh_on_the_bunny() {
    labels_defined_at_a_coarse_level_propagate_to_the_fine_mesh_with(bunny_ear);
}

fn labels_defined_at_a_coarse_level_propagate_to_the_fine_mesh_with(ear: fn() -> Ear) {
    let Ear {
        mesh,
        point,
        normal,
        ..
    } = ear();
    let mut h = Hierarchy::build(mesh, &HierarchyOptions::rounds().with_max_levels(4)).unwrap();
    let coarse_edge = h.mesh().mean_edge_length();
    let frontier = h.mesh().frontier_from_plane(point, normal).unwrap();
    let (labels, _) = h.mesh_mut().label_sides(&frontier, 1, 2).unwrap();
    h.attach_labels(labels).unwrap();
    let ear = smaller_side(h.mesh(), labels);
    let coarse_ear = side(h.mesh(), labels, ear).len();
    h.refine_to(0).unwrap();
    let mesh = h.mesh();
    mesh.check().unwrap();
    assert_separated(mesh, labels);
    let fine_ear = side(mesh, labels, ear);
    assert!(
        fine_ear.len() > 3 * coarse_ear,
        "{} fine, {coarse_ear} coarse",
        fine_ear.len()
    );
    // The fine ear lies where the coarse one was: above the plane (up to a coarse edge).
    let below = fine_ear
        .iter()
        .filter(|&&v| (mesh.position(v) - point).dot(normal) < -coarse_edge)
        .count();
    assert!(below == 0, "{below} ear vertices well below the plane");
    // Every live vertex is classified, and the frontier stays thin: each frontier vertex
    // has a neighbour inside a sub-mesh.
    let mut frontier_vertices = 0;
    for v in mesh.vertices() {
        let l = *mesh.attribute(labels, v).unwrap();
        assert!(l == 1 || l == 2 || l == FRONTIER);
        if l == FRONTIER && !mesh.is_isolated(v) {
            frontier_vertices += 1;
            assert!(
                mesh.adjacent_vertices(v)
                    .any(|w| *mesh.attribute(labels, w).unwrap() != FRONTIER),
                "frontier vertex {v} is surrounded by frontier vertices"
            );
        }
    }
    assert!(frontier_vertices > 0);
    // Walking again gives the same labels.
    let first: Vec<Label> = mesh.attribute_values(labels).unwrap().to_vec();
    h.coarsen_to(2).unwrap();
    h.refine_to(0).unwrap();
    assert_eq!(h.mesh().attribute_values(labels).unwrap(), &first[..]);
}

#[test]
fn labels_defined_at_the_fine_level_hold_at_every_level() {
    labels_defined_at_the_fine_level_hold_at_every_level_with(creature_ear);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn labels_defined_at_the_fine_level_hold_at_every_level_on_the_bunny() {
    labels_defined_at_the_fine_level_hold_at_every_level_with(bunny_ear);
}

fn labels_defined_at_the_fine_level_hold_at_every_level_with(ear: fn() -> Ear) {
    let Ear {
        mesh,
        point,
        normal,
        ..
    } = ear();
    let mut h = Hierarchy::build(mesh, &HierarchyOptions::qem().with_target_faces(2000)).unwrap();
    h.refine_to(0).unwrap();
    let frontier = h.mesh().frontier_from_plane(point, normal).unwrap();
    let (labels, _) = h.mesh_mut().label_sides(&frontier, 1, 2).unwrap();
    h.attach_labels(labels).unwrap();
    let fine: Vec<Label> = h.mesh().attribute_values(labels).unwrap().to_vec();
    for level in [2, h.coarsest_level(), 1] {
        h.go_to_level(level).unwrap();
        let mesh = h.mesh();
        // Live vertices keep their labels and collapsed ones keep theirs on the tombstone.
        assert_eq!(mesh.attribute_values(labels).unwrap(), &fine[..]);
        for v in mesh.vertices() {
            assert_eq!(
                *mesh.attribute(labels, v).unwrap(),
                fine[mesh.vertex_index(v)]
            );
        }
    }
    h.refine_to(0).unwrap();
    assert_eq!(h.mesh().attribute_values(labels).unwrap(), &fine[..]);
}

/// Vertices of `mesh` with label `label`, as positions.
fn positions_labelled(mesh: &Mesh, labels: Attribute<VertexId, Label>, label: Label) -> Vec<DVec3> {
    mesh.vertices_labelled(labels, label)
        .unwrap()
        .into_iter()
        .map(|v| mesh.position(v))
        .collect()
}

#[test]
fn a_plane_frontier_puts_the_normal_side_on_the_left() {
    // Closed (sphere), genus 1 (torus: the plane x = 1.1 cuts a cap off the outer side
    // of the tube) and open (a grid with a bump, cut around the bump).
    let mut bump = generators::grid(24, 24, 2.0, 2.0);
    for p in bump.positions_mut() {
        p.z = (-((p.x - 1.0).powi(2) + (p.y - 1.0).powi(2)) / 0.1).exp();
    }
    let cases = [
        (
            generators::icosphere(3),
            DVec3::new(0.1, 0.2, 0.3),
            DVec3::Z,
        ),
        (
            generators::icosphere(3),
            DVec3::new(0.0, -0.4, 0.0),
            DVec3::new(0.3, -1.0, 0.2),
        ),
        (
            generators::torus(1.0, 0.35, 40, 16).unwrap(),
            DVec3::new(1.1, 0.0, 0.0),
            DVec3::X,
        ),
        (bump, DVec3::new(1.0, 1.0, 0.5), DVec3::Z),
    ];
    for (k, (mesh, point, normal)) in cases.into_iter().enumerate() {
        let n = normal.normalize();
        let edge = 2.0 * mesh.mean_edge_length();
        for flip in [1.0, -1.0] {
            let mut mesh = mesh.clone();
            let frontier = mesh.frontier_from_plane(point, flip * n).unwrap();
            assert_eq!(frontier.plane(), Some((point, flip * n)));
            let (labels, counts) = mesh.label_sides(&frontier, 1, 2).unwrap();
            assert_separated(&mesh, labels);
            assert!(counts.left_vertices > 0 && counts.right_vertices > 0, "{k}");
            for p in positions_labelled(&mesh, labels, 1) {
                assert!(
                    flip * n.dot(p - point) > -edge,
                    "case {k}: left vertex {p} below"
                );
            }
            for p in positions_labelled(&mesh, labels, 2) {
                assert!(
                    flip * n.dot(p - point) < edge,
                    "case {k}: right vertex {p} above"
                );
            }
            // The reversed loop swaps the sides and flips the plane.
            let reversed = frontier.reversed(&mesh);
            assert_eq!(reversed.plane(), Some((point, -flip * n)));
            let (back, swapped) = mesh.label_sides(&reversed, 1, 2).unwrap();
            assert_eq!(
                (swapped.left_faces, swapped.right_faces),
                (counts.right_faces, counts.left_faces)
            );
            assert_eq!(format!("{back:?}"), format!("{labels:?}"));
        }
    }
}

/// A head (unit sphere) with an eye above the cut and a tooth below it: separate
/// components.
fn head_eye_tooth() -> Mesh {
    let head = generators::icosphere(3);
    let small = |centre: DVec3| {
        let mut m = generators::icosphere(1);
        for p in m.positions_mut() {
            *p = *p * 0.1 + centre;
        }
        m
    };
    let eye = small(DVec3::new(0.3, 0.7, 0.75));
    let tooth = small(DVec3::new(0.0, -0.2, 0.95));
    generators::disjoint_union(&[&head, &eye, &tooth]).unwrap()
}

#[test]
fn components_the_frontier_does_not_cross_go_to_the_side_of_their_centroid() {
    let mut mesh = head_eye_tooth();
    let head = generators::icosphere(3).n_vertices();
    let eye = |i: usize| (head..head + 42).contains(&i);
    let tooth = |i: usize| i >= head + 42;
    // Cut at y = 0.5: the eye's centroid is above, the tooth's below.
    let frontier = mesh
        .frontier_from_plane(DVec3::new(0.0, 0.5, 0.0), DVec3::Y)
        .unwrap();
    let (labels, counts) = mesh.label_sides(&frontier, 1, 2).unwrap();
    assert_separated(&mesh, labels);
    for v in mesh.vertices() {
        let i = mesh.vertex_index(v);
        let l = *mesh.attribute(labels, v).unwrap();
        if eye(i) {
            assert_eq!(l, 1, "the eye goes with the top of the head");
        }
        if tooth(i) {
            assert_eq!(l, 2, "the tooth stays with the bottom");
        }
    }
    assert_eq!(counts.left_faces + counts.right_faces, mesh.n_faces());
    // Downwards, the sides swap and the eye and tooth with them.
    let down = mesh
        .frontier_from_plane(DVec3::new(0.0, 0.5, 0.0), -DVec3::Y)
        .unwrap();
    let (labels, _) = mesh.label_sides(&down, 1, 2).unwrap();
    for v in mesh.vertices() {
        let i = mesh.vertex_index(v);
        if eye(i) {
            assert_eq!(*mesh.attribute(labels, v).unwrap(), 2);
        }
        if tooth(i) {
            assert_eq!(*mesh.attribute(labels, v).unwrap(), 1);
        }
    }
    // A loop through picks has no cutting plane: its side plane is fitted to the loop,
    // with the normal on the loop's left, and the eye goes to the side of the cap it is on.
    let section = mesh
        .frontier_from_plane(DVec3::new(0.0, 0.5, 0.0), DVec3::Y)
        .unwrap();
    let ring = section.vertices(&mesh);
    let picks: Vec<VertexId> = (0..5).map(|k| ring[k * ring.len() / 5]).collect();
    let picked = mesh.frontier_through(&picks).unwrap();
    assert_eq!(picked.plane(), None);
    let (origin, normal) = picked.side_plane(&mesh).unwrap();
    assert!((origin.y - 0.5).abs() < 0.1, "{origin}");
    assert!(normal.y.abs() > 0.95, "{normal}");
    let (labels, _) = mesh.label_sides(&picked, 1, 2).unwrap();
    assert_separated(&mesh, labels);
    let top = mesh.extreme_vertex(DVec3::Y).unwrap().unwrap();
    let cap = *mesh.attribute(labels, top).unwrap();
    for v in mesh.vertices() {
        let i = mesh.vertex_index(v);
        if eye(i) {
            assert_eq!(
                *mesh.attribute(labels, v).unwrap(),
                cap,
                "the eye goes with the cap"
            );
        }
        if tooth(i) {
            assert_ne!(*mesh.attribute(labels, v).unwrap(), cap);
        }
    }
}

#[test]
fn several_sub_meshes_live_in_one_mesh_and_hold_through_the_hierarchy() {
    let mut mesh = head_eye_tooth();
    let labels = mesh.label_attribute().unwrap();
    // The top cap (with the eye) as sub-mesh 1, the bottom cap as sub-mesh 2; the band
    // between keeps label 0.
    let top = mesh
        .frontier_from_plane(DVec3::new(0.0, 0.5, 0.0), DVec3::Y)
        .unwrap();
    let (a, top_counts) = mesh.label_sides_with(&top, Some(1), None).unwrap();
    assert_eq!(format!("{a:?}"), format!("{labels:?}"));
    assert_eq!(top_counts.right_vertices, 0);
    let after_top: Vec<Label> = mesh.attribute_values(labels).unwrap().to_vec();
    let bottom = mesh
        .frontier_from_plane(DVec3::new(0.0, -0.5, 0.0), -DVec3::Y)
        .unwrap();
    let (_, bottom_counts) = mesh.label_sides_with(&bottom, Some(2), None).unwrap();
    assert!(bottom_counts.left_vertices > 10);
    for v in mesh.vertices() {
        let (i, p) = (mesh.vertex_index(v), mesh.position(v));
        let l = *mesh.attribute(labels, v).unwrap();
        if p.y > 0.6 {
            assert_eq!(l, 1, "{p}: the top cap keeps its label");
        } else if p.y < -0.6 {
            assert_eq!(l, 2, "{p}");
        } else if p.y.abs() < 0.4 && i < generators::icosphere(3).n_vertices() {
            assert_eq!(l, 0, "{p}: the band is untouched");
        }
        // The second cut wrote only its own side and loop.
        if p.y > 0.0 {
            assert_eq!(l, after_top[i]);
        }
    }
    assert_separated(&mesh, labels);
    // Both parts keep their labels at every level of a hierarchy built now, and come
    // back exactly.
    let fine: Vec<Label> = mesh.attribute_values(labels).unwrap().to_vec();
    let mut h = Hierarchy::build(mesh, &HierarchyOptions::rounds().with_max_levels(3)).unwrap();
    // The labels were defined at the input level.
    h.refine_to(0).unwrap();
    h.attach_labels(labels).unwrap();
    for level in [3, 1, 2, 0] {
        h.go_to_level(level).unwrap();
        assert_eq!(h.mesh().attribute_values(labels).unwrap(), &fine[..]);
    }
    assert_separated(h.mesh(), labels);
    // Defined at a coarse level, two parts reach the fine mesh separated.
    h.go_to_level(2).unwrap();
    let mesh = h.mesh_mut();
    for v in mesh.vertices().collect::<Vec<_>>() {
        *mesh.attribute_mut(labels, v).unwrap() = 0;
    }
    let top = mesh
        .frontier_from_plane(DVec3::new(0.0, 0.4, 0.0), DVec3::Y)
        .unwrap();
    mesh.label_sides_with(&top, Some(1), None).unwrap();
    let bottom = mesh
        .frontier_from_plane(DVec3::new(0.0, -0.4, 0.0), -DVec3::Y)
        .unwrap();
    mesh.label_sides_with(&bottom, Some(2), None).unwrap();
    h.labels_defined_here();
    h.go_to_level(0).unwrap();
    let mesh = h.mesh();
    assert_separated(mesh, labels);
    let count = |l: Label| mesh.vertices_labelled(labels, l).unwrap().len();
    assert!(
        count(1) > 50 && count(2) > 50 && count(0) > 50,
        "{} {} {}",
        count(0),
        count(1),
        count(2)
    );
}

#[test]
fn label_sides_with_refuses_bad_labels_and_changes_nothing() {
    let mut mesh = generators::icosphere(2);
    let frontier = mesh.frontier_from_plane(DVec3::ZERO, DVec3::Z).unwrap();
    for (left, right) in [
        (None, None),
        (Some(FRONTIER), None),
        (None, Some(FRONTIER)),
        (Some(3), Some(3)),
    ] {
        assert!(matches!(
            mesh.label_sides_with(&frontier, left, right),
            Err(Error::InvalidArgument(_))
        ));
    }
    assert!(mesh
        .find_attribute::<VertexId, Label>(LABEL_ATTRIBUTE)
        .is_none());
    // Writing only the right side leaves the left side's labels alone.
    let labels = mesh.label_attribute().unwrap();
    for v in mesh.vertices().collect::<Vec<_>>() {
        *mesh.attribute_mut(labels, v).unwrap() = 7;
    }
    mesh.label_sides_with(&frontier, None, Some(4)).unwrap();
    for v in mesh.vertices() {
        let (z, l) = (mesh.position(v).z, *mesh.attribute(labels, v).unwrap());
        match l {
            7 => assert!(z > -0.1),
            4 => assert!(z < 0.1),
            FRONTIER => {}
            other => panic!("label {other}"),
        }
    }
}
