//! Kernel behaviour seen from outside: navigation identities, counter-clockwise
//! circulators, boundary loops, attributes that follow new elements, shortest edge paths,
//! closed loops and face regions, components, generators.

use glam::DVec3;
use halfedge::{generators, AddFaceError, Mesh, VertexId};

/// A hexagon fan: vertex 0 at the centre, vertices 1..=6 on the unit circle (counter-
/// clockwise), six faces facing +z.
fn hexagon_fan() -> Mesh {
    let mut positions = vec![DVec3::ZERO];
    for k in 0..6 {
        let a = k as f64 * std::f64::consts::TAU / 6.0;
        positions.push(DVec3::new(a.cos(), a.sin(), 0.0));
    }
    let triangles: Vec<[u32; 3]> = (0..6).map(|k| [0, 1 + k, 1 + (k + 1) % 6]).collect();
    let (mesh, _) = Mesh::from_triangles(&positions, &triangles).unwrap();
    mesh.check().unwrap();
    mesh
}

fn index_of(mesh: &Mesh, vs: impl Iterator<Item = VertexId>) -> Vec<usize> {
    vs.map(|v| mesh.vertex_index(v)).collect()
}

/// True when `b` is a rotation of `a`.
fn is_rotation(a: &[usize], b: &[usize]) -> bool {
    a.len() == b.len() && (0..a.len()).any(|s| (0..a.len()).all(|i| a[(i + s) % a.len()] == b[i]))
}

#[test]
fn halfedge_identities() {
    for mesh in [
        hexagon_fan(),
        generators::icosphere(2),
        generators::grid(4, 3, 1.0, 1.0),
    ] {
        for h in mesh.halfedges() {
            let o = mesh.opposite(h);
            assert_ne!(o, h);
            assert_eq!(mesh.opposite(o), h);
            assert_eq!(mesh.prev(mesh.next(h)), h);
            assert_eq!(mesh.next(mesh.prev(h)), h);
            assert_eq!(mesh.from_vertex(h), mesh.to_vertex(o));
            assert_eq!(mesh.from_vertex(mesh.next(h)), mesh.to_vertex(h));
            assert_eq!(mesh.cw_rotated(mesh.ccw_rotated(h)), h);
            assert_eq!(mesh.from_vertex(mesh.ccw_rotated(h)), mesh.from_vertex(h));
            if let Some(f) = mesh.face(h) {
                assert_eq!(mesh.face(mesh.next(h)), Some(f));
                assert_eq!(mesh.next(mesh.next(mesh.next(h))), h, "triangles");
            }
            assert_eq!(
                mesh.find_halfedge(mesh.from_vertex(h), mesh.to_vertex(h)),
                Some(h)
            );
        }
        for f in mesh.faces() {
            let t = mesh.triangle(f);
            assert_eq!(t[0], mesh.to_vertex(mesh.face_halfedge(f)));
            assert_eq!(mesh.face_vertices(f).collect::<Vec<_>>(), t.to_vec());
            assert_eq!(mesh.face_halfedges(f).count(), 3);
        }
    }
}

#[test]
fn one_ring_of_the_fan_centre() {
    let mesh = hexagon_fan();
    let centre = mesh.vertex_at(0).unwrap();
    assert_eq!(mesh.valence(centre), 6);
    assert!(!mesh.is_boundary_vertex(centre));
    // Counter-clockwise seen from +z: the ring 1, 2, …, 6 in order (from some start).
    let ring = index_of(&mesh, mesh.adjacent_vertices(centre));
    assert!(is_rotation(&[1, 2, 3, 4, 5, 6], &ring), "{ring:?}");
    assert_eq!(mesh.adjacent_faces(centre).count(), 6);
    // The face left of an outgoing halfedge lies between it and the next one
    // counter-clockwise.
    let out: Vec<_> = mesh.outgoing_halfedges(centre).collect();
    for (k, &h) in out.iter().enumerate() {
        let next = out[(k + 1) % 6];
        assert_eq!(mesh.ccw_rotated(h), next);
        let t = mesh.triangle(mesh.face(h).unwrap());
        assert!(t.contains(&centre) && t.contains(&mesh.to_vertex(h)));
        assert!(t.contains(&mesh.to_vertex(next)));
    }
    assert_eq!(
        index_of(
            &mesh,
            mesh.incoming_halfedges(centre).map(|h| mesh.from_vertex(h))
        ),
        ring
    );
}

