//! STL reading and writing: ASCII and binary, the encoding told apart by the size rule
//! (binary files that begin with `solid`), welding of the triangle soup by the rule of
//! `Mesh::welded_seams`, round trips, and hostile files that must give located errors.

use std::path::Path;

use glam::DVec3;
use halfedge::io::stl::{is_binary_stl, read_stl_soup_from_bytes};
use halfedge::io::{self, read_stl_from_bytes, write_stl_to, StlFormat};
use halfedge::{generators, BuildReport, Error, Mesh};
use testkit::temp_dir;

fn stl(mesh: &Mesh, format: StlFormat) -> Vec<u8> {
    let mut bytes = Vec::new();
    write_stl_to(&mut bytes, mesh, format).unwrap();
    bytes
}

fn read(bytes: &[u8]) -> (Mesh, BuildReport) {
    let (mesh, report) =
        read_stl_from_bytes(bytes, Path::new("t.stl")).unwrap_or_else(|e| panic!("{e}"));
    mesh.check().unwrap();
    (mesh, report)
}

fn error(bytes: &[u8]) -> String {
    match read_stl_from_bytes(bytes, Path::new("bad.stl")) {
        Ok((mesh, _)) => panic!("read a bad file as {mesh:?}"),
        Err(e @ Error::Format { .. }) => {
            let text = e.to_string();
            assert!(text.starts_with("bad.stl: "), "{text}");
            text
        }
        Err(e) => panic!("expected a format error, got {e:?}"),
    }
}

fn assert_error(bytes: &[u8], needles: &[&str]) {
    let message = error(bytes);
    for needle in needles {
        assert!(message.contains(needle), "{message:?} lacks {needle:?}");
    }
}

/// The corners of every face, in face order, as `f32` (what STL holds).
fn corners(mesh: &Mesh) -> Vec<[[f32; 3]; 3]> {
    mesh.faces()
        .map(|f| {
            mesh.triangle(f)
                .map(|v| mesh.position(v).as_vec3().to_array())
        })
        .collect()
}

/// Binary STL of `n` triangles from raw corner values.
fn binary(header: &[u8], triangles: &[[[f32; 3]; 3]]) -> Vec<u8> {
    let mut bytes = vec![b' '; 80];
    bytes[..header.len()].copy_from_slice(header);
    bytes.extend((triangles.len() as u32).to_le_bytes());
    for t in triangles {
        bytes.extend([0u8; 12]);
        for c in t.iter().flatten() {
            bytes.extend(c.to_le_bytes());
        }
        bytes.extend([0u8; 2]);
    }
    bytes
}

/// A closed mesh with coordinates that are not `f32`: an icosphere, scaled by π.
fn sphere() -> Mesh {
    let mut mesh = generators::icosphere(2);
    for p in mesh.positions_mut() {
        *p *= std::f64::consts::PI;
    }
    mesh
}

#[test]
fn round_trips_give_the_same_triangles_as_f32() {
    let torus = generators::torus(1.0, 0.3, 24, 12).unwrap();
    for (name, mesh) in [("sphere", sphere()), ("torus", torus)] {
        for format in [StlFormat::Binary, StlFormat::Ascii] {
            let bytes = stl(&mesh, format);
            assert_eq!(is_binary_stl(&bytes), format == StlFormat::Binary);
            let (back, report) = read(&bytes);
            let what = format!("{name} {format:?}");
            assert_eq!(corners(&back), corners(&mesh), "{what}");
            // Welded back into the closed mesh it was.
            assert_eq!(back.n_vertices(), mesh.n_vertices(), "{what}");
            assert_eq!(back.topology_report(), mesh.topology_report(), "{what}");
            assert_eq!(
                report.merged_vertices,
                3 * mesh.n_faces() - mesh.n_vertices()
            );
            assert_eq!(report.input_faces, mesh.n_faces());
            assert_eq!(report.dropped_faces + report.duplicated_vertices, 0);
            // Positions are the f32 ones, exactly.
            for v in back.vertices() {
                let p = back.position(v);
                assert_eq!(p, p.as_vec3().as_dvec3(), "{what}");
            }
        }
    }
}

