//! Bad files give typed errors that name the file and say what is wrong; nothing panics.

use std::path::{Path, PathBuf};

use halfedge::io;
use halfedge::Error;
use testkit::ply::{square, Enc, PlyBuilder};
use testkit::temp_dir;

/// Writes `bytes` to `dir/name`, reads it back with [`io::read`] and returns the error.
fn read_error(dir: &Path, name: &str, bytes: &[u8]) -> Error {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    match io::read(&path) {
        Ok((mesh, _)) => panic!("{name}: read a bad file as {mesh:?}"),
        Err(e) => e,
    }
}

/// Asserts a format error that names the file and contains every `needle`.
fn assert_format(e: &Error, name: &str, needles: &[&str]) {
    let Error::Format { path, message } = e else {
        panic!("{name}: expected a format error, got {e:?}");
    };
    assert!(path.ends_with(name), "{name}: error names {path:?}");
    let text = e.to_string();
    assert!(
        text.contains(name),
        "{name}: message does not name the file: {text}"
    );
    for needle in needles {
        assert!(
            message.contains(needle),
            "{name}: message lacks {needle:?}: {message}"
        );
    }
}

const ENCODINGS: [Enc; 3] = [Enc::Ascii, Enc::Le, Enc::Be];

/// The square with an extra per-face property, which sends binary files down the
/// general (`ply-rs-bw`) route instead of the fast one.
fn square_general(enc: Enc) -> PlyBuilder {
    let mut b = PlyBuilder::new(enc)
        .element("vertex", 4)
        .property("float", "x")
        .property("float", "y")
        .property("float", "z")
        .element("face", 2)
        .list_property("uchar", "int", "vertex_indices")
        .property("uchar", "flags");
    for p in [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ] {
        for c in p {
            b.value("float", c);
        }
        b.end();
    }
    b.list("uchar", "int", &[0.0, 1.0, 2.0])
        .value("uchar", 7.0)
        .end();
    b.list("uchar", "int", &[0.0, 2.0, 3.0])
        .value("uchar", 9.0)
        .end();
    b
}

/// Both routes in every encoding, each with a name.
fn squares() -> Vec<(String, PlyBuilder)> {
    let mut all = Vec::new();
    for enc in ENCODINGS {
        all.push((format!("fast-{enc:?}.ply"), square(enc)));
        all.push((format!("general-{enc:?}.ply"), square_general(enc)));
    }
    all
}