#[test]
fn boundary_vertex_circulation_starts_at_the_boundary() {
    let mesh = hexagon_fan();
    for i in 1..=6 {
        let v = mesh.vertex_at(i).unwrap();
        assert!(mesh.is_boundary_vertex(v));
        assert_eq!(mesh.valence(v), 3);
        let out: Vec<_> = mesh.outgoing_halfedges(v).collect();
        assert!(
            mesh.is_boundary_halfedge(out[0]),
            "first outgoing halfedge has no face"
        );
        assert!(out[1..].iter().all(|&h| mesh.face(h).is_some()));
        // The boundary halfedge points to the previous ring vertex (the boundary loop
        // runs clockwise); turning counter-clockwise from it crosses the gap to the next
        // ring vertex, then the centre.
        let ring = index_of(&mesh, mesh.adjacent_vertices(v));
        assert_eq!(ring, vec![(i + 4) % 6 + 1, i % 6 + 1, 0], "vertex {i}");
        assert_eq!(mesh.adjacent_faces(v).count(), 2);
    }
}

#[test]
fn circulators_turn_counter_clockwise_on_a_sphere() {
    let mesh = generators::icosphere(2);
    for v in mesh.vertices() {
        let p = mesh.position(v);
        let ring: Vec<DVec3> = mesh
            .adjacent_vertices(v)
            .map(|w| mesh.position(w))
            .collect();
        for k in 0..ring.len() {
            let turn = (ring[k] - p).cross(ring[(k + 1) % ring.len()] - p);
            assert!(turn.dot(p) > 0.0, "one-ring of {v} turns clockwise");
        }
        let faces: Vec<_> = mesh.adjacent_faces(v).collect();
        assert_eq!(faces.len(), mesh.valence(v));
        for f in faces {
            assert!(mesh.face_normal(f).dot(p) > 0.0, "faces face outwards");
        }
    }
}

#[test]
fn boundary_loop_of_a_grid() {
    let (nx, ny) = (5, 3);
    let mesh = generators::grid(nx, ny, 5.0, 3.0);
    let loops = mesh.boundary_loops();
    assert_eq!(loops.len(), 1);
    let boundary = &loops[0];
    assert_eq!(boundary.len(), 2 * (nx + ny));
    for (k, &h) in boundary.iter().enumerate() {
        assert!(mesh.is_boundary_halfedge(h));
        assert_eq!(mesh.next(h), boundary[(k + 1) % boundary.len()]);
        assert!(mesh.is_boundary_vertex(mesh.to_vertex(h)));
    }
    // Faces are counter-clockwise seen from +z, so the boundary loop turns clockwise:
    // its signed area is negative.
    let area: f64 = boundary
        .iter()
        .map(|&h| {
            let (a, b) = (
                mesh.position(mesh.from_vertex(h)),
                mesh.position(mesh.to_vertex(h)),
            );
            0.5 * (a.x * b.y - b.x * a.y)
        })
        .sum();
    assert!((area + 15.0).abs() < 1e-12, "{area}");
    let report = mesh.topology_report();
    assert_eq!(report.boundary_vertices, 2 * (nx + ny));
    assert_eq!(
        (report.boundary_loops, report.components, report.euler),
        (1, 1, 1)
    );
}

#[test]
fn attributes_follow_new_elements() {
    let mut mesh = hexagon_fan();
    let label = mesh.add_vertex_attribute("label", 7u32).unwrap();
    let weight = mesh.add_face_attribute("weight", 0.5f64).unwrap();
    let seen = mesh.add_halfedge_attribute("seen", false).unwrap();
    assert!(
        mesh.add_vertex_attribute("label", 0u8).is_err(),
        "duplicate name"
    );
    let centre = mesh.vertex_at(0).unwrap();
    *mesh.attribute_mut(label, centre).unwrap() = 1;

    // A new vertex and a new face on the boundary edge 1-2 (outside the fan).
    let v = mesh.add_vertex(DVec3::new(1.2, 1.2, 0.0));
    assert_eq!(
        mesh.attribute_values(label).unwrap().len(),
        mesh.vertex_slots()
    );
    assert_eq!(
        *mesh.attribute(label, v).unwrap(),
        7,
        "new vertices take the default"
    );
    assert_eq!(
        *mesh.attribute(label, centre).unwrap(),
        1,
        "old values are kept"
    );
    let (a, b) = (mesh.vertex_at(1).unwrap(), mesh.vertex_at(2).unwrap());
    let f = mesh.add_triangle(b, a, v).unwrap();
    mesh.check().unwrap();
    assert_eq!(
        mesh.attribute_values(weight).unwrap().len(),
        mesh.face_slots()
    );
    assert_eq!(*mesh.attribute(weight, f).unwrap(), 0.5);
    assert_eq!(
        mesh.attribute_values(seen).unwrap().len(),
        mesh.halfedge_slots()
    );
    assert_eq!(
        mesh.find_attribute::<VertexId, u32>("label").map(|_| ()),
        Some(())
    );
    assert!(
        mesh.find_attribute::<VertexId, u8>("label").is_none(),
        "typed lookup"
    );
}

