//! Gzip-compressed mesh files (`.obj.gz`, `.ply.gz`, `.off.gz`, `.stl.gz`), through
//! `flate2` (its pure-Rust `miniz_oxide` backend).
//!
//! **Reading** decompresses the whole file in memory (several gzip members in a row are
//! read as one stream, as `gzip -d` does) and reads the result with the reader of the
//! format named by the extension under `.gz` (any case): `mesh.OFF.gz` is OFF. Errors
//! name the `.gz` file, and places (lines, elements, triangles) are those of the
//! decompressed data.
//!
//! **Limit.** A small file can decompress to a huge one (a "decompression bomb": deflate
//! reaches about 1000 : 1 on repetitive data), so the decompressed size is capped by
//! [`decompressed_limit`]: [`MAX_RATIO`] (256) times the compressed size, but never less
//! than [`MIN_LIMIT`] (64 MiB) and never more than [`MAX_DECOMPRESSED`] (4 GiB). Real
//! meshes compress 3 to 25 times (measured: binary PLY and STL of scans and grids 3–13×,
//! OBJ 3–5×, ASCII STL of a flat grid 25×, its most repetitive case); only files of one
//! repeated value (all coordinates 0) come near deflate's limit, and those under 64 MiB
//! still read. 4 GiB bounds the memory of one load on the project's 24 GiB machines (the
//! mesh built from 4 GiB of file takes several times that). Past the limit, reading stops
//! at once with an [`Error::Format`] saying so; memory is allocated as the data really
//! comes, never from the size the gzip trailer announces. [`decompress`] takes any
//! limit, for callers with another budget.
//!
//! **Writing** ([`write_gz`]) writes the format named under `.gz` (binary PLY, binary
//! STL, OBJ, OFF) through a gzip encoder at the default level.

use std::io::{BufWriter, Read, Write};
use std::path::Path;

use flate2::read::MultiGzDecoder;
use flate2::write::GzEncoder;
use flate2::Compression;

use super::obj::read_obj_from_bytes;
use super::obj_write::write_obj_to;
use super::off::read_off_from_bytes;
use super::off_write::write_off_to;
use super::ply::read_ply_from_bytes;
use super::ply_write::{write_ply_to, PlyFormat};
use super::stl::read_stl_from_bytes;
use super::stl_write::{write_stl_to, StlFormat};
use crate::build::BuildReport;
use crate::error::{Error, Result};
use crate::mesh::Mesh;

/// The most a gzip file is decompressed to: 4 GiB (see the [module docs](self)).
pub const MAX_DECOMPRESSED: u64 = 4 << 30;
/// The decompressed size allowed per compressed byte (see the [module docs](self)).
pub const MAX_RATIO: u64 = 256;
/// The decompressed size always allowed, whatever the ratio: 64 MiB.
pub const MIN_LIMIT: u64 = 64 << 20;

/// The decompressed size allowed for a gzip file of `compressed` bytes:
/// `MAX_RATIO · compressed`, at least [`MIN_LIMIT`], at most [`MAX_DECOMPRESSED`].
pub fn decompressed_limit(compressed: u64) -> u64 {
    compressed
        .saturating_mul(MAX_RATIO)
        .clamp(MIN_LIMIT, MAX_DECOMPRESSED)
}

/// The extension under `.gz` (lower case): `obj` for `mesh.OBJ.gz`; `None` when the path
/// does not end in `.gz` or has nothing under it.
pub fn inner_extension(path: &Path) -> Option<String> {
    if super::extension(path).as_deref() != Some("gz") {
        return None;
    }
    super::extension(Path::new(path.file_stem()?))
}

/// Reads a gzip-compressed mesh file, in the format named under `.gz` (see the
/// [module docs](self)). An unknown format under `.gz` is [`Error::UnknownFormat`].
pub fn read_gz(path: impl AsRef<Path>) -> Result<(Mesh, BuildReport)> {
    let path = path.as_ref();
    let reader = inner_reader(path)?;
    let bytes = super::read_bytes(path)?;
    let data = decompress(&bytes, path, decompressed_limit(bytes.len() as u64))?;
    reader(&data, path)
}

