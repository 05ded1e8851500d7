//! OFF reading and writing: the variants of the format (COFF, NOFF, counts on the
//! keyword's line, comments, values across lines, CRLF and CR line ends), round trips,
//! the same polygons as OBJ, and hostile files that must give located errors.

use std::path::Path;

use halfedge::io::{self, read_off_from_bytes};
use halfedge::{generators, BuildReport, Error, Mesh};
use testkit::check::{position_bits as bits, triangles};
use testkit::{data_dir, temp_dir};

fn read(text: &[u8]) -> (Mesh, BuildReport) {
    let (mesh, report) =
        read_off_from_bytes(text, Path::new("t.off")).unwrap_or_else(|e| panic!("{e}"));
    mesh.check().unwrap();
    (mesh, report)
}

fn error(text: &[u8]) -> String {
    match read_off_from_bytes(text, Path::new("bad.off")) {
        Ok((mesh, _)) => panic!("read a bad file as {mesh:?}"),
        Err(e @ Error::Format { .. }) => {
            let text = e.to_string();
            assert!(text.starts_with("bad.off: "), "{text}");
            text
        }
        Err(e) => panic!("expected a format error, got {e:?}"),
    }
}

fn assert_error(text: &[u8], needles: &[&str]) {
    let message = error(text);
    for needle in needles {
        assert!(
            message.contains(needle),
            "{message:?} lacks {needle:?} (file {:?})",
            String::from_utf8_lossy(text)
        );
    }
}

/// A unit square as two triangles, the way the variants below write it.
const SQUARE: &str = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";

fn square() -> Mesh {
    read(SQUARE.as_bytes()).0
}

fn same_as_square(text: &str) {
    let (mesh, report) = read(text.as_bytes());
    assert_eq!(bits(&mesh), bits(&square()), "{text}");
    assert_eq!(triangles(&mesh), [[0, 1, 2], [0, 2, 3]], "{text}");
    assert_eq!(report.dropped_faces, 0);
    assert_eq!(report.merged_vertices, 0);
}

#[test]
fn the_square_reads_with_file_vertex_numbers() {
    let (mesh, report) = read(SQUARE.as_bytes());
    assert_eq!((mesh.n_vertices(), mesh.n_faces()), (4, 2));
    assert_eq!(report.input_faces, 2);
    for (i, p) in [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ]
    .iter()
    .enumerate()
    {
        assert_eq!(mesh.position(mesh.vertex_at(i).unwrap()).to_array(), *p);
    }
}