#[test]
fn refused_faces_change_nothing() {
    let mut square = generators::grid(1, 1, 1.0, 1.0);
    let before = square.topology_report();
    let f = square.faces().next().unwrap();
    let [a, b, c] = square.triangle(f);
    // The same triangle again: its edges already have faces on that side.
    assert!(matches!(
        square.add_triangle(a, b, c),
        Err(AddFaceError::ComplexEdge(..))
    ));
    square.check().unwrap();
    assert_eq!(square.topology_report(), before);

    let mut mesh = hexagon_fan();
    let before = mesh.topology_report();
    let v: Vec<VertexId> = (0..7).map(|i| mesh.vertex_at(i).unwrap()).collect();
    // A triangle through the interior centre vertex.
    let w = mesh.add_vertex(DVec3::new(0.0, 0.0, 1.0));
    let x = mesh.add_vertex(DVec3::new(0.0, 1.0, 1.0));
    assert!(matches!(
        mesh.add_triangle(v[0], w, x),
        Err(AddFaceError::ComplexVertex(c)) if c == v[0]
    ));
    mesh.check().unwrap();
    let after = mesh.topology_report();
    assert_eq!((after.faces, after.edges), (before.faces, before.edges));
    assert_eq!(after.vertices, before.vertices + 2);
}

#[test]
fn shortest_edge_path_on_a_grid() {
    let n = 4;
    let mesh = generators::grid(n, n, 4.0, 4.0);
    let corner = |i: usize, j: usize| mesh.vertex_at(i + j * (n + 1)).unwrap();
    let (from, to) = (corner(0, 0), corner(n, n));
    let path = mesh.shortest_edge_path(from, to, None).unwrap();
    // The grid's diagonals run from (i, j) to (i+1, j+1): the path is the diagonal.
    assert_eq!(path.len(), n);
    assert_eq!(mesh.from_vertex(path[0]), from);
    assert_eq!(mesh.to_vertex(*path.last().unwrap()), to);
    for w in path.windows(2) {
        assert_eq!(mesh.to_vertex(w[0]), mesh.from_vertex(w[1]));
    }
    let length: f64 = path.iter().map(|&h| mesh.edge_length(h)).sum();
    assert!((length - 4.0 * 2f64.sqrt()).abs() < 1e-12);
    assert_eq!(mesh.shortest_edge_path(from, from, None), Some(vec![]));
    // Forbidding every diagonal leaves only axis-aligned paths of length 8.
    let mut forbidden = vec![false; mesh.halfedge_slots()];
    for h in mesh.halfedges() {
        let d = mesh.edge_vector(h);
        forbidden[mesh.halfedge_index(h)] = d.x != 0.0 && d.y != 0.0;
    }
    let path = mesh.shortest_edge_path(from, to, Some(&forbidden)).unwrap();
    assert_eq!(path.len(), 2 * n);
    // Unreachable: an isolated vertex.
    let mut mesh = mesh;
    let lonely = mesh.add_vertex(DVec3::splat(9.0));
    assert_eq!(mesh.shortest_edge_path(from, lonely, None), None);
}

