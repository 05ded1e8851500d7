//! The loaders' mutation suite (issue 14): truncated, corrupted and hostile files never
//! make a reader panic. A reader either gives a valid mesh with finite positions, or an
//! error that names the file and the place (the line of an OBJ file or of a PLY header or
//! ASCII payload, the element or the byte of a binary PLY payload).
//!
//! The same for OFF, STL (ASCII and binary) and gzip-compressed files (an error of a
//! binary STL names its triangle and byte, one of an ASCII STL or OFF file its line, one
//! of gzip data the decompressed byte).
//!
//! Mutations: cuts, random bytes, garbage after a valid header, and token-level edits of
//! OBJ, ASCII PLY, OFF and ASCII STL text (numbers replaced by hostile ones: NaN,
//! infinities, huge, zero and negative indices, repeated indices; lines deleted, doubled
//! or swapped; element counts in PLY and OFF headers and triangle counts of binary STL
//! made huge). Seeds are fixed; `MULTIRES_HOSTILE_CASES` sets the
//! number of cases per test for a long run (and `MULTIRES_HOSTILE_SEED` another seed).

use std::path::Path;

use halfedge::generators;
use halfedge::io::{
    read_gz_from_bytes, read_obj_from_bytes, read_off_from_bytes, read_ply_from_bytes,
    read_stl_from_bytes, write_obj_to, write_off_to, write_ply_to, write_stl_to, PlyFormat,
    StlFormat,
};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use testkit::ply::{square, Enc};

fn config(default_cases: u32) -> Config {
    Config {
        cases: std::env::var("MULTIRES_HOSTILE_CASES")
            .ok()
            .and_then(|c| c.parse().ok())
            .unwrap_or(default_cases),
        rng_seed: RngSeed::Fixed(
            std::env::var("MULTIRES_HOSTILE_SEED")
                .ok()
                .and_then(|c| c.parse().ok())
                .unwrap_or(0x696f_5f66_757a_7a31),
        ),
        failure_persistence: None,
        ..Config::default()
    }
}

/// The formats the suite reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Obj,
    Ply,
    Off,
    Stl,
    /// Gzip-compressed OFF.
    OffGz,
    /// Gzip-compressed STL.
    StlGz,
}

const KINDS: [Kind; 6] = [
    Kind::Obj,
    Kind::Ply,
    Kind::Off,
    Kind::Stl,
    Kind::OffGz,
    Kind::StlGz,
];

fn gzip(bytes: &[u8]) -> Vec<u8> {
    use std::io::Write;
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    e.write_all(bytes).unwrap();
    e.finish().unwrap()
}

fn off_text() -> String {
    let mut bytes = Vec::new();
    write_off_to(&mut bytes, &generators::icosphere(1)).unwrap();
    String::from_utf8(bytes).unwrap()
}

fn stl(format: StlFormat) -> Vec<u8> {
    let mut bytes = Vec::new();
    write_stl_to(&mut bytes, &generators::icosphere(1), format).unwrap();
    bytes
}

fn valid_files() -> Vec<(Kind, Vec<u8>)> {
    let mesh = generators::icosphere(1);
    let mut files = Vec::new();
    for format in [
        PlyFormat::Ascii,
        PlyFormat::BinaryLittleEndian,
        PlyFormat::BinaryBigEndian,
    ] {
        let mut bytes = Vec::new();
        write_ply_to(&mut bytes, &mesh, format).unwrap();
        files.push((Kind::Ply, bytes));
    }
    for enc in [Enc::Ascii, Enc::Le, Enc::Be] {
        files.push((Kind::Ply, square(enc).bytes()));
    }
    files.push((Kind::Obj, obj_text().into_bytes()));
    files.push((Kind::Off, off_text().into_bytes()));
    // COFF with vertex and face colours, comments, a polygon.
    files.push((
        Kind::Off,
        b"COFF # colours\n5 3 0\n0 0 0 255 0 0\n1 0 0 0 255 0 255\n1 1 0 1 1 1\n0 1 0 1 1 1\n\
          2 0 0 9 9 9\n4 0 1 2 3 255 0 0\n3 1 4 2 0.5 0.5 0.5 1\n# end\n3 0 0 1\n"
            .to_vec(),
    ));
    files.push((Kind::Stl, stl(StlFormat::Binary)));
    files.push((Kind::Stl, stl(StlFormat::Ascii)));
    files.push((Kind::OffGz, gzip(off_text().as_bytes())));
    files.push((Kind::StlGz, gzip(&stl(StlFormat::Binary))));
    files
}

