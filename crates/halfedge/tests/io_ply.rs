//! What the PLY reader understands: every scalar type for coordinates, every integer
//! type for face lists, both index-list names, extra properties and elements, polygons,
//! tristrips, all three encodings, and the same result on the fast and the general route.

use std::path::Path;

use glam::DVec3;
use halfedge::io::{read_ply_from_bytes, write_ply_to, PlyFormat};
use halfedge::{BuildReport, Mesh};
use testkit::check::triangles;
use testkit::ply::{Enc, PlyBuilder};
use testkit::{data_dir, shared_meshes};

const ENCODINGS: [Enc; 3] = [Enc::Ascii, Enc::Le, Enc::Be];
const INTEGER_TYPES: [&str; 6] = ["char", "uchar", "short", "ushort", "int", "uint"];

fn read(bytes: &[u8]) -> (Mesh, BuildReport) {
    let (mesh, report) =
        read_ply_from_bytes(bytes, Path::new("test.ply")).unwrap_or_else(|e| panic!("{e}"));
    mesh.check().unwrap();
    (mesh, report)
}

/// A 3 × 2 grid of points (z = i + j) with two quads and one triangle fan of a pentagon,
/// written with the given coordinate type, count type and index type.
fn polygons(enc: Enc, coord: &str, count: &str, index: &str, list_name: &str) -> Vec<u8> {
    let mut b = PlyBuilder::new(enc)
        .element("vertex", 6)
        .property(coord, "x")
        .property(coord, "y")
        .property(coord, "z")
        .element("face", 2)
        .list_property(count, index, list_name);
    for j in 0..2 {
        for i in 0..3 {
            for c in [i as f64, j as f64, (i + j) as f64] {
                b.value(coord, c);
            }
            b.end();
        }
    }
    b.list(count, index, &[0.0, 1.0, 4.0, 3.0]).end();
    b.list(count, index, &[1.0, 2.0, 5.0, 4.0]).end();
    b.bytes()
}

#[test]
fn every_coordinate_type_in_every_encoding() {
    for enc in ENCODINGS {
        for coord in INTEGER_TYPES
            .iter()
            .chain(&["float", "double", "float32", "float64", "int8", "uint16"])
        {
            let (mesh, _) = read(&polygons(enc, coord, "uchar", "int", "vertex_indices"));
            assert_eq!(
                (mesh.n_vertices(), mesh.n_faces()),
                (6, 4),
                "{enc:?} {coord}"
            );
            for j in 0..2 {
                for i in 0..3 {
                    let v = mesh.vertex_at(i + 3 * j).unwrap();
                    let expected = DVec3::new(i as f64, j as f64, (i + j) as f64);
                    assert_eq!(mesh.position(v), expected, "{enc:?} {coord}");
                }
            }
        }
    }
}

#[test]
fn every_integer_list_type_and_both_names() {
    let reference = triangles(
        &read(&polygons(
            Enc::Ascii,
            "float",
            "uchar",
            "int",
            "vertex_indices",
        ))
        .0,
    );
    // Quads are fan-triangulated from their first vertex, in order.
    assert_eq!(reference, vec![[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]]);
    for enc in ENCODINGS {
        for count in INTEGER_TYPES {
            for index in INTEGER_TYPES {
                for name in ["vertex_indices", "vertex_index"] {
                    let (mesh, _) = read(&polygons(enc, "float", count, index, name));
                    assert_eq!(
                        triangles(&mesh),
                        reference,
                        "{enc:?} {count} {index} {name}"
                    );
                }
            }
        }
    }
}

/// A binary square with coordinates not first, normals and colours in between, a face
/// element with extra properties when `general`, and unknown elements before and after.
fn decorated_square(enc: Enc, general: bool) -> Vec<u8> {
    let mut b = PlyBuilder::new(enc)
        .line("comment decorated")
        .line("obj_info scanner 3")
        .element("camera", 1)
        .property("float", "view_px")
        .property("double", "view_py")
        .element("vertex", 4)
        .property("uchar", "red")
        .property("float", "nx")
        .property("double", "x")
        .property("short", "label")
        .property("double", "y")
        .property("float", "confidence")
        .property("double", "z")
        .element("face", 2)
        .list_property("uchar", "int", "vertex_indices");
    if general {
        b = b
            .property("uchar", "flags")
            .list_property("uchar", "float", "texcoord");
    }
    b = b
        .element("material", 2)
        .property("uchar", "ambient_red")
        .property("float", "shininess");
    b.value("float", 1.5).value("double", 2.5).end();
    let p = [
        [0.1, 0.2, 0.3],
        [1.1, 0.2, 0.3],
        [1.1, 1.2, 0.3],
        [0.1, 1.2, 0.3],
    ];
    for (i, [x, y, z]) in p.into_iter().enumerate() {
        b.value("uchar", 200.0)
            .value("float", 0.5)
            .value("double", x)
            .value("short", -(i as f64))
            .value("double", y)
            .value("float", 0.25)
            .value("double", z)
            .end();
    }
    for face in [[0.0, 1.0, 2.0], [0.0, 2.0, 3.0]] {
        b.list("uchar", "int", &face);
        if general {
            b.value("uchar", 1.0)
                .list("uchar", "float", &[0.5, 0.5, 0.25, 0.75]);
        }
        b.end();
    }
    for _ in 0..2 {
        b.value("uchar", 3.0).value("float", 0.5).end();
    }
    b.bytes()
}