#[test]
fn closed_loop_and_face_regions_on_a_grid() {
    let n = 8;
    let mesh = generators::grid(n, n, 8.0, 8.0);
    let at = |i: usize, j: usize| mesh.vertex_at(i + j * (n + 1)).unwrap();
    let picks = [at(2, 2), at(6, 2), at(6, 6), at(2, 6)];
    let cut = mesh.closed_loop_through(&picks).unwrap();
    // Straight grid lines are the unique shortest paths: a 4 × 4 square of 16 edges.
    assert_eq!(cut.len(), 16);
    for (k, &h) in cut.iter().enumerate() {
        assert_eq!(
            mesh.to_vertex(h),
            mesh.from_vertex(cut[(k + 1) % cut.len()])
        );
        assert!((mesh.edge_length(h) - 1.0).abs() < 1e-12);
    }
    let (region, count) = mesh.face_regions(&cut);
    assert_eq!(count, 2);
    let inside = |f| {
        let c = mesh.face_centroid(f);
        (2.0..6.0).contains(&c.x) && (2.0..6.0).contains(&c.y)
    };
    let inner: Vec<u32> = mesh
        .faces()
        .filter(|&f| inside(f))
        .map(|f| region[mesh.face_index(f)])
        .collect();
    assert_eq!(inner.len(), 32);
    assert!(inner.iter().all(|&r| r == inner[0]));
    assert!(mesh
        .faces()
        .filter(|&f| !inside(f))
        .all(|f| region[mesh.face_index(f)] != inner[0]));
    // Too few picks is an error, not a panic.
    assert!(mesh.closed_loop_through(&picks[..1]).is_err());
    // No cut: one region.
    assert_eq!(mesh.face_regions(&[]).1, 1);
}

#[test]
fn components_and_isolated_vertices() {
    let a = generators::grid(2, 2, 1.0, 1.0);
    let mut positions: Vec<DVec3> = a.positions().to_vec();
    let mut triangles: Vec<[u32; 3]> = a
        .faces()
        .map(|f| a.triangle(f).map(|v| a.vertex_index(v) as u32))
        .collect();
    let offset = positions.len() as u32;
    positions.extend(a.positions().iter().map(|p| *p + DVec3::X * 5.0));
    triangles.extend(triangles.clone().iter().map(|t| t.map(|i| i + offset)));
    positions.push(DVec3::splat(-3.0)); // isolated
    let (mesh, report) = Mesh::from_triangles(&positions, &triangles).unwrap();
    mesh.check().unwrap();
    assert_eq!(report.unreferenced_vertices, 1);
    let (component, count) = mesh.connected_components();
    assert_eq!(count, 3);
    assert_eq!(component[0], component[8]);
    assert_ne!(component[0], component[9]);
    let t = mesh.topology_report();
    assert_eq!(t.components, 3);
    assert_eq!(t.valence_histogram.get(&0), Some(&1));
    assert_eq!(
        t.boundary_vertices,
        2 * 8 + 1,
        "isolated vertices are boundary vertices"
    );
    assert_eq!(t.euler, 3);
}

#[test]
fn generators_have_the_documented_counts() {
    for level in 0..4 {
        let m = generators::icosphere(level);
        m.check().unwrap();
        let f = 20 * 4usize.pow(level as u32);
        assert_eq!(
            (m.n_vertices(), m.n_faces(), m.n_edges()),
            (f / 2 + 2, f, 3 * f / 2)
        );
        let h = m.valence_histogram();
        assert_eq!(h.get(&5), Some(&12));
    }
    let g = generators::grid(3, 2, 3.0, 2.0);
    let s = generators::subdivide(&g);
    s.check().unwrap();
    assert_eq!(s.n_vertices(), g.n_vertices() + g.n_edges());
    assert_eq!(s.n_faces(), 4 * g.n_faces());
    assert!((s.surface_area() - g.surface_area()).abs() < 1e-12);
    assert_eq!(
        &s.positions()[..g.n_vertices()],
        g.positions(),
        "old vertices first"
    );
}