#[test]
fn the_test_squares_are_valid() {
    let dir = temp_dir("valid-squares");
    for (name, b) in squares() {
        let path = dir.join(&name);
        std::fs::write(&path, b.bytes()).unwrap();
        let (mesh, report) = io::read(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        mesh.check().unwrap();
        assert_eq!((mesh.n_vertices(), mesh.n_faces()), (4, 2), "{name}");
        assert_eq!(report.dropped_faces, 0);
    }
}

#[test]
fn empty_files() {
    let dir = temp_dir("empty");
    for name in [
        "empty.ply",
        "empty.obj",
        "empty.off",
        "empty.stl",
        "empty.obj.gz",
    ] {
        let e = read_error(&dir, name, b"");
        assert_format(&e, name, &["empty file"]);
    }
}

#[test]
fn files_without_vertices() {
    let dir = temp_dir("no-vertices");
    let e = read_error(&dir, "comments.obj", b"# only a comment\n\n");
    assert_format(&e, "comments.obj", &["no vertices"]);
    for enc in ENCODINGS {
        let b = PlyBuilder::new(enc)
            .element("vertex", 0)
            .property("float", "x")
            .property("float", "y")
            .property("float", "z");
        let name = format!("zero-vertices-{enc:?}.ply");
        let e = read_error(&dir, &name, &b.bytes());
        assert_format(&e, &name, &["no vertices"]);
    }
}

#[test]
fn missing_file_is_an_io_error_naming_it() {
    let path = temp_dir("missing").join("not-there.ply");
    match io::read(&path) {
        Err(Error::Io { path: p, .. }) => assert_eq!(p, path),
        other => panic!("expected an I/O error, got {other:?}"),
    }
}

#[test]
fn unknown_extension() {
    let mesh = halfedge::generators::icosphere(0);
    for name in ["mesh.xyz", "mesh", "mesh.gz", "mesh.txt.gz", "mesh.obj.bz2"] {
        let path = PathBuf::from(name);
        let e = io::read(&path).unwrap_err();
        assert!(matches!(&e, Error::UnknownFormat(p) if *p == path), "{e:?}");
        // The message lists the formats there are.
        let text = e.to_string();
        for known in [".obj", ".ply", ".off", ".stl", ".obj.gz", ".stl.gz"] {
            assert!(text.contains(known), "{text}");
        }
        assert!(matches!(
            io::write(&path, &mesh),
            Err(Error::UnknownFormat(_))
        ));
    }
}

#[test]
fn truncated_binary_ply() {
    let dir = temp_dir("truncated");
    for (name, b) in squares() {
        if name.contains("Ascii") {
            continue;
        }
        let bytes = b.bytes();
        let header_end = bytes
            .windows(11)
            .position(|w| w == b"end_header\n")
            .unwrap()
            + 11;
        for len in header_end..bytes.len() {
            let cut = format!("cut{len}-{name}");
            let e = read_error(&dir, &cut, &bytes[..len]);
            assert_format(&e, &cut, &["truncated"]);
            let element = if len < header_end + 4 * 12 {
                "vertex"
            } else {
                "face"
            };
            assert!(e.to_string().contains(element), "{cut}: {e}");
        }
        // Cut inside the header.
        for len in [3, 10, header_end - 3] {
            let cut = format!("header{len}-{name}");
            let e = read_error(&dir, &cut, &bytes[..len]);
            assert_format(&e, &cut, &["header"]);
        }
    }
}

#[test]
fn truncated_ascii_ply() {
    let dir = temp_dir("truncated-ascii");
    let bytes = square(Enc::Ascii).bytes();
    let text = String::from_utf8(bytes.clone()).unwrap();
    // Drop the last face line.
    let cut = text.trim_end().rfind('\n').unwrap() + 1;
    let e = read_error(&dir, "cut.ply", &bytes[..cut]);
    assert_format(&e, "cut.ply", &["truncated", "face"]);
}

/// Replaces the second face of the square with `indices` (as `int`s).
fn square_with_face(enc: Enc, general: bool, indices: &[f64]) -> Vec<u8> {
    let mut b = PlyBuilder::new(enc)
        .element("vertex", 4)
        .property("float", "x")
        .property("float", "y")
        .property("float", "z")
        .element("face", 2)
        .list_property("uchar", "int", "vertex_indices");
    if general {
        b = b.property("uchar", "flags");
    }
    for p in [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ] {
        for c in p {
            b.value("float", c);
        }
        b.end();
    }
    for face in [&[0.0, 1.0, 2.0][..], indices] {
        b.list("uchar", "int", face);
        if general {
            b.value("uchar", 0.0);
        }
        b.end();
    }
    b.bytes()
}

#[test]
fn index_out_of_range() {
    let dir = temp_dir("out-of-range");
    for enc in ENCODINGS {
        for general in [false, true] {
            let name = format!("range-{enc:?}-{general}.ply");
            let e = read_error(
                &dir,
                &name,
                &square_with_face(enc, general, &[0.0, 2.0, 4.0]),
            );
            assert_format(&e, &name, &["face 1", "vertex 4", "4 vertices"]);
        }
    }
    let e = read_error(
        &dir,
        "range.obj",
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 7\n",
    );
    assert_format(&e, "range.obj", &["line 5", "vertex 7", "3 vertices"]);
}

#[test]
fn negative_index() {
    let dir = temp_dir("negative");
    for enc in ENCODINGS {
        for general in [false, true] {
            let name = format!("negative-{enc:?}-{general}.ply");
            let e = read_error(
                &dir,
                &name,
                &square_with_face(enc, general, &[0.0, -2.0, 3.0]),
            );
            assert_format(&e, &name, &["face 1", "negative", "-2"]);
        }
    }
    // OBJ indices may be negative (relative to the end), but not before the first vertex.
    let e = read_error(
        &dir,
        "negative.obj",
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -9\n",
    );
    assert_format(
        &e,
        "negative.obj",
        &["line 4", "-9", "before the first vertex"],
    );
    let (mesh, _) = io::read_obj_from_bytes(
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n",
        Path::new("x.obj"),
    )
    .unwrap();
    assert_eq!(mesh.n_faces(), 1);
}

#[test]
fn non_finite_coordinates() {
    let dir = temp_dir("nan");
    for value in [f64::NAN, f64::INFINITY] {
        for enc in [Enc::Le, Enc::Be] {
            for ty in ["float", "double"] {
                let mut b = PlyBuilder::new(enc)
                    .element("vertex", 3)
                    .property(ty, "x")
                    .property(ty, "y")
                    .property(ty, "z")
                    .element("face", 1)
                    .list_property("uchar", "int", "vertex_indices");
                for p in [[0.0, 0.0, 0.0], [1.0, 0.0, value], [0.0, 1.0, 0.0]] {
                    for c in p {
                        b.value(ty, c);
                    }
                    b.end();
                }
                b.list("uchar", "int", &[0.0, 1.0, 2.0]).end();
                let name = format!("nonfinite-{value}-{enc:?}-{ty}.ply");
                let e = read_error(&dir, &name, &b.bytes());
                assert_format(&e, &name, &["vertex 1", "non-finite"]);
            }
        }
    }
    // ASCII PLY has no spelling for NaN: the number does not parse.
    let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                property float z\nend_header\n0 0 0\n1 0 nan\n0 1 0\n";
    let e = read_error(&dir, "nan-ascii.ply", text.as_bytes());
    assert_format(&e, "nan-ascii.ply", &["vertex"]);
    for (name, text) in [
        ("nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n"),
        ("inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1 inf\nf 1 2 3\n"),
    ] {
        let e = read_error(&dir, name, text.as_bytes());
        assert_format(&e, name, &["non-finite"]);
    }
}

#[test]
fn malformed_headers() {
    let dir = temp_dir("header");
    let cases: [(&str, &str); 8] = [
        ("magic.ply", "plx\nformat ascii 1.0\nend_header\n"),
        (
            "format.ply",
            "ply\nformat ebcdic 1.0\nelement vertex 0\nend_header\n",
        ),
        (
            "noformat.ply",
            "ply\nelement vertex 1\nproperty float x\nend_header\n0\n",
        ),
        (
            "type.ply",
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty int128 x\nend_header\n0\n",
        ),
        (
            "keyword.ply",
            "ply\nformat ascii 1.0\nelemnt vertex 1\nproperty float x\nend_header\n0\n",
        ),
        (
            "orphan.ply",
            "ply\nformat ascii 1.0\nproperty float x\nelement vertex 1\nend_header\n0\n",
        ),
        (
            "count.ply",
            "ply\nformat ascii 1.0\nelement vertex -3\nproperty float x\nend_header\n",
        ),
        (
            "noend.ply",
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n",
        ),
    ];
    for (name, text) in cases {
        let e = read_error(&dir, name, text.as_bytes());
        assert_format(&e, name, &["header"]);
    }
}

#[test]
fn missing_vertex_element_or_coordinate() {
    let dir = temp_dir("no-vertex");
    let text = "ply\nformat ascii 1.0\nelement point 1\nproperty float x\nproperty float y\n\
                property float z\nend_header\n0 0 0\n";
    let e = read_error(&dir, "point.ply", text.as_bytes());
    assert_format(&e, "point.ply", &["no 'vertex' element"]);
    let text = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
                end_header\n0 0\n";
    let e = read_error(&dir, "noz.ply", text.as_bytes());
    assert_format(&e, "noz.ply", &["'z'"]);
    let text = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
                property list uchar float z\nend_header\n0 0 1 0\n";
    let e = read_error(&dir, "listz.ply", text.as_bytes());
    assert_format(&e, "listz.ply", &["'z'", "list"]);
}

#[test]
fn bad_face_lists() {
    let dir = temp_dir("face-lists");
    let header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                  property float z\n";
    let vertices = "0 0 0\n1 0 0\n0 1 0\n";
    let cases = [
        (
            "float-list.ply",
            "property list uchar float vertex_indices\n",
            "integers",
        ),
        (
            "scalar.ply",
            "property int vertex_indices\n",
            "expected a list",
        ),
        ("nolist.ply", "property int flags\n", "no 'vertex_indices'"),
        (
            "both.ply",
            "property list uchar int vertex_indices\nproperty list uchar int vertex_index\n",
            "both",
        ),
    ];
    for (name, property, needle) in cases {
        let text = format!("{header}element face 1\n{property}end_header\n{vertices}3 0 1 2\n");
        let e = read_error(&dir, name, text.as_bytes());
        assert_format(&e, name, &[needle]);
    }
    // A negative list length (signed count type) in binary, on both routes.
    for general in [false, true] {
        let mut b = PlyBuilder::new(Enc::Le)
            .element("vertex", 3)
            .property("float", "x")
            .property("float", "y")
            .property("float", "z")
            .element("face", 1)
            .list_property("char", "int", "vertex_indices");
        if general {
            b = b.property("uchar", "flags");
        }
        for p in [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
            for c in p {
                b.value("float", c);
            }
        }
        b.value("char", -1.0).value("int", 0.0).value("int", 1.0);
        let name = format!("negative-count-{general}.ply");
        let e = read_error(&dir, &name, &b.bytes());
        assert_format(&e, &name, &["face"]);
    }
}

#[test]
fn malformed_ascii_data() {
    let dir = temp_dir("ascii-data");
    let header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                  property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
                  end_header\n";
    for (name, body) in [
        ("word.ply", "0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n"),
        ("short-line.ply", "0 0 0\n1 0\n0 1 0\n3 0 1 2\n"),
        ("short-list.ply", "0 0 0\n1 0 0\n0 1 0\n3 0 1\n"),
    ] {
        let e = read_error(&dir, name, format!("{header}{body}").as_bytes());
        assert_format(&e, name, &["malformed"]);
    }
}

#[test]
fn malformed_obj() {
    let dir = temp_dir("obj");
    // Bytes that are not UTF-8 in a number (a Latin-1 comment is read: see
    // io_encodings.rs).
    let e = read_error(
        &dir,
        "latin1.obj",
        b"v 0 0 0\nv 1 0 0\nv 0 1\xe9 0\n# caf\xe9\nf 1 2 3\n",
    );
    assert_format(&e, "latin1.obj", &["line 3"]);
    let e = read_error(&dir, "short.obj", b"v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n");
    assert!(matches!(e, Error::Format { .. }), "{e:?}");
    let e = read_error(&dir, "word.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 two 3\n");
    assert_format(&e, "word.obj", &["line 4", "'two'"]);
    let e = read_error(&dir, "zero.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
    assert_format(&e, "zero.obj", &["line 4", "index 0"]);
}

/// A line ending in `\\` goes on on the next (the OBJ format's continuation, which
/// exporters write for long polygons; OpenMesh 1.2.1 reads only the first part): a
/// hexagon written over three lines, with CRLF line ends and white space after a `\\`,
/// reads as the hexagon on one line, and errors after it still name the file's line.
#[test]
fn obj_lines_continued_with_a_backslash() {
    let vertices = "v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 2 0\nv -1 1 0\n";
    let one_line = format!("{vertices}f 1 2 3 4 5 6\n");
    let continued = format!("{vertices}f 1 2 \\\n3 4 \\  \n5 6\n").replace('\n', "\r\n");
    let read = |text: &str| {
        io::read_obj_from_bytes(text.as_bytes(), Path::new("x.obj"))
            .unwrap()
            .0
    };
    let (a, b) = (read(&one_line), read(&continued));
    assert_eq!(b.n_faces(), 4, "the hexagon fanned into four triangles");
    let triangles = |m: &halfedge::Mesh| -> Vec<_> {
        m.faces()
            .map(|f| m.triangle(f).map(|v| m.vertex_index(v)))
            .collect()
    };
    assert_eq!(triangles(&a), triangles(&b));
    // The continued face is lines 7–9; the bad face after it is line 10.
    let dir = temp_dir("continued");
    let bad = format!("{vertices}f 1 2 \\\n3 4 \\\n5 6\nf 1 2 x\n");
    let e = read_error(&dir, "continued.obj", bad.as_bytes());
    assert_format(&e, "continued.obj", &["line 10", "'x'"]);
    // A `\\` on the last line continues into nothing.
    let last = format!("{vertices}f 4 5 6 \\");
    assert_eq!(read(&last).n_faces(), 1);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn truncated_large_binary_ply_across_read_chunks() {
    // Files are streamed in chunks of 1 MiB: cut a 2.4 MB binary PLY around chunk borders.
    let (horse, _) = io::read(testkit::shared_meshes().join("horse.ply")).unwrap();
    truncated_across_chunks(&horse, "truncated-large");
}

#[test]
fn truncated_generated_binary_ply_across_read_chunks() {
    // A generated mesh of about 3 MB in binary PLY.
    let big = halfedge::generators::disjoint_union(&[
        &halfedge::generators::icosphere(6),
        &halfedge::generators::icosphere(5),
    ])
    .unwrap();
    truncated_across_chunks(&big, "truncated-generated");
}

/// Writes `mesh` as binary PLY (over 2 MiB), reads it back whole, then cut around the
/// 1 MiB chunk borders: every cut is a "truncated" format error.
fn truncated_across_chunks(mesh: &halfedge::Mesh, tag: &str) {
    let mut bytes = Vec::new();
    io::write_ply_to(&mut bytes, mesh, io::PlyFormat::BinaryLittleEndian).unwrap();
    assert!(bytes.len() > 2 << 20);
    let dir = temp_dir(tag);
    let whole = dir.join("whole.ply");
    std::fs::write(&whole, &bytes).unwrap();
    let (back, _) = io::read(&whole).unwrap();
    assert_eq!(back.positions(), mesh.positions());
    for len in [
        (1 << 20) - 1,
        1 << 20,
        (1 << 20) + 1,
        (2 << 20) + 7,
        bytes.len() - 1,
    ] {
        let name = format!("cut{len}.ply");
        let e = read_error(&dir, &name, &bytes[..len]);
        assert_format(&e, &name, &["truncated"]);
    }
}