#[test]
fn io_write_and_read_pick_stl_by_extension() {
    let dir = temp_dir("stl-dispatch");
    let mesh = sphere();
    let path = dir.join("sphere.Stl");
    io::write(&path, &mesh).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    assert!(is_binary_stl(&bytes), "io::write writes binary STL");
    assert_eq!(bytes.len(), 84 + 50 * mesh.n_faces());
    let (back, _) = io::read(&path).unwrap();
    assert_eq!(corners(&back), corners(&mesh));
    let ascii = dir.join("sphere-ascii.STL");
    io::write_stl(&ascii, &mesh, StlFormat::Ascii).unwrap();
    assert!(std::fs::read(&ascii).unwrap().starts_with(b"solid "));
    assert_eq!(corners(&io::read(&ascii).unwrap().0), corners(&mesh));
    std::fs::remove_dir_all(&dir).ok();
}

/// Normals are the faces' unit normals, as `f32`.
#[test]
fn written_normals_are_the_face_normals() {
    let mesh = sphere();
    let bytes = stl(&mesh, StlFormat::Binary);
    for (k, f) in mesh.faces().enumerate() {
        let at = 84 + 50 * k;
        let n: Vec<f32> = (0..3)
            .map(|i| f32::from_le_bytes(bytes[at + 4 * i..at + 4 * i + 4].try_into().unwrap()))
            .collect();
        assert_eq!(n, mesh.face_normal(f).as_vec3().to_array());
    }
    let text = String::from_utf8(stl(&generators::grid(2, 2, 1.0, 1.0), StlFormat::Ascii)).unwrap();
    assert!(text.contains("facet normal 0 0 1"), "{text}");
}

/// A binary file whose header begins with `solid` (as many exporters write them) is read
/// as binary by the size rule, and an ASCII file is read as ASCII whatever its size.
#[test]
fn binary_files_beginning_with_solid_are_binary() {
    let mesh = sphere();
    let mut bytes = stl(&mesh, StlFormat::Binary);
    bytes[..80].fill(b' ');
    bytes[..22].copy_from_slice(b"solid exported\nfacet n");
    assert!(is_binary_stl(&bytes));
    assert_eq!(corners(&read(&bytes).0), corners(&mesh));
    // Cut by one byte: no longer the size its count says, and not ASCII either (the word
    // after the `solid` line is `facet` here, so it is taken for ASCII and refused with
    // the place where the text goes wrong).
    let message = error(&bytes[..bytes.len() - 1]);
    assert!(message.contains("line 2"), "{message}");
    // With another word there, it is a truncated binary file.
    bytes[15..20].copy_from_slice(b"xxxxx");
    let message = error(&bytes[..bytes.len() - 1]);
    assert!(message.contains("truncated file"), "{message}");
    assert!(message.contains("announces"), "{message}");
    // One triangle whose header is `solid` and nothing else.
    let one = binary(
        b"solid",
        &[[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]],
    );
    assert_eq!(read(&one).0.n_faces(), 1);
}

#[test]
fn ascii_variants() {
    let square = "solid sq\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
                  vertex 1 1 0\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\n\
                  vertex 0 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid sq\n";
    let (mesh, report) = read(square.as_bytes());
    assert_eq!((mesh.n_vertices(), mesh.n_faces()), (4, 2));
    assert_eq!(report.merged_vertices, 2);
    assert_eq!(mesh.topology_report().boundary_loops, 1);
    let expected = corners(&mesh);
    let same = |text: &[u8]| assert_eq!(corners(&read(text).0), expected);
    // Upper case, CRLF, every facet on one line, a Latin-1 name, two solids.
    same(square.to_uppercase().as_bytes());
    same(square.replace('\n', "\r\n").as_bytes());
    same(format!("solid sq\n{}", square[9..].replace('\n', " ")).as_bytes());
    same(&[b"solid caf\xe9 \xff\n".as_slice(), &square.as_bytes()[9..]].concat());
    let half = square
        .find("facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 1")
        .unwrap();
    let two = format!(
        "{}endsolid a\nsolid b\n{}",
        &square[..half],
        &square[half..]
    );
    same(two.as_bytes());
    // A solid without facets before one with them; `endsolid` without a name.
    same(format!("solid empty\nendsolid\n{square}").as_bytes());
}

