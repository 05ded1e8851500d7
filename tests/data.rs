//! The meshes in `data/` are the project's own: `make_data` writes them again byte for
//! byte, and each has the shape the default test tier relies on (closed, open, several
//! components, genus 1, quads, dirty input).

use std::process::Command;
use testkit::data_dir;

const FILES: [&str; 8] = [
    "blob.obj",
    "patch.ply",
    "strips.ply",
    "quads_hole.obj",
    "creature.obj",
    "torus.obj",
    "cup.obj",
    "dirty.obj",
];

#[test]
fn make_data_writes_the_data_folder_again() {
    let out = std::env::temp_dir().join(format!("multires-make-data-{}", std::process::id()));
    let status = Command::new(testkit::example_binary("make_data"))
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    for name in FILES {
        let made = std::fs::read(out.join(name)).unwrap();
        let shipped = std::fs::read(data_dir().join(name)).unwrap();
        assert!(
            made == shipped,
            "data/{name} differs from what make_data writes: run `cargo run --release --example make_data`"
        );
    }
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn each_data_mesh_has_the_shape_the_tests_rely_on() {
    // (file, components, boundary loops, Euler characteristic of the faces' surface)
    let read = |name: &str| halfedge::io::read(data_dir().join(name)).unwrap();
    for (name, components, loops, euler) in [
        ("blob.obj", 1, 0, 2),
        ("creature.obj", 3, 0, 6),
        ("torus.obj", 1, 0, 0),
        ("cup.obj", 1, 3, -1),
        ("patch.ply", 1, 1, 1),
    ] {
        let (mesh, build) = read(name);
        mesh.check().unwrap();
        let t = mesh.topology_report();
        assert_eq!(
            (t.components, t.boundary_loops, t.euler),
            (components, loops, euler),
            "{name}"
        );
        assert_eq!((build.duplicated_vertices, build.dropped_faces), (0, 0));
    }
    // Quads and a hole, an unreferenced vertex.
    let (quads, build) = read("quads_hole.obj");
    assert_eq!(build.unreferenced_vertices, 1);
    assert_eq!(quads.topology_report().boundary_loops, 2);
    // Dirty input: every kind of trouble is there, and the mesh is still valid.
    let (dirty, build) = read("dirty.obj");
    dirty.check().unwrap();
    assert!(build.duplicated_vertices > 0, "{build:?}");
    assert_eq!(build.dropped_faces, 1, "the face with a repeated vertex");
    assert!(build.unreferenced_vertices >= 2);
    let t = dirty.topology_report();
    assert!(t.non_manifold_vertices > 0, "the bow-tie");
    assert!(t.components > 1);
    let zero_area = dirty
        .faces()
        .filter(|&f| dirty.face_area(f) < 1e-12)
        .count();
    assert!(zero_area >= 1);
}
