//! Gzip-compressed mesh files: every format round-trips through `.gz`, the format is the
//! extension under `.gz`, and bombs, corrupt and truncated data give typed errors.

use std::io::Write;
use std::path::Path;

use flate2::write::GzEncoder;
use flate2::Compression;
use halfedge::io::gz::{self, decompress, decompressed_limit, read_gz_from_bytes};
use halfedge::io::{self, PlyFormat};
use halfedge::{generators, Error, Mesh};
use testkit::check::triangles;
use testkit::temp_dir;

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut e = GzEncoder::new(Vec::new(), Compression::default());
    e.write_all(bytes).unwrap();
    e.finish().unwrap()
}

fn corners(mesh: &Mesh) -> Vec<[[f32; 3]; 3]> {
    mesh.faces()
        .map(|f| {
            mesh.triangle(f)
                .map(|v| mesh.position(v).as_vec3().to_array())
        })
        .collect()
}

fn format_error(result: halfedge::Result<impl std::fmt::Debug>) -> String {
    match result {
        Err(e @ Error::Format { .. }) => e.to_string(),
        other => panic!("expected a format error, got {other:?}"),
    }
}

#[test]
fn every_format_round_trips_through_gz() {
    let dir = temp_dir("gz-roundtrip");
    let mut mesh = generators::torus(1.0, 0.3, 20, 10).unwrap();
    for p in mesh.positions_mut() {
        *p *= std::f64::consts::E;
    }
    for name in ["t.obj.gz", "t.ply.gz", "t.off.gz", "t.OFF.GZ", "t.Obj.Gz"] {
        let path = dir.join(name);
        io::write(&path, &mesh).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert!(bytes.starts_with(&[0x1f, 0x8b]), "{name} is gzip");
        let (back, report) = io::read(&path).unwrap_or_else(|e| panic!("{e}"));
        back.check().unwrap();
        assert_eq!(back.positions(), mesh.positions(), "{name}");
        assert_eq!(triangles(&back), triangles(&mesh), "{name}");
        assert_eq!(report.input_faces, mesh.n_faces());
    }
    // STL: positions as f32, welded back into the torus.
    for name in ["t.stl.gz", "t.STL.gz"] {
        let path = dir.join(name);
        io::write(&path, &mesh).unwrap();
        let (back, report) = io::read(&path).unwrap();
        assert_eq!(corners(&back), corners(&mesh), "{name}");
        assert_eq!(back.topology_report(), mesh.topology_report());
        assert_eq!(
            report.merged_vertices,
            3 * mesh.n_faces() - mesh.n_vertices()
        );
    }
    // Files compressed by someone else: ASCII PLY, several gzip members in a row.
    let mut ascii = Vec::new();
    io::write_ply_to(&mut ascii, &mesh, PlyFormat::Ascii).unwrap();
    let (a, b) = ascii.split_at(ascii.len() / 3);
    let members = [gzip(a), gzip(b)].concat();
    let (back, _) = read_gz_from_bytes(&members, Path::new("two-members.ply.gz")).unwrap();
    assert_eq!(back.positions(), mesh.positions());
    std::fs::remove_dir_all(&dir).ok();
}

/// The format is the extension under `.gz`: OBJ text named `.off.gz` is read as OFF
/// and refused as such.
#[test]
fn the_format_is_the_extension_under_gz() {
    let mut obj = Vec::new();
    io::write_obj_to(&mut obj, &generators::icosphere(0)).unwrap();
    let data = gzip(&obj);
    assert!(read_gz_from_bytes(&data, Path::new("a.obj.gz")).is_ok());
    let message = format_error(read_gz_from_bytes(&data, Path::new("a.off.gz")));
    assert!(
        message.starts_with("a.off.gz: line 2: not an OFF file"),
        "{message}"
    );
    for unknown in ["a.gz", "a.txt.gz", ".gz"] {
        assert!(
            matches!(
                read_gz_from_bytes(&data, Path::new(unknown)),
                Err(Error::UnknownFormat(_))
            ),
            "{unknown}"
        );
    }
    assert_eq!(
        gz::inner_extension(Path::new("dir.x/m.PLY.gz")).as_deref(),
        Some("ply")
    );
    assert_eq!(gz::inner_extension(Path::new("m.ply")), None);
}

