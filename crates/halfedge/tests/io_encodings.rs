//! Bytes that are not UTF-8 never refuse a readable mesh: names and comments in Latin-1
//! or Windows-1252 (as older exporters write them) read as their ASCII equivalents,
//! while such bytes inside numbers still give an error naming the line.

use std::path::Path;

use halfedge::io::{read_obj_from_bytes, read_off_from_bytes, read_ply_from_bytes};
use halfedge::{BuildReport, Error, Mesh};
use testkit::ply::{square, Enc};

fn summary(result: (Mesh, BuildReport)) -> (Vec<[u64; 3]>, Vec<[usize; 3]>, BuildReport) {
    let (mesh, report) = result;
    mesh.check().unwrap();
    let bits = mesh
        .vertices()
        .map(|v| mesh.position(v).to_array().map(f64::to_bits))
        .collect();
    let triangles = mesh
        .faces()
        .map(|f| mesh.triangle(f).map(|v| mesh.vertex_index(v)))
        .collect();
    (bits, triangles, report)
}

/// An OBJ file with names and comments in `encode`d text around plain ASCII geometry
/// (a quad and a triangle, a vertex no face uses, `v/vt/vn` indices).
fn obj(encode: impl Fn(&str) -> Vec<u8>) -> Vec<u8> {
    let mut out = Vec::new();
    for line in [
        "# Terraindæk — exported by Blender © 2020, Ærø",
        "mtllib terraindæk.mtl",
        "o Terraindæk",
        "v 0 0 0",
        "v 1 0 0",
        "v 1 1 0",
        "v 0 1 0",
        "v 2 0.5 0",
        "v 9 9 9",
        "vt 0 0",
        "vn 0 0 1",
        "g grüppe €",
        "usemtl Terraindæk",
        "s off",
        "f 1/1/1 2/1/1 3/1/1 4/1/1",
        "usemtl Bjørn",
        "# trekant",
        "f 2 5 3",
    ] {
        out.extend(encode(line));
        out.push(b'\n');
    }
    out
}

/// Latin-1 (ISO 8859-1) with `€` as Windows-1252 writes it (0x80).
fn latin1(text: &str) -> Vec<u8> {
    text.chars()
        .map(|c| match c {
            '€' => 0x80,
            '—' => 0x97,
            c if (c as u32) < 256 => c as u8,
            c => panic!("{c} is not Latin-1"),
        })
        .collect()
}

/// Every character outside ASCII replaced by `?`.
fn ascii(text: &str) -> Vec<u8> {
    text.chars()
        .map(|c| if c.is_ascii() { c as u8 } else { b'?' })
        .collect()
}

#[test]
fn latin1_names_and_comments_in_obj_read_as_their_ascii_equivalent() {
    let path = Path::new("terraindæk.obj");
    let bytes = obj(latin1);
    assert!(
        std::str::from_utf8(&bytes).is_err(),
        "the test file is not UTF-8"
    );
    let read = read_obj_from_bytes(&bytes, path).unwrap_or_else(|e| panic!("{e}"));
    let expected = read_obj_from_bytes(&obj(ascii), path).unwrap();
    let utf8 = read_obj_from_bytes(&obj(|t| t.as_bytes().to_vec()), path).unwrap();
    let (read, expected, utf8) = (summary(read), summary(expected), summary(utf8));
    assert_eq!(read, expected);
    assert_eq!(read, utf8);
    // The geometry, for the record: 6 vertices in file order, the quad fanned.
    assert_eq!(read.1, [[0, 1, 2], [0, 2, 3], [1, 4, 2]]);
    assert_eq!(read.2.unreferenced_vertices, 1);
}

fn format_error(result: Result<(Mesh, BuildReport), Error>) -> String {
    match result {
        Err(e @ Error::Format { .. }) => e.to_string(),
        other => panic!("expected a format error, got {other:?}"),
    }
}

#[test]
fn bytes_that_are_not_utf8_inside_numbers_give_located_errors() {
    let path = Path::new("x.obj");
    // In a coordinate, a face index, and a coordinate on a line after Latin-1 names.
    let cases: [(&[u8], &str); 3] = [
        (b"v 0 0 0\nv 1 0\xe9 0\nv 0 1 0\nf 1 2 3\n", "line 2"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\xe9 3\n", "line 4"),
        (
            b"o caf\xe9\n# \xff\xfe\nv 0 0 0\nv 1 0 0\nv \xb10 1 0\nf 1 2 3\n",
            "line 5",
        ),
    ];
    for (bytes, line) in cases {
        let message = format_error(read_obj_from_bytes(bytes, path));
        assert!(message.starts_with("x.obj: "), "{message}");
        assert!(message.contains(line), "{message} lacks {line}");
    }
    let message = format_error(read_off_from_bytes(
        b"OFF # caf\xe9\n3 1 0\n0 0 0\n1 0\xe9 0\n0 1 0\n3 0 1 2\n",
        Path::new("x.off"),
    ));
    assert!(message.contains("line 4"), "{message}");
}

/// ASCII PLY headers with a Latin-1 comment: the PLY reader hands header lines to
/// `ply-rs-bw`, which reads them as UTF-8 `String`s.
#[test]
fn a_latin1_comment_in_a_ply_header_is_read() {
    for enc in [Enc::Ascii, Enc::Le] {
        let plain = square(enc).bytes();
        let at = plain.windows(7).position(|w| w == b"element").unwrap();
        let mut latin1 = plain[..at].to_vec();
        latin1.extend(b"comment Terraind\xe6k\n");
        latin1.extend(&plain[at..]);
        let read = read_ply_from_bytes(&latin1, Path::new("x.ply"))
            .unwrap_or_else(|e| panic!("{enc:?}: {e}"));
        let expected = read_ply_from_bytes(&plain, Path::new("x.ply")).unwrap();
        assert_eq!(summary(read), summary(expected));
    }
}