/// Garbage collection frees the tombstones of collapses; new elements reuse their
/// slots under new versions, so the removed handles stay stale and the live ones keep
/// their handles and indices.
#[test]
fn garbage_collection_reuses_slots_under_new_versions() {
    let mut mesh = generators::icosphere(2);
    let live_before: Vec<VertexId> = mesh.vertices().collect();
    let mut removed = Vec::new();
    for _ in 0..5 {
        let h = mesh
            .halfedges()
            .find(|&h| mesh.is_collapse_ok(h).is_ok())
            .unwrap();
        removed.push(mesh.collapse(h).unwrap().v0);
    }
    mesh.check().unwrap();
    let survivors: Vec<(VertexId, usize, DVec3)> = mesh
        .vertices()
        .map(|v| (v, mesh.vertex_index(v), mesh.position(v)))
        .collect();
    let slots = mesh.vertex_slots();
    mesh.garbage_collection();
    mesh.check().unwrap();
    for &v in &removed {
        assert!(!mesh.is_valid_vertex(v) && !mesh.is_deleted_vertex(v));
    }
    for &(v, i, p) in &survivors {
        assert!(mesh.is_valid_vertex(v));
        assert_eq!((mesh.vertex_index(v), mesh.position(v)), (i, p));
    }
    // Splitting edges creates vertices, edges and faces in the freed slots.
    let mut created = Vec::new();
    for _ in 0..5 {
        let h = mesh.edges().next().unwrap();
        let p = 0.5 * (mesh.position(mesh.from_vertex(h)) + mesh.position(mesh.to_vertex(h)));
        created.push(mesh.split_edge(h, p).unwrap());
        mesh.check().unwrap();
    }
    assert_eq!(mesh.vertex_slots(), slots, "freed slots are reused");
    let mut removed_slots = index_of(&mesh, removed.iter().copied());
    let mut created_slots = index_of(&mesh, created.iter().copied());
    removed_slots.sort();
    created_slots.sort();
    assert_eq!(removed_slots, created_slots);
    for &old in &removed {
        // Same slot, new version: the old handle does not alias the new vertex.
        let new = mesh.vertex_at(mesh.vertex_index(old)).unwrap();
        assert_ne!(old, new);
        assert!(!mesh.is_valid_vertex(old) && mesh.is_valid_vertex(new));
    }
    // Navigation after reuse hands out the new versions.
    for &v in &created {
        for w in mesh.adjacent_vertices(v) {
            assert!(mesh.is_valid_vertex(w));
            assert!(mesh.adjacent_vertices(w).any(|u| u == v));
        }
    }
    assert_eq!(mesh.n_vertices(), live_before.len());
}

#[test]
fn a_removed_attribute_handle_never_reads_the_attribute_added_in_its_place() {
    // The new attribute takes the freed column; the old handle, of the same type, is
    // refused instead of reading the new values.
    let mut mesh = halfedge::generators::icosphere(1);
    let v = mesh.vertices().next().unwrap();
    let old = mesh.add_vertex_attribute("weight", 1.0f64).unwrap();
    mesh.remove_attribute(old).unwrap();
    let new = mesh.add_vertex_attribute("other", 7.0f64).unwrap();
    assert!(!mesh.has_attribute(old));
    assert!(mesh.has_attribute(new));
    assert!(mesh.attribute_values(old).is_err());
    assert_eq!(mesh.attribute_values(new).unwrap()[0], 7.0);
    assert_eq!(*mesh.attribute(new, v).unwrap(), 7.0);
    assert!(matches!(
        mesh.attribute(old, v),
        Err(halfedge::Error::Stale(_))
    ));
    assert!(matches!(
        mesh.attribute_mut(old, v),
        Err(halfedge::Error::Stale(_))
    ));
    // Removing with the stale handle is refused and leaves the new attribute alone.
    assert!(matches!(
        mesh.remove_attribute(old),
        Err(halfedge::Error::Stale(_))
    ));
    assert!(mesh.has_attribute(new));
    // A handle found by name is the live attribute's.
    assert_eq!(
        mesh.find_attribute::<halfedge::VertexId, f64>("other"),
        Some(new)
    );
}