/// Reads gzip-compressed data from memory, in the format named by `path`'s extension
/// under `.gz` (`path` is also used in error messages); the limit is
/// [`decompressed_limit`] of the data's size.
pub fn read_gz_from_bytes(bytes: &[u8], path: &Path) -> Result<(Mesh, BuildReport)> {
    let reader = inner_reader(path)?;
    let data = decompress(bytes, path, decompressed_limit(bytes.len() as u64))?;
    reader(&data, path)
}

type BytesReader = fn(&[u8], &Path) -> Result<(Mesh, BuildReport)>;

fn inner_reader(path: &Path) -> Result<BytesReader> {
    match inner_extension(path).as_deref() {
        Some("obj") => Ok(read_obj_from_bytes),
        Some("ply") => Ok(read_ply_from_bytes),
        Some("off") => Ok(read_off_from_bytes),
        Some("stl") => Ok(read_stl_from_bytes),
        _ => Err(Error::UnknownFormat(path.to_owned())),
    }
}

/// Decompresses gzip data (one or more members) of at most `limit` bytes; `path` is only
/// used in error messages. Errors are [`Error::Format`]: an empty file, data that is not
/// gzip, corrupt or truncated data (at which decompressed byte), more than `limit` bytes.
pub fn decompress(bytes: &[u8], path: &Path, limit: u64) -> Result<Vec<u8>> {
    let format = |message: String| Error::Format {
        path: path.to_owned(),
        message,
    };
    if bytes.is_empty() {
        return Err(format("byte 0: empty file".into()));
    }
    if !bytes.starts_with(&[0x1f, 0x8b]) {
        return Err(format(
            "byte 0: not gzip data (it does not start with the gzip magic bytes 1f 8b)".into(),
        ));
    }
    let mut decoder = MultiGzDecoder::new(bytes);
    let mut out: Vec<u8> = Vec::new();
    let mut chunk = vec![0u8; 1 << 16];
    loop {
        let n = match decoder.read(&mut chunk) {
            Ok(0) => break,
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => {
                let what = if e.kind() == std::io::ErrorKind::UnexpectedEof {
                    "truncated gzip data"
                } else {
                    "corrupt gzip data"
                };
                return Err(format(format!(
                    "byte {} of the decompressed data: {what} ({e})",
                    out.len()
                )));
            }
        };
        if (out.len() + n) as u64 > limit {
            return Err(format(format!(
                "byte {limit} of the decompressed data: the file decompresses to more than \
                 {limit} bytes, the limit for a {}-byte gzip file (see halfedge::io::gz)",
                bytes.len()
            )));
        }
        if out.capacity() - out.len() < n {
            // Grow by doubling, but never past the limit.
            let want = (out.capacity().max(1 << 20) as u64).min(limit - out.len() as u64);
            out.try_reserve_exact((want as usize).max(n)).map_err(|e| {
                format(format!(
                    "byte {} of the decompressed data: cannot allocate memory for it ({e})",
                    out.len()
                ))
            })?;
        }
        out.extend_from_slice(&chunk[..n]);
    }
    Ok(out)
}

/// Writes a mesh gzip-compressed, in the format named under `.gz` (binary PLY, binary
/// STL, OBJ or OFF). An unknown format under `.gz` is [`Error::UnknownFormat`].
pub fn write_gz(path: impl AsRef<Path>, mesh: &Mesh) -> Result<()> {
    let path = path.as_ref();
    let inner = inner_extension(path);
    let write: fn(&mut GzEncoder<BufWriter<std::fs::File>>, &Mesh) -> Result<()> =
        match inner.as_deref() {
            Some("obj") => |out, mesh| write_obj_to(out, mesh),
            Some("ply") => |out, mesh| write_ply_to(out, mesh, PlyFormat::BinaryLittleEndian),
            Some("off") => |out, mesh| write_off_to(out, mesh),
            Some("stl") => |out, mesh| write_stl_to(out, mesh, StlFormat::Binary),
            _ => return Err(Error::UnknownFormat(path.to_owned())),
        };
    let io = |source: std::io::Error| Error::Io {
        path: path.to_owned(),
        source,
    };
    let file = std::fs::File::create(path).map_err(io)?;
    let mut encoder = GzEncoder::new(
        BufWriter::with_capacity(1 << 20, file),
        Compression::default(),
    );
    write(&mut encoder, mesh).map_err(|e| match e {
        Error::Io { source, .. } => io(source),
        other => other,
    })?;
    encoder.finish().map_err(io)?.flush().map_err(io)
}
