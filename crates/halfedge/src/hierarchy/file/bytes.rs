//! The byte level of a hierarchy file: little-endian scalars and counted arrays, written
//! to a counting sink (the sizes for the section table) or to a stream (with the
//! section's CRC-32), and read back from a slice with every count checked against the
//! bytes that remain before anything is allocated.

use std::io::Write;
use std::path::Path;

use glam::DVec3;

use crate::error::{Error, Result};

/// Where a section's bytes go: [`Count`] or [`Stream`]. Every value is little-endian; an
/// array is its element count (`u64`) and its elements, each `size` bytes.
pub(super) trait Out {
    /// Appends raw bytes.
    fn raw(&mut self, bytes: &[u8]);
    /// Appends `items.len()` as a `u64`, then every item encoded by `encode` into
    /// exactly `size` bytes.
    fn array<T>(&mut self, items: &[T], size: usize, encode: impl Fn(&T, &mut [u8]));

    /// A byte.
    fn u8(&mut self, x: u8) {
        self.raw(&[x]);
    }
    /// A `u64`.
    fn u64(&mut self, x: u64) {
        self.raw(&x.to_le_bytes());
    }
    /// A `usize`, as a `u64`.
    fn usize(&mut self, x: usize) {
        self.u64(x as u64);
    }
    /// An `f64`, its bits.
    fn f64(&mut self, x: f64) {
        self.raw(&x.to_le_bytes());
    }
    /// A boolean, as the byte 0 or 1.
    fn bool(&mut self, x: bool) {
        self.u8(u8::from(x));
    }
}

/// Writes `x` at the start of `out` (little-endian).
#[inline(always)]
pub(super) fn put_u32(out: &mut [u8], x: u32) {
    out[..4].copy_from_slice(&x.to_le_bytes());
}
/// Writes `x` at the start of `out` (little-endian).
#[inline(always)]
pub(super) fn put_u64(out: &mut [u8], x: u64) {
    out[..8].copy_from_slice(&x.to_le_bytes());
}
/// Writes `x` at the start of `out` (its bits, little-endian).
#[inline(always)]
pub(super) fn put_f64(out: &mut [u8], x: f64) {
    out[..8].copy_from_slice(&x.to_le_bytes());
}
/// Writes the three coordinates of `p` at the start of `out`.
#[inline(always)]
pub(super) fn put_vec3(out: &mut [u8], p: DVec3) {
    put_f64(out, p.x);
    put_f64(&mut out[8..], p.y);
    put_f64(&mut out[16..], p.z);
}
/// The `u32` at the start of `bytes`.
#[inline(always)]
pub(super) fn get_u32(bytes: &[u8]) -> u32 {
    u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]])
}
/// The `u64` at the start of `bytes`.
#[inline(always)]
pub(super) fn get_u64(bytes: &[u8]) -> u64 {
    let mut b = [0u8; 8];
    b.copy_from_slice(&bytes[..8]);
    u64::from_le_bytes(b)
}
/// The `f64` at the start of `bytes`.
#[inline(always)]
pub(super) fn get_f64(bytes: &[u8]) -> f64 {
    f64::from_bits(get_u64(bytes))
}
/// The three coordinates at the start of `bytes`.
#[inline(always)]
pub(super) fn get_vec3(bytes: &[u8]) -> DVec3 {
    DVec3::new(get_f64(bytes), get_f64(&bytes[8..]), get_f64(&bytes[16..]))
}

/// A sink that only counts: the size of a section before it is written.
#[derive(Default)]
pub(super) struct Count(pub(super) u64);

impl Out for Count {
    fn raw(&mut self, bytes: &[u8]) {
        self.0 += bytes.len() as u64;
    }
    fn array<T>(&mut self, items: &[T], size: usize, _encode: impl Fn(&T, &mut [u8])) {
        self.0 += 8 + (items.len() * size) as u64;
    }
}

/// Bytes gathered before they are handed to the writer.
const CHUNK: usize = 1 << 16;

/// A sink that writes a section to `W` through a buffer, hashing what it writes (the
/// section's CRC-32) and counting it. The first write error is kept and every later
/// write skipped; [`finish`](Self::finish) returns it.
pub(super) struct Stream<'w, W: Write> {
    writer: &'w mut W,
    buffer: Vec<u8>,
    hasher: crc32fast::Hasher,
    written: u64,
    error: Option<std::io::Error>,
}

impl<'w, W: Write> Stream<'w, W> {
    /// A stream writing to `writer`.
    pub(super) fn new(writer: &'w mut W) -> Self {
        Self {
            writer,
            buffer: Vec::with_capacity(CHUNK),
            hasher: crc32fast::Hasher::new(),
            written: 0,
            error: None,
        }
    }

