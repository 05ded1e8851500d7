//! Sub-mesh labels (seed paper, section 4.1): frontiers from picks, collars and plane
//! sections; the two sides labelled; errors for loops that do not separate; the Fig. 4
//! rule through vertex splits; labels defined at any level hold at every other.

mod common;

use std::collections::HashSet;

use common::load;
use glam::DVec3;
use halfedge::labels::{classify_split, LABEL_ATTRIBUTE};
use halfedge::{
    generators, Attribute, Error, FaceId, Frontier, Hierarchy, HierarchyOptions, Label, Mesh,
    VertexId, FRONTIER,
};

/// The plane through the bunny's left ear (y up) and a point on it near that ear.
fn ear_plane() -> (DVec3, DVec3) {
    (DVec3::new(-0.066, 0.16, -0.017), DVec3::Y)
}

/// No edge joins two different sub-meshes: the frontier separates them.
fn assert_separated(mesh: &Mesh, labels: Attribute<VertexId, Label>) {
    for h in mesh.edges() {
        let a = *mesh.attribute(labels, mesh.from_vertex(h));
        let b = *mesh.attribute(labels, mesh.to_vertex(h));
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
    mesh.vertices_labelled(labels, label).into_iter().collect()
}

/// The smaller of the two labelled sides (1 or 2).
fn smaller_side(mesh: &Mesh, labels: Attribute<VertexId, Label>) -> Label {
    if side(mesh, labels, 1).len() < side(mesh, labels, 2).len() {
        1
    } else {
        2
    }
}

/// A torus of `n × m` quads split in two triangles, wrapped in both directions.
fn torus(n: usize, m: usize) -> Mesh {
    let (big, small) = (1.0, 0.35);
    let mut positions = Vec::new();
    for j in 0..m {
        for i in 0..n {
            let (u, v) = (
                i as f64 / n as f64 * std::f64::consts::TAU,
                j as f64 / m as f64 * std::f64::consts::TAU,
            );
            let r = big + small * v.cos();
            positions.push(DVec3::new(r * u.cos(), r * u.sin(), small * v.sin()));
        }
    }
    let id = |i: usize, j: usize| ((i % n) + (j % m) * n) as u32;
    let mut triangles = Vec::new();
    for j in 0..m {
        for i in 0..n {
            triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    Mesh::from_triangles(&positions, &triangles).unwrap().0
}

#[test]
fn plane_section_cuts_off_the_bunny_ear() {
    let mut mesh = load("stanford-bunny.obj");
    let (point, normal) = ear_plane();
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
    assert!(ear_vertices.len() > 300, "{counts:?}");
    // The ear is above the plane and near the picked point.
    for &v in &ear_vertices {
        let p = mesh.position(v);
        assert!(
            (p - point).dot(normal) > -max_edge,
            "ear vertex {v} below the plane"
        );
        assert!(
            (p.x - point.x).abs() < 0.04,
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
        let label = mesh.face_label(labels, f);
        let vertex_labels: Vec<Label> = mesh
            .face_vertices(f)
            .map(|v| *mesh.attribute(labels, v))
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
    let mut mesh = load("stanford-bunny.obj");
    let (point, normal) = ear_plane();
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
    let mut mesh = load("stanford-bunny.obj");
    let (point, normal) = ear_plane();
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
    let mut t = torus(16, 8);
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
        *mesh.attribute_mut(labels, v) = match column(mesh.position(v)) {
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
        let before = *mesh.attribute(labels, v0);
        let record = mesh.collapse(h).unwrap();
        mesh.vertex_split(&record).unwrap();
        *mesh.attribute_mut(labels, v0) = 12345;
        classify_split(&mut mesh, labels, v0);
        assert_eq!(*mesh.attribute(labels, v0), expected);
        assert_eq!(before, expected);
    }
}

#[test]
fn labels_defined_at_a_coarse_level_propagate_to_the_fine_mesh() {
    let mut h = Hierarchy::build(
        load("stanford-bunny.obj"),
        &HierarchyOptions::rounds().with_max_levels(4),
    )
    .unwrap();
    let coarse_edge = h.mesh().mean_edge_length();
    let (point, normal) = ear_plane();
    let frontier = h.mesh().frontier_from_plane(point, normal).unwrap();
    let (labels, _) = h.mesh_mut().label_sides(&frontier, 1, 2).unwrap();
    h.attach_labels(labels);
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
        let l = *mesh.attribute(labels, v);
        assert!(l == 1 || l == 2 || l == FRONTIER);
        if l == FRONTIER && !mesh.is_isolated(v) {
            frontier_vertices += 1;
            assert!(
                mesh.adjacent_vertices(v)
                    .any(|w| *mesh.attribute(labels, w) != FRONTIER),
                "frontier vertex {v} is surrounded by frontier vertices"
            );
        }
    }
    assert!(frontier_vertices > 0);
    // Walking again gives the same labels.
    let first: Vec<Label> = mesh.attribute_values(labels).to_vec();
    h.coarsen_to(2).unwrap();
    h.refine_to(0).unwrap();
    assert_eq!(h.mesh().attribute_values(labels), &first[..]);
}

#[test]
fn labels_defined_at_the_fine_level_hold_at_every_level() {
    let mut h = Hierarchy::build(
        load("stanford-bunny.obj"),
        &HierarchyOptions::qem().with_target_faces(2000),
    )
    .unwrap();
    h.refine_to(0).unwrap();
    let (point, normal) = ear_plane();
    let frontier = h.mesh().frontier_from_plane(point, normal).unwrap();
    let (labels, _) = h.mesh_mut().label_sides(&frontier, 1, 2).unwrap();
    h.attach_labels(labels);
    let fine: Vec<Label> = h.mesh().attribute_values(labels).to_vec();
    for level in [2, h.coarsest_level(), 1] {
        h.go_to_level(level).unwrap();
        let mesh = h.mesh();
        // Live vertices keep their labels and collapsed ones keep theirs on the tombstone.
        assert_eq!(mesh.attribute_values(labels), &fine[..]);
        for v in mesh.vertices() {
            assert_eq!(*mesh.attribute(labels, v), fine[mesh.vertex_index(v)]);
        }
    }
    h.refine_to(0).unwrap();
    assert_eq!(h.mesh().attribute_values(labels), &fine[..]);
}