#[test]
fn extra_properties_and_elements_are_skipped() {
    let expected = [
        [0.1, 0.2, 0.3],
        [1.1, 0.2, 0.3],
        [1.1, 1.2, 0.3],
        [0.1, 1.2, 0.3],
    ];
    for enc in ENCODINGS {
        for general in [false, true] {
            let (mesh, _) = read(&decorated_square(enc, general));
            assert_eq!(
                triangles(&mesh),
                vec![[0, 1, 2], [0, 2, 3]],
                "{enc:?} {general}"
            );
            for (i, p) in expected.iter().enumerate() {
                // Doubles are read bit for bit, in ASCII too.
                assert_eq!(
                    mesh.positions()[i],
                    DVec3::from_array(*p),
                    "{enc:?} {general}"
                );
            }
        }
    }
}

#[test]
fn polygons_unreferenced_vertices_and_degenerate_faces() {
    for enc in ENCODINGS {
        let mut b = PlyBuilder::new(enc)
            .element("vertex", 7)
            .property("float", "x")
            .property("float", "y")
            .property("float", "z")
            .element("face", 4)
            .list_property("uchar", "uint", "vertex_indices");
        let ring: Vec<[f64; 3]> = (0..5)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 5.0;
                [a.cos(), a.sin(), 0.0]
            })
            .collect();
        for p in ring.iter().chain(&[[0.0, 0.0, 1.0], [5.0, 5.0, 5.0]]) {
            for &c in p {
                b.value("float", c);
            }
            b.end();
        }
        b.list("uchar", "uint", &[0.0, 1.0, 2.0, 3.0, 4.0]).end(); // pentagon
        b.list("uchar", "uint", &[1.0, 0.0, 5.0]).end();
        b.list("uchar", "uint", &[2.0, 2.0, 5.0]).end(); // repeated index
        b.list("uchar", "uint", &[2.0, 1.0]).end(); // too short
        let (mesh, report) = read(&b.bytes());
        assert_eq!(
            mesh.n_vertices(),
            7,
            "{enc:?}: the unreferenced vertex is kept"
        );
        assert!(mesh.is_isolated(mesh.vertex_at(6).unwrap()));
        assert_eq!(mesh.n_faces(), 4, "{enc:?}: 3 fan triangles + 1 triangle");
        assert_eq!(report.dropped_faces, 2, "{enc:?}");
        assert_eq!(report.unreferenced_vertices, 1, "{enc:?}");
        assert_eq!(triangles(&mesh)[..3], [[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
    }
}

/// Strips over an `nx × ny` grid, one per row, as in `data/strips.ply`.
fn strips(enc: Enc, count: &str, index: &str, general: bool) -> Vec<u8> {
    let (nx, ny) = (3usize, 2usize);
    let id = |i: usize, j: usize| (i + j * (nx + 1)) as f64;
    let mut list = Vec::new();
    for j in 0..ny {
        if j > 0 {
            list.push(-1.0);
        }
        for i in 0..=nx {
            list.extend([id(i, j + 1), id(i, j)]);
        }
    }
    let mut b = PlyBuilder::new(enc)
        .element("vertex", (nx + 1) * (ny + 1))
        .property("float", "x")
        .property("float", "y")
        .property("float", "z")
        .element("tristrips", 1)
        .list_property(count, index, "vertex_indices");
    if general {
        b = b.property("float", "weight");
    }
    for j in 0..=ny {
        for i in 0..=nx {
            b.value("float", i as f64)
                .value("float", j as f64)
                .value("float", 0.0)
                .end();
        }
    }
    b.list(count, index, &list);
    if general {
        b.value("float", 1.0);
    }
    b.end();
    b.bytes()
}

#[test]
fn tristrips_become_consistently_oriented_triangles() {
    for enc in ENCODINGS {
        for (count, index) in [("int", "int"), ("uchar", "char"), ("ushort", "short")] {
            for general in [false, true] {
                let (mesh, report) = read(&strips(enc, count, index, general));
                let what = format!("{enc:?} {count} {index} {general}");
                assert_eq!(mesh.n_faces(), 12, "{what}");
                assert_eq!(report.dropped_faces, 0, "{what}");
                for f in mesh.faces() {
                    assert!(mesh.face_normal(f).abs_diff_eq(DVec3::Z, 1e-12), "{what}");
                }
                let t = mesh.topology_report();
                assert_eq!((t.boundary_loops, t.components), (1, 1), "{what}");
            }
        }
    }
}

#[test]
fn data_strips_file() {
    let bytes = std::fs::read(data_dir().join("strips.ply")).unwrap();
    let (mesh, report) = read(&bytes);
    // 12 × 8 quads; the stitching triangles between rows 0 and 1 are left out.
    assert_eq!((mesh.n_vertices(), mesh.n_faces()), (117, 192));
    assert_eq!(report.dropped_faces, 0);
    for f in mesh.faces() {
        assert!(
            mesh.face_normal(f).z > 0.0,
            "strip triangles keep their orientation"
        );
    }
    let t = mesh.topology_report();
    assert_eq!((t.boundary_loops, t.components, t.euler), (1, 1, 1));
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn fast_and_general_routes_agree_on_horse() {
    // horse.ply (float x y z, normals) takes the fast route; the same data written with an
    // extra face property takes the general one.
    let horse = std::fs::read(shared_meshes().join("horse.ply")).unwrap();
    let fast = routes_agree(&horse);
    assert_eq!((fast.n_vertices(), fast.n_faces()), (48_485, 96_966));
}

#[test]
fn fast_and_general_routes_agree_on_a_generated_scan() {
    // The layout scanners write (and horse.ply has): float x y z, float normals, faces as
    // uchar-counted int lists, binary little endian; here on the blob of `data/`.
    let (blob, _) = halfedge::io::read(data_dir().join("blob.obj")).unwrap();
    let normals = blob.vertex_normals();
    let mut b = PlyBuilder::new(Enc::Le)
        .element("vertex", blob.n_vertices())
        .property("float", "x")
        .property("float", "y")
        .property("float", "z")
        .property("float", "nx")
        .property("float", "ny")
        .property("float", "nz")
        .element("face", blob.n_faces())
        .list_property("uchar", "int", "vertex_indices");
    for (p, n) in blob.positions().iter().zip(&normals) {
        for c in [p.x, p.y, p.z, n.x, n.y, n.z] {
            b.value("float", c);
        }
    }
    for t in triangles(&blob) {
        b.list("uchar", "int", &t.map(|i| i as f64));
    }
    let fast = routes_agree(&b.bytes());
    assert_eq!(triangles(&fast), triangles(&blob));
    for (p, q) in fast.positions().iter().zip(blob.positions()) {
        assert_eq!(
            *p,
            q.as_vec3().as_dvec3(),
            "positions are the file's floats"
        );
    }
}

/// Reads `file` (a binary PLY with float x y z) and the same data written with an extra
/// face property, which sends it down the general route: both give the same mesh.
fn routes_agree(file: &[u8]) -> Mesh {
    let (fast, _) = read(file);
    for enc in [Enc::Le, Enc::Be] {
        let mut b = PlyBuilder::new(enc)
            .element("vertex", fast.n_vertices())
            .property("float", "x")
            .property("float", "y")
            .property("float", "z")
            .element("face", fast.n_faces())
            .list_property("uchar", "int", "vertex_indices")
            .property("uchar", "flags");
        for p in fast.positions() {
            b.value("float", p.x)
                .value("float", p.y)
                .value("float", p.z);
        }
        for t in triangles(&fast) {
            b.list("uchar", "int", &t.map(|i| i as f64))
                .value("uchar", 0.0);
        }
        let (general, _) = read(&b.bytes());
        assert_eq!(general.positions(), fast.positions(), "{enc:?}");
        assert_eq!(triangles(&general), triangles(&fast), "{enc:?}");
    }
    fast
}

#[test]
fn big_endian_and_little_endian_files_are_the_same_mesh() {
    let mesh = halfedge::generators::icosphere(2);
    let mut files = Vec::new();
    for format in [
        PlyFormat::Ascii,
        PlyFormat::BinaryLittleEndian,
        PlyFormat::BinaryBigEndian,
    ] {
        let mut bytes = Vec::new();
        write_ply_to(&mut bytes, &mesh, format).unwrap();
        files.push(read(&bytes).0);
    }
    for m in &files {
        assert_eq!(m.positions(), mesh.positions());
        assert_eq!(triangles(m), triangles(&mesh));
    }
}
