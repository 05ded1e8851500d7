//! The plain OBJ files most meshes come as, read in one pass without `tobj`.
//!
//! The reader of [`super::obj`] hands the file to `tobj` after a scan that keeps every
//! vertex in file order (`tobj` renumbers them otherwise) and names the line of any error:
//! three passes over the text and a copy of it. Most files need none of that care: ASCII
//! text with `v x y z` lines and faces of positive or negative indices (`v`, `v/vt`,
//! `v//vn`, `v/vt/vn`), comments, normals, texture coordinates, groups and materials. This
//! reader takes exactly those, in one pass, and gives the same mesh bit for bit: the same
//! numbers (`str::parse::<f64>`, which `tobj` uses too), the same polygons with their
//! repeated indices dropped, the same builder. Anything else — a `w` or colours on a `v`
//! line, a `\` (a continued line), bytes beyond ASCII or a vertical tab, an index out of
//! range or malformed, a face of fewer than three vertices — makes it answer `None`, and
//! the careful reader takes the file (and names the line of its error, if it is one).

use glam::DVec3;

use crate::build::BuildReport;
use crate::mesh::Mesh;

/// Counts and largest references of the `vt` / `vn` records, checked as `tobj` checks
/// them: only when the file has such records at all.
#[derive(Default)]
struct Attribute {
    count: usize,
    /// The largest 0-based index referred to (`None`: none yet).
    largest: Option<usize>,
}

impl Attribute {
    /// Notes a reference `text` (empty: none), relative ones resolved against the
    /// records read so far; `None` for a malformed or impossible one.
    fn refer(&mut self, text: &str) -> Option<()> {
        if text.is_empty() {
            return Some(());
        }
        let index: i64 = text.parse().ok()?;
        let resolved = match index {
            0 => return None,
            i if i > 0 => i - 1,
            i => i64::try_from(self.count).ok()? + i,
        };
        let resolved = usize::try_from(resolved).ok()?;
        self.largest = Some(self.largest.map_or(resolved, |l| l.max(resolved)));
        Some(())
    }
    /// True when every reference names a record (or there are no records, which `tobj`
    /// does not check against).
    fn fits(&self) -> bool {
        self.count == 0 || self.largest.is_none_or(|l| l < self.count)
    }
}

/// A face token's vertex index (the digits before its first `/`, with an optional sign,
/// as `str::parse::<i64>` reads them) and what follows that `/` (empty: no `/`). `None`
/// where `parse` would fail, and for `-9223372036854775808` (which the careful reader
/// then takes). Digits are read by hand: `split_once` and `parse` were a fifth of this
/// reader on the bunny.
#[inline]
fn split_index(token: &str) -> Option<(i64, &str)> {
    let bytes = token.as_bytes();
    let (negative, start) = match bytes.first()? {
        b'-' => (true, 1),
        b'+' => (false, 1),
        _ => (false, 0),
    };
    let mut value: i64 = 0;
    let mut i = start;
    while let Some(&c) = bytes.get(i) {
        if c == b'/' {
            break;
        }
        let digit = c.wrapping_sub(b'0');
        if digit > 9 {
            return None;
        }
        value = value.checked_mul(10)?.checked_add(i64::from(digit))?;
        i += 1;
    }
    if i == start {
        return None;
    }
    let rest = token.get(i + 1..).unwrap_or("");
    Some((if negative { -value } else { value }, rest))
}

/// True when every byte is ASCII, none is a `\\` nor a vertical tab: one pass, in
/// blocks without an early exit so that it compiles to vector instructions.
fn plain_bytes(bytes: &[u8]) -> bool {
    let bad = |b: u8| u8::from(b >= 0x80) | u8::from(b == b'\\') | u8::from(b == 0x0B);
    let mut blocks = bytes.chunks_exact(64);
    for block in &mut blocks {
        if block.iter().fold(0u8, |acc, &b| acc | bad(b)) != 0 {
            return false;
        }
    }
    blocks.remainder().iter().all(|&b| bad(b) == 0)
}