/// An OBJ file with what readers meet: comments, groups, normals and texture
/// coordinates, quads and polygons, `v/vt/vn` and negative indices.
fn obj_text() -> String {
    let mesh = generators::icosphere(1);
    let mut obj = Vec::new();
    write_obj_to(&mut obj, &mesh).unwrap();
    let mut text = String::from_utf8(obj).unwrap();
    text.push_str(
        "o extra\nv 3 0 0\nv 4 0 0\nv 4 1 0\nv 3 1 0\nv 5 0 0\nvt 0 0\nvt 1 0\nvn 0 0 1\n\
         g quads\nf -5/1/1 -4/2/1 -3//1 -2\nf -4 -1 -3\nusemtl none\nf 43 44 45 46 47\n",
    );
    text
}

/// True when an error message says where: `line N`, `byte N`, or an element and its
/// number (`vertex 3`, `face 12`, or any element the message names as `element 'name'`).
fn has_place(text: &str) -> bool {
    let words: Vec<&str> = text
        .split(|c: char| c.is_whitespace() || ":(),".contains(c))
        .collect();
    words.windows(2).any(|w| {
        let word = w[0].to_lowercase();
        let named = ["line", "byte", "vertex", "face", "tristrips"].contains(&word.as_str())
            || text.contains(&format!("element '{}'", w[0]));
        named && w[1].chars().next().is_some_and(|c| c.is_ascii_digit())
    })
}

fn read(kind: Kind, bytes: &[u8]) -> Result<(), TestCaseError> {
    let name = match kind {
        Kind::Obj => "fuzz.obj",
        Kind::Ply => "fuzz.ply",
        Kind::Off => "fuzz.off",
        Kind::Stl => "fuzz.stl",
        Kind::OffGz => "fuzz.off.gz",
        Kind::StlGz => "fuzz.stl.gz",
    };
    let path = Path::new(name);
    let result = match kind {
        Kind::Obj => read_obj_from_bytes(bytes, path),
        Kind::Ply => read_ply_from_bytes(bytes, path),
        Kind::Off => read_off_from_bytes(bytes, path),
        Kind::Stl => read_stl_from_bytes(bytes, path),
        Kind::OffGz | Kind::StlGz => read_gz_from_bytes(bytes, path),
    };
    match result {
        Ok((mesh, _)) => {
            mesh.check()
                .map_err(|e| TestCaseError::fail(format!("invalid mesh read: {e}")))?;
            prop_assert!(
                mesh.vertices().all(|v| mesh.position(v).is_finite()),
                "a non-finite position was read"
            );
        }
        Err(e) => {
            let text = e.to_string();
            prop_assert!(
                matches!(e, halfedge::Error::Format { .. }),
                "not a format error: {text}"
            );
            prop_assert!(
                text.starts_with(name),
                "the error does not name the file: {text}"
            );
            prop_assert!(has_place(&text), "the error does not say where: {text}");
        }
    }
    Ok(())
}

/// Tokens a hostile edit puts in place of a number.
const HOSTILE: &[&str] = &[
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e999",
    "-1e999",
    "1e308",
    "-1e308",
    "0",
    "-1",
    "-2",
    "-99999999999",
    "4294967295",
    "4294967296",
    "18446744073709551615",
    "99999999999999999999999",
    "1.5",
    "",
    "x",
    "1/2/3",
    "1//",
    "//1",
    "1/-1",
    "0x10",
    "+3",
    "3 3",
    "1 1 1 1",
];