    /// Hands the buffer to the writer.
    fn flush_buffer(&mut self) {
        if self.error.is_none() && !self.buffer.is_empty() {
            self.hasher.update(&self.buffer);
            if let Err(e) = self.writer.write_all(&self.buffer) {
                self.error = Some(e);
            }
        }
        self.written += self.buffer.len() as u64;
        self.buffer.clear();
    }

    /// Writes what is buffered and returns the bytes written and their CRC-32 (the
    /// hasher starts again), or the first write error.
    pub(super) fn finish(&mut self) -> std::io::Result<(u64, u32)> {
        self.flush_buffer();
        if let Some(e) = self.error.take() {
            return Err(e);
        }
        let hasher = std::mem::replace(&mut self.hasher, crc32fast::Hasher::new());
        let written = std::mem::take(&mut self.written);
        Ok((written, hasher.finalize()))
    }

    /// Writes bytes that are not part of a section (the header, a section's CRC).
    pub(super) fn unhashed(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        self.flush_buffer();
        if let Some(e) = self.error.take() {
            return Err(e);
        }
        self.writer.write_all(bytes)
    }
}

impl<W: Write> Out for Stream<'_, W> {
    fn raw(&mut self, bytes: &[u8]) {
        if self.buffer.len() + bytes.len() > CHUNK {
            self.flush_buffer();
        }
        if bytes.len() > CHUNK {
            self.buffer.extend_from_slice(bytes);
            self.flush_buffer();
        } else {
            self.buffer.extend_from_slice(bytes);
        }
    }
    fn array<T>(&mut self, items: &[T], size: usize, encode: impl Fn(&T, &mut [u8])) {
        self.u64(items.len() as u64);
        let per_chunk = (CHUNK / size.max(1)).max(1);
        for batch in items.chunks(per_chunk) {
            if self.buffer.len() + batch.len() * size > CHUNK {
                self.flush_buffer();
            }
            let start = self.buffer.len();
            self.buffer.resize(start + batch.len() * size, 0);
            for (item, out) in batch
                .iter()
                .zip(self.buffer[start..].chunks_exact_mut(size))
            {
                encode(item, out);
            }
        }
    }
}

/// A reader of one section's bytes, from a slice holding them or streamed from a file
/// (hashed as they come, the CRC-32 compared at the section's end): every read is
/// bounds-checked, every array count is checked against the bytes that remain in the
/// section before its memory is allocated, and every error is an [`Error::Format`]
/// naming the file, the section and the byte.
pub(super) struct In<'a> {
    source: Source<'a>,
    /// Bytes of the section read so far.
    pos: usize,
    /// Bytes of the section.
    len: usize,
    /// Where the section starts in the file (for messages).
    base: usize,
    section: &'static str,
    path: &'a Path,
}

/// Where an [`In`] reads from.
enum Source<'a> {
    /// The section's bytes, their CRC-32 checked already.
    Slice(&'a [u8]),
    /// A reader positioned at the section's first byte, with a buffer for what is being
    /// decoded and the hash of what was read.
    Stream {
        reader: &'a mut dyn std::io::Read,
        scratch: Vec<u8>,
        hasher: crc32fast::Hasher,
    },
}

impl<'a> In<'a> {
    /// A reader of `bytes`, section `section` of `path` starting at file offset `base`.
    pub(super) fn new(bytes: &'a [u8], base: usize, section: &'static str, path: &'a Path) -> Self {
        Self {
            source: Source::Slice(bytes),
            pos: 0,
            len: bytes.len(),
            base,
            section,
            path,
        }
    }

    /// A reader of the `len` bytes of section `section` of `path` (at file offset `base`)
    /// that `reader` gives next, followed by their CRC-32 (read and compared by
    /// [`end`](Self::end)).
    pub(super) fn stream(
        reader: &'a mut dyn std::io::Read,
        len: usize,
        base: usize,
        section: &'static str,
        path: &'a Path,
    ) -> Self {
        Self {
            source: Source::Stream {
                reader,
                scratch: Vec::new(),
                hasher: crc32fast::Hasher::new(),
            },
            pos: 0,
            len,
            base,
            section,
            path,
        }
    }

    /// The error "section S, byte N: `what`" of this file, at the current position.
    pub(super) fn error(&self, what: impl std::fmt::Display) -> Error {
        format_error(
            self.path,
            format!(
                "section {}, byte {}: {what}",
                self.section,
                self.base + self.pos
            ),
        )
    }

    /// `result`, its error message turned into [`error`](Self::error).
    pub(super) fn check<T>(&self, result: std::result::Result<T, String>) -> Result<T> {
        result.map_err(|what| self.error(what))
    }