/// The soup of a closed mesh welds into one closed component, as `welded_seams` welds
/// it, with the same mesh; a soup whose welding closes nothing stays a soup.
#[test]
fn the_soup_is_welded_by_the_welded_seams_rule() {
    let torus = generators::torus(1.0, 0.3, 16, 8).unwrap();
    let two = generators::disjoint_union(&[&sphere(), &torus]).unwrap();
    for mesh in [sphere(), torus, two, generators::grid(6, 4, 1.0, 1.0)] {
        let bytes = stl(&mesh, StlFormat::Binary);
        let (welded, report) = read(&bytes);
        let (soup, soup_report) = read_stl_soup_from_bytes(&bytes, Path::new("s.stl")).unwrap();
        assert_eq!(soup.n_vertices(), 3 * mesh.n_faces());
        assert_eq!(soup_report.merged_vertices, 0);
        let (by_rule, weld) = soup
            .welded_seams()
            .unwrap()
            .expect("welding closes the soup");
        assert_eq!(welded.to_arrays(), by_rule.to_arrays());
        assert_eq!(report.merged_vertices, weld.merged_vertices);
        let topology = welded.topology_report();
        assert_eq!(topology, mesh.topology_report());
        if mesh.n_faces() == sphere().n_faces() {
            assert_eq!((topology.components, topology.boundary_loops), (1, 0));
        }
    }
    // The same triangle twice: welding puts the second on the first's edges, which the
    // builder refuses and puts on copies again (no fewer boundary loops), so the soup is
    // kept.
    let twice = binary(
        b"twice",
        &[
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        ],
    );
    let (mesh, report) = read(&twice);
    assert_eq!((mesh.n_vertices(), report.merged_vertices), (6, 0));
    assert_eq!(report.duplicated_vertices, 0, "the soup's report");
    let (soup, _) = read_stl_soup_from_bytes(&twice, Path::new("s.stl")).unwrap();
    assert!(soup.welded_seams().unwrap().is_none());
    // Two triangles touching at a corner: welding joins their boundaries into one loop.
    let bow = binary(
        b"bow",
        &[
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            [[0.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]],
        ],
    );
    let (mesh, report) = read(&bow);
    assert_eq!((mesh.n_vertices(), report.merged_vertices), (5, 1));
    assert_eq!(mesh.topology_report().boundary_loops, 1);
    // Nothing at one place: the soup.
    let apart = binary(
        b"apart",
        &[
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            [[5.0, 0.0, 0.0], [6.0, 0.0, 0.0], [5.0, 1.0, 0.0]],
        ],
    );
    assert_eq!(read(&apart).0.n_vertices(), 6);
}