/// Applies token-level edits to text: `(line, token, what)` picks a line, a token in it,
/// and an edit (replace the token by a hostile one, delete or double the line, swap it
/// with another, repeat a token, append a face line).
fn edit_text(text: &str, edits: &[(usize, usize, usize)]) -> Vec<u8> {
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    for &(l, t, what) in edits {
        if lines.is_empty() {
            break;
        }
        let l = l % lines.len();
        let mut tokens: Vec<String> = lines[l].split(' ').map(str::to_owned).collect();
        let t = t % tokens.len();
        match what % 8 {
            0..=2 => tokens[t] = HOSTILE[what / 8 % HOSTILE.len()].to_owned(),
            3 => {
                lines.remove(l);
                continue;
            }
            4 => {
                let copy = lines[l].clone();
                lines.insert(l, copy);
                continue;
            }
            5 => {
                let other = what / 8 % lines.len();
                lines.swap(l, other);
                continue;
            }
            6 => {
                let copy = tokens[t].clone();
                tokens.insert(t, copy);
            }
            _ => {
                let k = 1 + what / 8 % 40;
                lines.push(format!("f {} {} {} {}", k, k + 1, k, k + 2));
                continue;
            }
        }
        lines[l] = tokens.join(" ");
    }
    let mut out = lines.join("\n").into_bytes();
    out.push(b'\n');
    out
}