    /// The next `n` bytes.
    pub(super) fn take(&mut self, n: usize) -> Result<&[u8]> {
        let rest = self.len - self.pos;
        if n > rest {
            return Err(self.error(format!("{n} bytes needed, {rest} left in the section")));
        }
        let start = self.pos;
        self.pos += n;
        match &mut self.source {
            Source::Slice(bytes) => Ok(&bytes[start..start + n]),
            Source::Stream {
                reader,
                scratch,
                hasher,
            } => {
                scratch.resize(n, 0);
                if let Err(source) = reader.read_exact(scratch) {
                    return Err(Error::Io {
                        path: self.path.to_path_buf(),
                        source,
                    });
                }
                hasher.update(scratch);
                Ok(scratch)
            }
        }
    }
    /// A byte.
    pub(super) fn u8(&mut self) -> Result<u8> {
        Ok(self.take(1)?[0])
    }
    /// A `u64`.
    pub(super) fn u64(&mut self) -> Result<u64> {
        Ok(get_u64(self.take(8)?))
    }
    /// An `f64`.
    pub(super) fn f64(&mut self) -> Result<f64> {
        Ok(get_f64(self.take(8)?))
    }
    /// A `u64` that must fit `usize` and be at most `max` (`what` names it in the error).
    pub(super) fn usize_at_most(&mut self, max: usize, what: &str) -> Result<usize> {
        let x = self.u64()?;
        match usize::try_from(x) {
            Ok(x) if x <= max => Ok(x),
            _ => Err(self.error(format!("{what} is {x}, at most {max} allowed"))),
        }
    }
    /// A `u64` that must fit `usize`.
    pub(super) fn usize(&mut self, what: &str) -> Result<usize> {
        self.usize_at_most(usize::MAX, what)
    }
    /// A boolean (the byte 0 or 1).
    pub(super) fn bool(&mut self, what: &str) -> Result<bool> {
        match self.u8()? {
            0 => Ok(false),
            1 => Ok(true),
            b => Err(self.error(format!("{what} is the byte {b}, not 0 or 1"))),
        }
    }
    /// An array of elements of `size` bytes, each made by `decode`: the count is checked
    /// against the bytes left before anything is allocated (a stream is decoded a chunk
    /// at a time).
    pub(super) fn array<T>(
        &mut self,
        size: usize,
        what: &str,
        decode: impl Fn(&[u8]) -> T,
    ) -> Result<Vec<T>> {
        let n = self.u64()?;
        let rest = (self.len - self.pos) as u64;
        if n.checked_mul(size as u64).is_none_or(|bytes| bytes > rest) {
            self.pos -= 8;
            return Err(self.error(format!(
                "{what}: {n} elements of {size} bytes announced, {rest} bytes left in the section"
            )));
        }
        let n = n as usize;
        if let Source::Slice(_) = self.source {
            let bytes = self.take(n * size)?;
            return Ok(bytes.chunks_exact(size).map(decode).collect());
        }
        let mut out = Vec::with_capacity(n);
        let per_chunk = (CHUNK * 16 / size.max(1)).max(1);
        while out.len() < n {
            let k = (n - out.len()).min(per_chunk);
            let bytes = self.take(k * size)?;
            out.extend(bytes.chunks_exact(size).map(&decode));
        }
        Ok(out)
    }

    /// Skips an array of elements of `size` bytes (its count checked as by
    /// [`array`](Self::array)).
    pub(super) fn skip_array(&mut self, size: usize, what: &str) -> Result<()> {
        self.array(size, what, |_| ()).map(drop)
    }

    /// Fails unless every byte of the section was read; for a stream, reads the CRC-32
    /// that follows and compares it with the hash of the section.
    pub(super) fn end(&mut self) -> Result<()> {
        let rest = self.len - self.pos;
        if rest != 0 {
            return Err(self.error(format!("{rest} bytes past the section's end")));
        }
        if let Source::Stream { reader, hasher, .. } = &mut self.source {
            let mut stored = [0u8; 4];
            if let Err(source) = reader.read_exact(&mut stored) {
                return Err(Error::Io {
                    path: self.path.to_path_buf(),
                    source,
                });
            }
            let stored = u32::from_le_bytes(stored);
            let computed = std::mem::replace(hasher, crc32fast::Hasher::new()).finalize();
            if stored != computed {
                return Err(format_error(
                    self.path,
                    format!(
                        "section {}: CRC-32 {stored:08x} stored, {computed:08x} computed (the \
                         section is corrupt)",
                        self.section
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// [`Error::Format`] for `path`.
pub(super) fn format_error(path: &Path, message: String) -> Error {
    Error::Format {
        path: path.to_path_buf(),
        message,
    }
}