/// A decompression bomb (a few hundred kilobytes that decompress to gigabytes) stops at
/// the limit with a format error, never allocating more than the limit.
#[test]
fn a_gzip_bomb_is_refused_at_the_limit() {
    // 1 MiB of zeros compresses to about 1 KiB; 160 members of it are 160 MiB, and no
    // ASCII mesh is anything like that (OFF header, then zeros).
    let member = gzip(&vec![0u8; 1 << 20]);
    let mut bomb = gzip(b"OFF\n3 1 0\n");
    for _ in 0..160 {
        bomb.extend(&member);
    }
    assert!(bomb.len() < 400_000, "{}", bomb.len());
    let limit = decompressed_limit(bomb.len() as u64);
    assert_eq!(limit, gz::MIN_LIMIT);
    let message = format_error(read_gz_from_bytes(&bomb, Path::new("bomb.off.gz")));
    assert!(message.starts_with("bomb.off.gz: "), "{message}");
    assert!(
        message.contains(&format!("more than {limit} bytes")),
        "{message}"
    );
    // Any limit: one byte short of the data, and just enough.
    let text = b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    let data = gzip(text);
    let size = text.len() as u64;
    let message = format_error(decompress(&data, Path::new("x.off.gz"), size - 1));
    assert!(
        message.contains(&format!("more than {} bytes", size - 1)),
        "{message}"
    );
    assert_eq!(
        decompress(&data, Path::new("x.off.gz"), size).unwrap(),
        text
    );
}

#[test]
fn the_limit_follows_the_compressed_size_within_bounds() {
    assert_eq!(decompressed_limit(0), gz::MIN_LIMIT);
    assert_eq!(decompressed_limit(1000), 64 << 20);
    assert_eq!(decompressed_limit(1 << 20), 256 << 20);
    assert_eq!(decompressed_limit(100 << 20), gz::MAX_DECOMPRESSED);
    assert_eq!(decompressed_limit(u64::MAX), 4 << 30);
}

#[test]
fn corrupt_truncated_and_foreign_data_give_format_errors() {
    let path = Path::new("x.stl.gz");
    let mut stl = Vec::new();
    io::write_stl_to(&mut stl, &generators::icosphere(2), io::StlFormat::Binary).unwrap();
    let data = gzip(&stl);
    let message = format_error(read_gz_from_bytes(&[], path));
    assert!(message.contains("empty file"), "{message}");
    let message = format_error(read_gz_from_bytes(&stl, path));
    assert!(message.contains("byte 0: not gzip data"), "{message}");
    // Truncated: at the end of the compressed data, or inside it.
    for cut in [data.len() - 4, data.len() / 2, 11] {
        let message = format_error(read_gz_from_bytes(&data[..cut], path));
        assert!(message.contains("decompressed data"), "{message}");
        assert!(
            message.contains("truncated") || message.contains("corrupt"),
            "{message}"
        );
    }
    // Flipped bits: the CRC or the deflate stream notices.
    for at in [data.len() / 2, data.len() - 6] {
        let mut bad = data.clone();
        bad[at] ^= 0x10;
        let message = format_error(read_gz_from_bytes(&bad, path));
        assert!(
            message.contains("corrupt") || message.contains("truncated"),
            "{message}"
        );
    }
    // Errors of the inner reader name the .gz file.
    let message = format_error(read_gz_from_bytes(&gzip(&stl[..300]), path));
    assert!(
        message.starts_with("x.stl.gz: byte 300: truncated file"),
        "{message}"
    );
}