proptest! {
    #![proptest_config(config(300))]

    #[test]
    fn truncated_files_do_not_panic(file in any::<prop::sample::Index>(), cut in 0.0f64..1.0) {
        let files = valid_files();
        let (kind, bytes) = &files[file.index(files.len())];
        let len = (cut * bytes.len() as f64) as usize;
        read(*kind, &bytes[..len])?;
    }

    #[test]
    fn corrupted_files_do_not_panic(
        file in any::<prop::sample::Index>(),
        edits in proptest::collection::vec((0.0f64..1.0, any::<u8>()), 1..8),
    ) {
        let files = valid_files();
        let (kind, bytes) = &files[file.index(files.len())];
        let mut bytes = bytes.clone();
        for (at, value) in edits {
            let i = ((at * bytes.len() as f64) as usize).min(bytes.len() - 1);
            bytes[i] = value;
        }
        read(*kind, &bytes)?;
    }

    #[test]
    fn garbage_does_not_panic(kind in 0usize..KINDS.len(), bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        read(KINDS[kind], &bytes)?;
        let mut with_header = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n".to_vec();
        with_header.extend(&bytes);
        read(Kind::Ply, &with_header)?;
        // Garbage after a binary STL header and count, or an OFF header.
        let mut stl = vec![b'x'; 80];
        stl.extend(((bytes.len() / 50) as u32).to_le_bytes());
        stl.extend(&bytes);
        read(Kind::Stl, &stl)?;
        let mut off = b"OFF\n3 1 0\n".to_vec();
        off.extend(&bytes);
        read(Kind::Off, &off)?;
        read(Kind::OffGz, &gzip(&off))?;
    }

    #[test]
    fn hostile_edits_of_obj_text_are_read_or_refused_with_their_line(
        edits in proptest::collection::vec((any::<usize>(), any::<usize>(), any::<usize>()), 1..6),
    ) {
        read(Kind::Obj, &edit_text(&obj_text(), &edits))?;
    }

    #[test]
    fn hostile_edits_of_ascii_ply_are_read_or_refused_with_their_place(
        edits in proptest::collection::vec((any::<usize>(), any::<usize>(), any::<usize>()), 1..6),
    ) {
        let mut bytes = Vec::new();
        write_ply_to(&mut bytes, &generators::icosphere(1), PlyFormat::Ascii).unwrap();
        read(Kind::Ply, &edit_text(&String::from_utf8(bytes).unwrap(), &edits))?;
    }

    #[test]
    fn hostile_edits_of_off_text_are_read_or_refused_with_their_line(
        edits in proptest::collection::vec((any::<usize>(), any::<usize>(), any::<usize>()), 1..6),
        coff in any::<bool>(),
    ) {
        let text = if coff {
            String::from_utf8(valid_files().into_iter().find(|(_, b)| b.starts_with(b"COFF")).unwrap().1).unwrap()
        } else {
            off_text()
        };
        read(Kind::Off, &edit_text(&text, &edits))?;
    }

    #[test]
    fn hostile_edits_of_ascii_stl_are_read_or_refused_with_their_line(
        edits in proptest::collection::vec((any::<usize>(), any::<usize>(), any::<usize>()), 1..6),
    ) {
        let text = String::from_utf8(stl(StlFormat::Ascii)).unwrap();
        read(Kind::Stl, &edit_text(&text, &edits))?;
    }

    /// Huge counts in an OFF header or a binary STL never allocate what they announce.
    #[test]
    fn lying_off_and_stl_counts_are_refused(
        vertices in prop_oneof![Just(0u64), 0u64..100, Just(u64::from(u32::MAX)), Just(1u64 << 40), Just(u64::MAX)],
        faces in prop_oneof![0u64..100, Just(u64::from(u32::MAX)), Just(1u64 << 40), Just(u64::MAX)],
        triangles in prop_oneof![0u32..100, Just(u32::MAX), Just(1u32 << 31)],
    ) {
        let mesh = generators::icosphere(1);
        let text = off_text();
        let counts = format!("{} {} {}", mesh.n_vertices(), mesh.n_faces(), mesh.n_edges());
        let edited = text.replacen(&counts, &format!("{vertices} {faces} 0"), 1);
        read(Kind::Off, edited.as_bytes())?;
        let mut bytes = stl(StlFormat::Binary);
        bytes[80..84].copy_from_slice(&triangles.to_le_bytes());
        read(Kind::Stl, &bytes)?;
        read(Kind::StlGz, &gzip(&bytes))?;
    }

    /// Huge or negative element counts and list lengths in a header never allocate what
    /// they announce: the readers only keep what the payload really has.
    #[test]
    fn lying_element_counts_are_refused(
        vertices in prop_oneof![Just(0u64), 0u64..40, Just(u64::from(u32::MAX)), Just(1u64 << 40), Just(u64::MAX)],
        faces in prop_oneof![0u64..40, Just(u64::from(u32::MAX)), Just(1u64 << 40), Just(u64::MAX)],
        format in 0usize..3,
        list_count in prop_oneof![Just("uchar"), Just("int"), Just("uint"), Just("char")],
    ) {
        let mesh = generators::icosphere(1);
        let format = [PlyFormat::Ascii, PlyFormat::BinaryLittleEndian, PlyFormat::BinaryBigEndian][format];
        let mut bytes = Vec::new();
        write_ply_to(&mut bytes, &mesh, format).unwrap();
        let end = bytes.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
        let header = String::from_utf8(bytes[..end].to_vec()).unwrap();
        let header = header
            .replace(&format!("element vertex {}", mesh.n_vertices()), &format!("element vertex {vertices}"))
            .replace(&format!("element face {}", mesh.n_faces()), &format!("element face {faces}"))
            .replace("property list uchar", &format!("property list {list_count}"));
        let mut edited = header.into_bytes();
        edited.extend(&bytes[end..]);
        read(Kind::Ply, &edited)?;
    }
}

/// The oracle says what it should: the messages it must refuse are refused.
#[test]
fn the_place_oracle_tells_places_from_none() {
    assert!(has_place("x.obj: line 4: malformed face index 'two'"));
    assert!(has_place(
        "x.ply: truncated file: the payload ends in face 3 of 20"
    ));
    assert!(has_place("x.ply: Line 7: Couldn't parse line."));
    assert!(!has_place("x.obj: OBJ parse error: position parse error"));
    assert!(!has_place("x.ply: stream did not contain valid UTF-8"));
    assert!(!has_place("x.ply: the header has no 'vertex' element"));
}