/// A triangle with two corners at one place is dropped by welding and counted; `-0.0`
/// and `0.0` weld.
#[test]
fn degenerate_triangles_and_signed_zeros() {
    let bytes = binary(
        b"degenerate",
        &[
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            [[-0.0, 0.0, -0.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]],
            [[1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        ],
    );
    let (mesh, report) = read(&bytes);
    assert_eq!(mesh.n_vertices(), 4);
    assert_eq!(mesh.n_faces(), 2);
    assert_eq!(report.input_faces, 3);
    assert_eq!(report.dropped_faces, 1);
    assert_eq!(report.merged_vertices, 9 - 4);
    assert_eq!(mesh.topology_report().components, 1);
}

#[test]
fn hostile_stl_files_give_located_errors() {
    assert_error(b"", &["line 1", "empty file"]);
    assert_error(b"garbage", &["byte 7", "truncated", "80-byte header"]);
    // A count of 4 billion triangles in a 200-byte file: refused from the size, before
    // anything is allocated.
    let mut lying = binary(b"lying", &[[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]]);
    lying.extend([0u8; 66]);
    assert_eq!(lying.len(), 200);
    lying[80..84].copy_from_slice(&4_000_000_000u32.to_le_bytes());
    assert_error(
        &lying,
        &["byte 200", "truncated", "announces 4000000000 triangles"],
    );
    lying[80..84].copy_from_slice(&u32::MAX.to_le_bytes());
    assert_error(&lying, &["announces 4294967295 triangles"]);
    // Truncated in the middle of a triangle.
    let full = stl(&sphere(), StlFormat::Binary);
    assert_error(
        &full[..84 + 50 * 7 + 20],
        &["truncated", "triangle 7 is the first one missing"],
    );
    assert_error(&binary(b"none", &[]), &["byte 80", "no triangles"]);
    // Non-finite coordinates, at their byte.
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let bytes = binary(
            b"nan",
            &[
                [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
                [[0.0; 3], [1.0, bad, 0.0], [0.0, 1.0, 0.0]],
            ],
        );
        assert_error(
            &bytes,
            &[
                "triangle 1",
                &format!("byte {}", 84 + 50 + 24),
                "non-finite",
            ],
        );
    }
    // ASCII.
    let ascii = String::from_utf8(stl(&generators::icosphere(0), StlFormat::Ascii)).unwrap();
    let lines: Vec<&str> = ascii.lines().collect();
    let without_end = lines[..lines.len() - 1].join("\n");
    assert_error(
        without_end.as_bytes(),
        &[
            "end of file",
            "truncated",
            "'facet' or 'endsolid'",
            "facet 20",
        ],
    );
    let first_vertex = lines[3];
    assert!(first_vertex.trim_start().starts_with("vertex "));
    for (from, to, needles) in [
        (
            first_vertex,
            "vertex 0 nan 0",
            &["line 4", "facet 0", "non-finite"][..],
        ),
        (first_vertex, "vertex 1e39 0 0", &["line 4", "non-finite"]),
        (
            first_vertex,
            "vertex x 0 0",
            &["line 4", "malformed coordinate 'x'"],
        ),
        (
            "outer loop",
            "outer lop",
            &["line 3", "expected 'loop'", "'lop'"],
        ),
        (
            "endloop",
            "vertex 1 2 3\nendloop",
            &["line 7", "more than three"],
        ),
        (
            "facet normal",
            "facet nromal",
            &["line 2", "expected 'normal'"],
        ),
    ] {
        let text = ascii.replacen(from, to, 1);
        assert_error(text.as_bytes(), needles);
    }
    // Bytes that are not UTF-8 in a number.
    let at = ascii.find(first_vertex).unwrap() + first_vertex.find("vertex").unwrap() + 7;
    let mut latin1 = ascii.clone().into_bytes();
    latin1[at] = 0xe9;
    assert_error(&latin1, &["line 4", "facet 0", "malformed coordinate"]);
    // A loop of two vertices.
    let mut short: Vec<&str> = ascii.lines().collect();
    short.remove(5);
    assert_error(
        short.join("\n").as_bytes(),
        &["line 6", "facet 0", "the loop has 2 vertices"],
    );
    assert_error(b"solid x\nendsolid x\n", &["line 3", "no triangles"]);
    assert_error(
        b"solid x\n",
        &["line 2", "end of file", "'facet' or 'endsolid'"],
    );
    assert_error(
        format!("{ascii}garbage\n").as_bytes(),
        &["expected 'solid' or the end of the file", "'garbage'"],
    );
}

/// Writing refuses positions that `f32` cannot hold.
#[test]
fn positions_beyond_f32_are_refused() {
    let mut mesh = generators::icosphere(0);
    let v = mesh.vertices().nth(3).unwrap();
    mesh.set_position(v, DVec3::new(1e39, 0.0, 0.0));
    let mut bytes = Vec::new();
    for format in [StlFormat::Binary, StlFormat::Ascii] {
        let e = write_stl_to(&mut bytes, &mesh, format).unwrap_err();
        assert!(
            matches!(&e, Error::InvalidArgument(m) if m.contains("f32")),
            "{e:?}"
        );
    }
}
