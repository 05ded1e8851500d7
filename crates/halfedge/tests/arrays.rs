//! Plain arrays in and out (`Mesh::to_arrays` / `Mesh::from_arrays`): the writers'
//! numbering, round trips, and typed errors for bad arrays.

use halfedge::{generators, Error, Mesh};

#[test]
fn arrays_round_trip_and_number_vertices_as_the_writers_do() {
    let mut mesh = generators::torus(1.0, 0.3, 12, 8).unwrap();
    mesh.add_vertex(glam::DVec3::new(5.0, 5.0, 5.0)); // isolated: kept
    let e = mesh
        .halfedges()
        .find(|&h| mesh.is_collapse_ok(h).is_ok())
        .unwrap();
    mesh.collapse(e).unwrap();
    let (positions, triangles) = mesh.to_arrays();
    assert_eq!(
        (positions.len(), triangles.len()),
        (mesh.n_vertices(), mesh.n_faces())
    );
    let index = halfedge::io::file_vertex_indices(&mesh);
    for (k, v) in mesh.vertices().enumerate() {
        assert_eq!(index[mesh.vertex_index(v)] as usize, k);
        assert_eq!(positions[k], mesh.position(v).to_array());
    }
    for (f, t) in mesh.faces().zip(&triangles) {
        assert_eq!(mesh.triangle(f).map(|v| index[mesh.vertex_index(v)]), *t);
    }
    let (back, report) = Mesh::from_arrays(&positions, &triangles).unwrap();
    back.check().unwrap();
    assert_eq!(back.to_arrays(), (positions, triangles));
    assert_eq!(report.unreferenced_vertices, 1);
    assert_eq!(back.topology_report().euler, mesh.topology_report().euler);
}

#[test]
fn bad_arrays_are_typed_errors() {
    assert!(matches!(
        Mesh::from_arrays(&[], &[]),
        Err(Error::EmptyInput)
    ));
    let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, f64::NAN, 0.0]];
    assert!(matches!(
        Mesh::from_arrays(&p, &[[0, 1, 2]]),
        Err(Error::NonFiniteCoordinate { vertex: 2, .. })
    ));
    let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    assert!(matches!(
        Mesh::from_arrays(&p, &[[0, 1, 2], [2, 1, 7]]),
        Err(Error::IndexOutOfRange {
            face: 1,
            index: 7,
            vertex_count: 3
        })
    ));
    // A triangle with a repeated index is dropped and counted, not an error.
    let (mesh, report) = Mesh::from_arrays(&p, &[[0, 1, 2], [0, 0, 1]]).unwrap();
    assert_eq!((mesh.n_faces(), report.dropped_faces), (1, 1));
    let empty = Mesh::new();
    assert_eq!(empty.to_arrays(), (vec![], vec![]));
}
