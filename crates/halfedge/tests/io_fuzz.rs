//! Truncated and corrupted files never make a reader panic: they give an error or, when
//! the damage happens to leave a valid file, a valid mesh.

mod common;

use std::path::Path;

use common::{square, Enc};
use halfedge::generators;
use halfedge::io::{
    read_obj_from_bytes, read_ply_from_bytes, write_obj_to, write_ply_to, PlyFormat,
};
use proptest::prelude::*;

fn valid_files() -> Vec<(bool, Vec<u8>)> {
    let mesh = generators::icosphere(1);
    let mut files = Vec::new();
    for format in [
        PlyFormat::Ascii,
        PlyFormat::BinaryLittleEndian,
        PlyFormat::BinaryBigEndian,
    ] {
        let mut bytes = Vec::new();
        write_ply_to(&mut bytes, &mesh, format).unwrap();
        files.push((true, bytes));
    }
    for enc in [Enc::Ascii, Enc::Le, Enc::Be] {
        files.push((true, square(enc).bytes()));
    }
    let mut obj = Vec::new();
    write_obj_to(&mut obj, &mesh).unwrap();
    files.push((false, obj));
    files
}

fn read(is_ply: bool, bytes: &[u8]) {
    let result = if is_ply {
        read_ply_from_bytes(bytes, Path::new("fuzz.ply"))
    } else {
        read_obj_from_bytes(bytes, Path::new("fuzz.obj"))
    };
    if let Ok((mesh, _)) = result {
        mesh.check().unwrap();
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn truncated_files_do_not_panic(file in 0usize..7, cut in 0.0f64..1.0) {
        let files = valid_files();
        let (is_ply, bytes) = &files[file];
        let len = (cut * bytes.len() as f64) as usize;
        read(*is_ply, &bytes[..len]);
    }

    #[test]
    fn corrupted_files_do_not_panic(
        file in 0usize..7,
        edits in proptest::collection::vec((0.0f64..1.0, any::<u8>()), 1..8),
    ) {
        let files = valid_files();
        let (is_ply, bytes) = &files[file];
        let mut bytes = bytes.clone();
        for (at, value) in edits {
            let i = ((at * bytes.len() as f64) as usize).min(bytes.len() - 1);
            bytes[i] = value;
        }
        read(*is_ply, &bytes);
    }

    #[test]
    fn garbage_does_not_panic(is_ply in any::<bool>(), bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        read(is_ply, &bytes);
        let mut with_header = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n".to_vec();
        with_header.extend(&bytes);
        read(true, &with_header);
    }
}
