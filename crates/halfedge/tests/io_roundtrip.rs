//! Every format the kernel writes reads back to the same mesh: positions bit for bit
//! (all formats write full `f64` precision), the same faces in the same order, the same
//! topology; on real meshes (with isolated vertices, boundaries, non-manifold input whose
//! duplicated vertices are written as ordinary vertices) and on generated ones.

use std::path::Path;

use glam::DVec3;
use halfedge::io::{self, PlyFormat};
use halfedge::{generators, Mesh};
use testkit::check::{position_bits as bits, triangles};
use testkit::{data_dir, shared_meshes, temp_dir};

/// Writes `mesh` in every format into `dir` and checks that each reads back equal.
fn round_trip(name: &str, mesh: &Mesh, dir: &Path) {
    mesh.check().unwrap();
    // A freshly built mesh has no removed vertices: file numbers are vertex indices.
    let numbers = io::file_vertex_indices(mesh);
    assert!(numbers.iter().enumerate().all(|(i, &k)| k as usize == i));
    let stem = dir.join(name.replace('.', "_"));
    let files = [
        (stem.with_extension("obj"), None),
        (stem.with_extension("ascii.ply"), Some(PlyFormat::Ascii)),
        (
            stem.with_extension("le.ply"),
            Some(PlyFormat::BinaryLittleEndian),
        ),
        (
            stem.with_extension("be.ply"),
            Some(PlyFormat::BinaryBigEndian),
        ),
    ];
    for (file, format) in files {
        match format {
            None => io::write_obj(&file, mesh).unwrap(),
            Some(format) => io::write_ply(&file, mesh, format).unwrap(),
        }
        let (back, report) = io::read(&file).unwrap_or_else(|e| panic!("{e}"));
        let what = file.file_name().unwrap().to_string_lossy().into_owned();
        back.check().unwrap();
        assert_eq!(back.n_vertices(), mesh.n_vertices(), "{what}");
        assert_eq!(bits(&back), bits(mesh), "{what}: positions differ");
        assert_eq!(triangles(&back), triangles(mesh), "{what}: faces differ");
        assert_eq!(back.topology_report(), mesh.topology_report(), "{what}");
        assert_eq!(report.duplicated_vertices, 0, "{what}");
        assert_eq!(report.dropped_faces, 0, "{what}");
    }
    // `io::write` picks the format by extension (binary PLY for .ply).
    let file = stem.with_extension("PLY");
    io::write(&file, mesh).unwrap();
    assert_eq!(bits(&io::read(&file).unwrap().0), bits(mesh));
}

fn shared_round_trip(name: &str) {
    let dir = temp_dir(&format!("roundtrip-{name}"));
    let (mesh, _) = io::read(shared_meshes().join(name)).unwrap();
    round_trip(name, &mesh, &dir);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn horse_round_trips() {
    shared_round_trip("horse.ply");
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn bunny_round_trips() {
    // Isolated vertices and holes.
    shared_round_trip("stanford-bunny.obj");
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn suzanne_teapot_cow_round_trip() {
    // Quads, a non-manifold edge, many boundary loops, duplicated vertices.
    for name in ["suzanne.obj", "teapot.obj", "cow.obj"] {
        shared_round_trip(name);
    }
}

#[test]
fn data_meshes_round_trip() {
    let dir = temp_dir("roundtrip-data");
    // Open, tristrips, quads with a hole, closed, several components, genus 1, holes,
    // dirty input (its duplicated vertices are written as ordinary ones).
    for name in [
        "patch.ply",
        "strips.ply",
        "quads_hole.obj",
        "blob.obj",
        "creature.obj",
        "torus.obj",
        "cup.obj",
        "dirty.obj",
    ] {
        let (mesh, _) = io::read(data_dir().join(name)).unwrap();
        round_trip(name, &mesh, &dir);
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn generated_meshes_round_trip() {
    let dir = temp_dir("roundtrip-generated");
    let mut awkward = generators::grid(5, 4, 1.0, 1.0);
    // Coordinates that stress the number formatting: tiny, huge, negative zero, thirds.
    let values = [
        1e-300,
        -2.5e300,
        -0.0,
        1.0 / 3.0,
        f64::MIN_POSITIVE,
        123456789.125,
        -7e-9,
    ];
    for (i, p) in awkward.positions_mut().iter_mut().enumerate() {
        let v = values[i % values.len()];
        *p = DVec3::new(v, p.y + v, std::f64::consts::PI * i as f64);
    }
    let meshes = [
        ("icosphere", generators::icosphere(3)),
        (
            "subdivided",
            generators::subdivide(&generators::grid(3, 2, 2.0, 1.0)),
        ),
        ("awkward", awkward),
    ];
    for (name, mesh) in &meshes {
        round_trip(name, mesh, &dir);
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn duplicated_vertices_are_written_as_ordinary_vertices() {
    duplicated_written_as_ordinary(&data_dir().join("dirty.obj"), 6);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn duplicated_vertices_of_the_cow_are_written_as_ordinary_vertices() {
    duplicated_written_as_ordinary(&shared_meshes().join("cow.obj"), 12);
}

fn duplicated_written_as_ordinary(path: &Path, duplicated: usize) {
    let (mesh, report) = io::read(path).unwrap();
    assert_eq!(report.duplicated_vertices, duplicated);
    let mut bytes = Vec::new();
    io::write_obj_to(&mut bytes, &mesh).unwrap();
    let (back, again) = io::read_obj_from_bytes(&bytes, Path::new("written.obj")).unwrap();
    assert_eq!(again.duplicated_vertices, 0);
    assert_eq!(back.n_vertices(), mesh.n_vertices());
    // The copies come after the file's vertices, at the same positions as their originals.
    let n_file = mesh.n_vertices() - duplicated;
    for i in n_file..mesh.n_vertices() {
        let p = back.positions()[i];
        assert!(back.positions()[..n_file].contains(&p));
    }
}