/// Every accessor that takes an element handle refuses a stale one, in release builds
/// as in debug ones: after garbage collection and the reuse of the freed slots, an old
/// handle panics with "stale … handle" instead of reading the element now in its slot.
#[test]
fn stale_element_handles_never_read_the_element_now_in_their_slot() {
    use std::panic::{catch_unwind, AssertUnwindSafe};
    let mut mesh = generators::icosphere(2);
    let h = mesh
        .halfedges()
        .find(|&h| mesh.is_collapse_ok(h).is_ok())
        .unwrap();
    let record = mesh.collapse(h).unwrap();
    let (old_v, old_h, old_f) = (record.v0, h, record.fl.unwrap());
    mesh.garbage_collection();
    // Refill the freed slots so that each old handle's slot holds a live element.
    for _ in 0..4 {
        let e = mesh.edges().next().unwrap();
        let p = 0.5 * (mesh.position(mesh.from_vertex(e)) + mesh.position(mesh.to_vertex(e)));
        mesh.split_edge(e, p).unwrap();
    }
    assert!(
        mesh.vertex_at(mesh.vertex_index(old_v)).is_some(),
        "vertex slot reused"
    );
    assert!(
        mesh.halfedge_at(mesh.halfedge_index(old_h)).is_some(),
        "halfedge slot reused"
    );
    assert!(
        mesh.face_at(mesh.face_index(old_f)).is_some(),
        "face slot reused"
    );
    let refused = |what: &str, read: &dyn Fn()| {
        let result = catch_unwind(AssertUnwindSafe(read));
        let message = result
            .err()
            .unwrap_or_else(|| panic!("{what} read through a stale handle"));
        let text = message
            .downcast_ref::<String>()
            .cloned()
            .unwrap_or_default();
        assert!(text.contains("stale"), "{what}: {text}");
    };
    let m = &mesh;
    refused("position", &|| {
        m.position(old_v);
    });
    refused("vertex_halfedge", &|| {
        m.vertex_halfedge(old_v);
    });
    refused("is_boundary_vertex", &|| {
        m.is_boundary_vertex(old_v);
    });
    refused("is_isolated", &|| {
        m.is_isolated(old_v);
    });
    refused("adjacent_vertices", &|| {
        m.adjacent_vertices(old_v).count();
    });
    refused("to_vertex", &|| {
        m.to_vertex(old_h);
    });
    refused("from_vertex", &|| {
        m.from_vertex(old_h);
    });
    refused("next", &|| {
        m.next(old_h);
    });
    refused("prev", &|| {
        m.prev(old_h);
    });
    refused("opposite", &|| {
        m.opposite(old_h);
    });
    refused("face", &|| {
        m.face(old_h);
    });
    refused("face_halfedge", &|| {
        m.face_halfedge(old_f);
    });
    refused("triangle", &|| {
        m.triangle(old_f);
    });
    refused("face_vertices", &|| {
        m.face_vertices(old_f).count();
    });
    refused("set_position", &|| {
        let mut copy = m.clone();
        copy.set_position(old_v, DVec3::ZERO);
    });
}

#[test]
fn an_attribute_handle_of_another_mesh_is_refused_as_stale() {
    // Two meshes with attributes in the same column and of the same type: a handle of
    // one never reads or writes the other's values, whatever the column.
    let mut a = halfedge::generators::icosphere(1);
    let mut b = halfedge::generators::icosphere(1);
    let of_a = a.add_vertex_attribute("w", 1.0f64).unwrap();
    let of_b = b.add_vertex_attribute("w", 2.0f64).unwrap();
    let v = a.vertices().next().unwrap();
    for result in [a.attribute(of_b, v).copied(), b.attribute(of_a, v).copied()] {
        let e = result.unwrap_err();
        assert!(matches!(e, halfedge::Error::Stale(_)), "{e}");
        assert!(e.to_string().contains("attribute handle"), "{e}");
    }
    assert!(a.attribute_values_mut(of_b).is_err());
    assert!(a.remove_attribute(of_b).is_err());
    assert_eq!(*a.attribute(of_a, v).unwrap(), 1.0);
    assert!(!a.has_attribute(of_b));
    // A clone has the attributes of its original: their handles work on it, and the
    // clone's own new attributes are refused by the original.
    let mut clone = a.clone();
    assert_eq!(*clone.attribute(of_a, v).unwrap(), 1.0);
    let of_clone = clone.add_vertex_attribute("x", 3u8).unwrap();
    let mut dup = a.clone();
    let of_dup = dup.add_vertex_attribute("x", 4u8).unwrap();
    assert!(a.attribute(of_clone, v).is_err());
    assert!(
        clone.attribute(of_dup, v).is_err(),
        "same column and type, other mesh"
    );
    // An element handle that is not of the mesh is an invalid handle, not a panic.
    let w = halfedge::generators::icosphere(3)
        .vertices()
        .last()
        .unwrap();
    assert!(matches!(
        a.attribute(of_a, w),
        Err(halfedge::Error::InvalidHandle(_))
    ));
}