/// Reads `bytes` when it is a plain OBJ file (see the module docs); `None` hands it to the
/// careful reader.
pub(super) fn read_plain_obj(bytes: &[u8]) -> Option<(Mesh, BuildReport)> {
    // ASCII only and no vertical tab, so that white space is what
    // `split_ascii_whitespace` splits at (tobj splits at `char::is_whitespace`, which
    // takes the vertical tab too); no `\` anywhere, so that no line continues.
    if !plain_bytes(bytes) {
        return None;
    }
    let text = std::str::from_utf8(bytes).ok()?;
    let mut positions: Vec<DVec3> = Vec::with_capacity(bytes.len() / 80);
    // Polygons as one list of 0-based indices and their ends.
    let mut indices: Vec<u32> = Vec::with_capacity(bytes.len() / 12);
    let mut ends: Vec<usize> = Vec::with_capacity(bytes.len() / 40);
    let mut largest_position = 0u64;
    let (mut texcoords, mut normals) = (Attribute::default(), Attribute::default());
    for line in text.lines() {
        let mut tokens = line.split_ascii_whitespace();
        match tokens.next() {
            Some("v") => {
                let mut p = [0.0f64; 3];
                for x in &mut p {
                    *x = tokens.next()?.parse().ok()?;
                }
                if tokens.next().is_some() {
                    return None;
                }
                positions.push(DVec3::from_array(p));
            }
            Some("f") => {
                let start = indices.len();
                for token in tokens {
                    // 1-based, as `obj::face_index` resolves it; not that function, whose
                    // error messages (a `Result<u64, String>` and a second split) cost 10 %
                    // of this reader on the bunny.
                    let (index, rest) = split_index(token)?;
                    let resolved = match index {
                        0 => return None,
                        i if i > 0 => i as u64,
                        i => u64::try_from(positions.len() as i64 + i + 1).ok()?,
                    };
                    if resolved == 0 || resolved > u64::from(u32::MAX) {
                        return None;
                    }
                    largest_position = largest_position.max(resolved);
                    if !rest.is_empty() {
                        let mut parts = rest.split('/');
                        texcoords.refer(parts.next().unwrap_or(""))?;
                        normals.refer(parts.next().unwrap_or(""))?;
                        if parts.next().is_some() {
                            return None;
                        }
                    }
                    indices.push((resolved - 1) as u32);
                }
                if indices.len() - start < 3 {
                    return None;
                }
                ends.push(indices.len());
            }
            Some("vt") => {
                for _ in 0..2 {
                    tokens.next()?.parse::<f64>().ok()?;
                }
                texcoords.count += 1;
            }
            Some("vn") => {
                for _ in 0..3 {
                    tokens.next()?.parse::<f64>().ok()?;
                }
                normals.count += 1;
            }
            // Comments, groups, objects, materials, smoothing groups, polylines and
            // anything else `tobj` ignores.
            _ => {}
        }
    }
    if positions.is_empty()
        || largest_position > positions.len() as u64
        || !texcoords.fits()
        || !normals.fits()
    {
        return None;
    }
    if indices.len() == 3 * ends.len() {
        // Triangles only: a triangle that names a vertex twice is dropped by the builder
        // as it is once its repeat is dropped (fewer than three vertices).
        return Mesh::from_polygons(&positions, indices.chunks_exact(3)).ok();
    }
    let starts = std::iter::once(0).chain(ends.iter().copied());
    let faces = starts
        .zip(ends.iter().copied())
        .map(|(a, b)| super::obj::without_repeats(&indices[a..b]));
    Mesh::from_polygons(&positions, faces).ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::path::Path;

    /// Everything a reader gives, as plain values: positions bit for bit, each face slot's
    /// corners, and the build report.
    type Read = (Vec<[u64; 3]>, Vec<(usize, [usize; 3])>, BuildReport);

    fn plain((mesh, report): (Mesh, BuildReport)) -> Read {
        let positions = mesh
            .positions()
            .iter()
            .map(|p| p.to_array().map(f64::to_bits))
            .collect();
        let faces = mesh
            .faces()
            .map(|f| {
                let corners = mesh.triangle(f).map(|v| mesh.vertex_index(v));
                (mesh.face_index(f), corners)
            })
            .collect();
        (positions, faces, report)
    }

    fn careful(text: &[u8]) -> Option<Read> {
        super::super::obj::read_obj_through_tobj(text, Path::new("t.obj"))
            .ok()
            .map(plain)
    }

    /// Files the one-pass reader must take, each read as tobj's path reads it.
    #[test]
    fn plain_files_are_read_in_one_pass_as_tobj_reads_them() {
        let files = [
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0.5\nf 1 2 3\nf 2 4 3\n",
            // Comments, groups, materials, smoothing, polylines, CRLF, blank lines.
            "# made by hand\r\nmtllib a.mtl\r\no thing\r\nv 0 0 0\r\nv 1 0 0\r\n\r\nv 0 1 0\r\nv 1 1 1e-3\r\ng part\r\nusemtl red\r\ns 1\r\nf 1 2 3\r\nl 1 4\r\nf 2 4 3\r\n",
            // Quads and a pentagon, negative indices, a forward reference.
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf -4 -3 -2 -1\nf 3 4 6\nv 0.5 2 0\nv -1 1 0\nv 2 1 0\nf 4 3 5 7 6\n",
            // Texture coordinates and normals in every face form.
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1 0.5\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\nf 2//1 4//1 3//1\nf 2/2 4/-1 3/3\n",
            // A face naming a vertex twice keeps the first mention; numbers as C prints them.
            "v -1.5e+2 .25 3.\nv 1E-7 -0 +4\nv 0 1 0\nv 1 1 1\nf 1 2 4 2 3\n",
            // Tabs and form feeds split as spaces do.
            "v 0\t0\x0c0\nv\t1 0 0\nv 0 1 0\nf 1\x0c2 3\n",
            // A triangle that names a vertex twice, in a file of triangles.
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 1 2\nf 1 2 3\nf 2 4 3\n",
            // References to texture coordinates the file does not have (tobj ignores them).
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/7 2/7 3/7\n",
        ];
        for (k, file) in files.iter().enumerate() {
            let fast = read_plain_obj(file.as_bytes()).map(plain);
            assert!(fast.is_some(), "file {k} was not taken");
            assert_eq!(fast, careful(file.as_bytes()), "file {k}");
        }
    }

    /// Files the one-pass reader must leave to tobj's path (it reads some, refuses others
    /// with the line).
    #[test]
    fn other_files_go_to_tobj() {
        let files: [&[u8]; 13] = [
            b"v 0\x0b0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
            b"v 0 0 0 2\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
            b"v 0 0 0 1 0 0\nv 1 0 0 1 0 0\nv 0 1 0 1 0 0\nf 1 2 3\n",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 \\\n 3\n",
            b"# caf\xe9\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/2 2/1 3/1\n",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\nf 1 2 3\n",
            b"v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1/1 2 3\n",
            b"# nothing\n",
        ];
        for (k, file) in files.iter().enumerate() {
            assert!(read_plain_obj(file).is_none(), "file {k} was taken");
        }
    }

    /// One line of an OBJ-like file, from a grammar that mostly makes what the one-pass
    /// reader takes (so that it takes about a third of the files) with now and then what
    /// it must leave alone.
    fn line() -> impl Strategy<Value = String> {
        let number = prop_oneof![
            20 => (-20i32..20).prop_map(|i| i.to_string()),
            20 => (-2.0f64..2.0).prop_map(|x| format!("{x}")),
            2 => Just("1e-3".to_owned()),
            1 => Just("nan".to_owned()),
        ];
        let index = prop_oneof![
            12 => (1i32..7).prop_map(|i| i.to_string()),
            4 => (-4i32..0).prop_map(|i| i.to_string()),
            1 => Just("0".to_owned()),
            2 => ((1i32..7), (-2i32..3)).prop_map(|(i, t)| format!("{i}/{t}")),
            2 => ((-3i32..7), (1i32..3)).prop_map(|(i, n)| format!("{i}//{n}")),
            2 => ((1i32..7), (1i32..3), (1i32..3)).prop_map(|(i, t, n)| format!("{i}/{t}/{n}")),
        ];
        prop_oneof![
            30 => prop::collection::vec(number.clone(), 3..=3).prop_map(|v| format!("v {}", v.join(" "))),
            1 => prop::collection::vec(number.clone(), 4..=6).prop_map(|v| format!("v {}", v.join(" "))),
            30 => prop::collection::vec(index, 3..6).prop_map(|v| format!("f {}", v.join(" "))),
            1 => Just("f 1 2".to_owned()),
            4 => prop::collection::vec(number.clone(), 2..=3).prop_map(|v| format!("vt {}", v.join(" "))),
            4 => prop::collection::vec(number, 3..=3).prop_map(|v| format!("vn {}", v.join(" "))),
            4 => prop_oneof![Just("# c".to_owned()), Just("g a".to_owned()), Just("s off".to_owned()),
                 Just("l 1 2".to_owned()), Just(String::new()), Just("usemtl m".to_owned())],
            1 => Just("f 1 2 \\".to_owned()),
        ]
    }

    /// The hand-read index is `str::parse::<i64>`'s reading of the text before the first
    /// `/`, or nothing where `parse` fails (and for `i64::MIN`).
    fn agrees_with_parse(token: &str) {
        let (first, rest) = token.split_once('/').unwrap_or((token, ""));
        match (split_index(token), first.parse::<i64>()) {
            (Some((index, after)), Ok(parsed)) => {
                assert_eq!((index, after), (parsed, rest), "{token:?}");
            }
            (None, Ok(parsed)) => assert_eq!(parsed, i64::MIN, "{token:?}"),
            (Some(read), Err(_)) => panic!("{token:?} read as {read:?}, parse refuses it"),
            (None, Err(_)) => {}
        }
    }

    #[test]
    fn face_indices_are_read_as_parse_reads_them() {
        for token in [
            "",
            "+",
            "-",
            "/",
            "0",
            "-0",
            "+7",
            "007",
            "12a",
            "1/2",
            "1//3",
            "1/",
            "-2/-1/-1",
            "+-1",
            "--1",
            "1-",
            " 1",
            "9223372036854775807",
            "9223372036854775808",
            "-9223372036854775808",
            "-9223372036854775809",
            "99999999999999999999/1",
        ] {
            agrees_with_parse(token);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2048))]
        /// Any short token of signs, digits, slashes and letters.
        #[test]
        fn any_face_token_is_read_as_parse_reads_it(token in "[-+0-9/a ]{0,24}") {
            agrees_with_parse(&token);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]
        /// Whatever the one-pass reader takes, tobj's path reads the same, bit for bit.
        #[test]
        fn what_the_one_pass_reader_takes_tobj_reads_the_same(
            vertices in prop::collection::vec(prop::array::uniform3(-9i32..9), 3..7),
            lines in prop::collection::vec(line(), 0..12),
        ) {
            let mut text = String::new();
            for [x, y, z] in vertices {
                text += &format!("v {x} {y} {z}\n");
            }
            text += &(lines.join("\n") + "\n");
            if let Some(fast) = read_plain_obj(text.as_bytes()).map(plain) {
                prop_assert_eq!(Some(fast), careful(text.as_bytes()), "{}", text);
            }
        }
    }

    /// Real-mesh tier (`cargo test -p multires-halfedge --lib -- --ignored`; the shared
    /// meshes from `$MULTIRES_MESHES` or a `shared/meshes` folder above the workspace):
    /// every shared OBJ is read in one pass, as tobj's path reads it.
    #[test]
    #[ignore = "needs the shared meshes"]
    fn the_shared_obj_files_are_read_in_one_pass_as_tobj_reads_them() {
        let dir = std::env::var_os("MULTIRES_MESHES")
            .map(std::path::PathBuf::from)
            .or_else(|| {
                Path::new(env!("CARGO_MANIFEST_DIR"))
                    .ancestors()
                    .map(|a| a.join("shared/meshes"))
                    .find(|d| d.is_dir())
            })
            .expect("a shared/meshes folder above the workspace, or MULTIRES_MESHES=DIR");
        let mut read = 0;
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().and_then(|e| e.to_str()) != Some("obj") {
                continue;
            }
            let bytes = std::fs::read(&path).unwrap();
            let fast = read_plain_obj(&bytes).map(plain);
            assert!(fast.is_some(), "{} was not taken", path.display());
            assert_eq!(fast, careful(&bytes), "{}", path.display());
            read += 1;
        }
        assert!(read > 0, "no OBJ file in {}", dir.display());
    }
}