#[test]
fn off_variants_read_as_the_same_square() {
    // Counts on the keyword's line.
    same_as_square("OFF 4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
    // Comments everywhere, blank lines, tabs.
    same_as_square(
        "# a square\nOFF # keyword\n\n# counts next\n4 2 0 # V F E\n0 0 0 # first\n\
         1\t0 0\n# between vertices\n1 1 0\n0 1 0\n3 0 1 2 # a face\n# between faces\n3 0 2 3\n# end",
    );
    // Values across lines.
    same_as_square("OFF\n4\n2\n0\n0\n0 0\n1 0\n0\n1 1 0\n0\n1\n0\n3 0\n1 2\n3 0 2\n3\n");
    // CRLF, and lone CR.
    same_as_square(&SQUARE.replace('\n', "\r\n"));
    same_as_square(&SQUARE.replace('\n', "\r"));
    // The keyword is optional.
    same_as_square(SQUARE.strip_prefix("OFF\n").unwrap());
    // A byte order mark, no line end at the end.
    same_as_square(&format!("\u{feff}{}", SQUARE.trim_end()));
    // COFF: a colour after each vertex (3 or 4 values, integers or floats) and after
    // faces.
    same_as_square(
        "COFF\n4 2 0\n0 0 0 255 0 0\n1 0 0 0 255 0 255\n1 1 0 0.5 0.5 0.5 1.0\n0 1 0 1 1 1\n\
         3 0 1 2 255 0 0\n3 0 2 3 0.1 0.2 0.3 0.4\n",
    );
    // NOFF: a normal after each vertex (here one on the next line).
    same_as_square(
        "NOFF\n4 2 0\n0 0 0 0 0 1\n1 0 0\n0 0 1\n1 1 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n3 0 2 3\n",
    );
    // CNOFF and STOFF, with a colour index on a face.
    same_as_square(
        "CNOFF\n4 2 0\n0 0 0 0 0 1 1 0 0\n1 0 0 0 0 1 1 0 0\n1 1 0 0 0 1 1 0 0 1\n\
         0 1 0 0 0 1 1 0 0\n3 0 1 2 7\n3 0 2 3\n",
    );
    // Vertex colours without the C keyword are skipped, as OpenMesh skips them.
    same_as_square(
        "OFF\n4 2 0\n0 0 0 9 9 9\n1 0 0 9 9 9\n1 1 0 9 9 9 9\n0 1 0\n3 0 1 2\n3 0 2 3\n",
    );
    same_as_square("STOFF\n4 2 0\n0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n3 0 1 2\n3 0 2 3\n");
    // Edges or anything after the last face are ignored; names in Latin-1 in comments.
    same_as_square(&format!("{SQUARE}2 0 1\n# caf\u{e9}\n"));
    let latin1 = [b"# caf\xe9 \xff\xfe\n".as_slice(), SQUARE.as_bytes()].concat();
    let (mesh, _) = read(&latin1);
    assert_eq!(triangles(&mesh), [[0, 1, 2], [0, 2, 3]]);
}

/// Polygons are fan-triangulated by the builder, as OBJ and PLY polygons are: the OFF
/// and OBJ forms of `data/`'s meshes (quads, a pentagon, non-manifold and repeated
/// faces, unreferenced vertices) read to the same mesh and report.
#[test]
fn polygons_read_as_obj_polygons_read() {
    for name in ["dirty.obj", "quads_hole.obj", "creature.obj"] {
        let text = std::fs::read_to_string(data_dir().join(name)).unwrap();
        let mut positions = Vec::new();
        let mut faces = Vec::new();
        for line in text.lines() {
            let mut tokens = line.split_whitespace();
            match tokens.next() {
                Some("v") => positions.push(tokens.take(3).collect::<Vec<_>>().join(" ")),
                Some("f") => {
                    let f: Vec<String> = tokens
                        .map(|t| {
                            let i: usize = t.split('/').next().unwrap().parse().unwrap();
                            (i - 1).to_string()
                        })
                        .collect();
                    faces.push(format!("{} {}", f.len(), f.join(" ")));
                }
                _ => {}
            }
        }
        let off = format!(
            "OFF\n{} {} 0\n{}\n{}\n",
            positions.len(),
            faces.len(),
            positions.join("\n"),
            faces.join("\n")
        );
        let (ours, report) = read(off.as_bytes());
        let (obj, obj_report) = io::read(data_dir().join(name)).unwrap();
        assert_eq!(bits(&ours), bits(&obj), "{name}");
        assert_eq!(triangles(&ours), triangles(&obj), "{name}");
        if name != "dirty.obj" {
            assert_eq!(report, obj_report, "{name}");
        } else {
            // OBJ drops the repeats of a face and keeps it, OFF (like PLY) drops the face.
            assert_eq!(report.input_faces, obj_report.input_faces);
        }
    }
}

#[test]
fn written_off_reads_back_bit_for_bit() {
    let dir = temp_dir("off-roundtrip");
    let torus = generators::torus(1.0, 0.3, 24, 12).unwrap();
    // Coordinates that need all 17 digits.
    let mut sphere = generators::icosphere(2);
    for p in sphere.positions_mut() {
        *p *= std::f64::consts::PI * 1e-7;
    }
    for (name, mesh) in [
        ("torus", torus),
        ("sphere", sphere),
        ("grid", generators::grid(7, 5, 1.0, 1.0)),
    ] {
        let path = dir.join(format!("{name}.OFF"));
        io::write(&path, &mesh).unwrap();
        let (back, report) = io::read(&path).unwrap();
        back.check().unwrap();
        assert_eq!(bits(&back), bits(&mesh), "{name}");
        assert_eq!(triangles(&back), triangles(&mesh), "{name}");
        assert_eq!(back.topology_report(), mesh.topology_report(), "{name}");
        assert_eq!(report.duplicated_vertices, 0);
        let text = std::fs::read_to_string(&path).unwrap();
        let counts = format!(
            "{} {} {}",
            mesh.n_vertices(),
            mesh.n_faces(),
            mesh.n_edges()
        );
        assert_eq!(text.lines().nth(1), Some(counts.as_str()));
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A mesh with removed vertices is written compacted, as OBJ and PLY are.
#[test]
fn written_off_compacts_live_vertices() {
    let mut mesh = generators::icosphere(2);
    let h = mesh
        .halfedges()
        .find(|&h| mesh.is_collapse_ok(h).is_ok())
        .unwrap();
    mesh.collapse(h).unwrap();
    let mut bytes = Vec::new();
    io::write_off_to(&mut bytes, &mesh).unwrap();
    let (back, _) = read(&bytes);
    assert_eq!(back.n_vertices(), mesh.n_vertices());
    assert_eq!(back.n_faces(), mesh.n_faces());
    let positions = |m: &Mesh| -> Vec<[f64; 3]> {
        m.faces()
            .flat_map(|f| m.triangle(f).map(|v| m.position(v).to_array()))
            .collect()
    };
    assert_eq!(positions(&back), positions(&mesh));
}

#[test]
fn hostile_off_files_give_located_errors() {
    assert_error(b"", &["line 1", "empty file"]);
    assert_error(b"# only a comment\n\n", &["line 3", "no OFF header"]);
    assert_error(b"PLY\n3 1 0\n", &["line 1", "not an OFF file", "'PLY'"]);
    assert_error(
        b"4OFF\n1 0 0\n0 0 0 0\n",
        &["line 1", "'4OFF'", "not supported"],
    );
    assert_error(b"nOFF\n3\n1 0 0\n0 0 0\n", &["line 1", "not supported"]);
    assert_error(
        b"OFF BINARY\n\0\0\0\x04",
        &["line 1", "binary OFF", "not supported"],
    );
    // Counts.
    assert_error(b"OFF\n", &["line 2", "end of file", "vertex count"]);
    assert_error(b"OFF\n4 2\n", &["edge count"]);
    assert_error(b"OFF\nfour 2 0\n", &["line 2", "'four'"]);
    assert_error(b"OFF\n-4 2 0\n", &["line 2", "vertex count", "'-4'"]);
    assert_error(b"OFF\n0 0 0\n", &["line 2", "no vertices"]);
    assert_error(b"OFF\n99999999999 0 0\n", &["line 2", "32-bit"]);
    // Counts the file cannot hold: refused before allocating (10^12 vertices would be
    // 24 TB of positions).
    let huge = b"OFF\n# a lying header\n1000000000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    assert!(huge.len() < 100);
    assert_error(huge, &["line 3", "32-bit"]);
    assert_error(
        b"OFF\n4000000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
        &["line 2", "announces 4000000000 vertices", "bytes after it"],
    );
    assert_error(
        b"OFF\n3 18446744073709551615 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
        &["line 2", "bytes after it"],
    );
    // Truncated.
    let full = SQUARE.as_bytes();
    for cut in [12, 20, 30, full.len() - 4] {
        let message = error(&full[..cut]);
        assert!(
            message.contains("truncated") || message.contains("bytes after it"),
            "{message}"
        );
        assert!(message.contains("line "), "{message}");
    }
    assert_error(
        b"OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n",
        &["line 8", "end of file", "face 1 of 2"],
    );
    assert_error(
        b"OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2\n",
        &["line 9", "truncated", "face 1 (3 vertices announced)"],
    );
    // Coordinates.
    for bad in ["nan", "NaN", "inf", "-inf", "1e999"] {
        let text = SQUARE.replace("1 1 0", &format!("1 {bad} 0"));
        assert_error(text.as_bytes(), &["line 5", "vertex 2", "non-finite", bad]);
    }
    assert_error(
        SQUARE.replace("1 1 0", "1 x 0").as_bytes(),
        &["line 5", "vertex 2", "malformed number 'x'"],
    );
    let latin1_number = SQUARE.as_bytes().to_vec();
    let at = SQUARE.find("1 1 0").unwrap() + 2;
    let mut latin1_number = latin1_number;
    latin1_number[at] = 0xe9;
    assert_error(&latin1_number, &["line 5", "vertex 2", "malformed number"]);
    // Indices.
    assert_error(
        SQUARE.replace("3 0 2 3", "3 0 2 4").as_bytes(),
        &["line 8", "face 1 refers to vertex 4", "4 vertices"],
    );
    assert_error(
        SQUARE.replace("3 0 2 3", "3 0 -1 3").as_bytes(),
        &["line 8", "face 1", "negative vertex index (-1)"],
    );
    assert_error(
        SQUARE
            .replace("3 0 2 3", "3 0 2 99999999999999999999")
            .as_bytes(),
        &["line 8", "face 1", "malformed vertex index"],
    );
    assert_error(
        SQUARE.replace("3 0 2 3", "3 0 2.0 3").as_bytes(),
        &["line 8", "malformed vertex index '2.0'"],
    );
    assert_error(
        SQUARE.replace("3 0 2 3", "x 0 2 3").as_bytes(),
        &["line 8", "face 1", "number of vertices", "'x'"],
    );
    // Two faces on one line, or a count smaller than the indices.
    assert_error(
        b"OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2 4 0 1 2 3\n3 0 2 3\n",
        &["line 7", "face 0", "followed by 5 values"],
    );
    // Four values after a face are its colour: the second face is then missing.
    assert_error(
        b"OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2 3 0 2 3\n",
        &["line 8", "truncated", "face 1 of 2 is missing"],
    );
    // Several vertices on one line (OpenMesh reads one per line, as every writer
    // writes them).
    assert_error(
        b"OFF\n4 2 0\n0 0 0 1 0 0 1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n",
        &["line 3", "vertex 0", "followed by 6 values", "4 at most"],
    );
    assert_error(
        b"COFF\n1 0 0\n0 0 0 1 2 3 4 5 6 7 8 9\n",
        &["line 3", "vertex 0", "followed by 9 values", "8 at most"],
    );
}

/// Faces with fewer than three vertices or repeated indices are dropped and counted, as
/// for PLY; unreferenced vertices stay.
#[test]
fn degenerate_faces_and_unreferenced_vertices() {
    let (mesh, report) = read(
        b"OFF\n6 5 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0.5 0\n9 9 9\n0\n2 0 1\n3 0 1 1\n4 0 1 2 3\n3 1 4 2 1 0 0\n",
    );
    assert_eq!(mesh.n_vertices(), 6);
    assert_eq!(report.duplicated_vertices, 0);
    assert_eq!(report.input_faces, 5);
    assert_eq!(report.dropped_faces, 3);
    assert_eq!(report.unreferenced_vertices, 1);
    assert_eq!(mesh.n_faces(), 3);
}
