//! The fast route for binary PLY: the payload is decoded straight from the input, in
//! chunks of a megabyte.
//!
//! Why it exists: `ply-rs-bw` reads element by element through a `Read` trait, looks
//! every value's property name up in the destination struct and builds one `Vec` per
//! face. On a 1.6-million-face binary PLY (nefertiti subdivided twice) that took about
//! 0.17 s of parsing alone, on top of building the mesh, while OpenMesh's whole load
//! (parse and build) takes about 0.36 s; decoding the bytes in place takes a few
//! hundredths of a second. The file is streamed rather than read whole, which spares
//! touching (and page-faulting) another copy of it.
//!
//! It takes the common layout only; anything else goes the general `ply-rs-bw` route:
//! - `vertex`: scalar properties only (any types; `x`, `y`, `z` anywhere among them);
//! - `face` / `tristrips`: the index list (`vertex_indices` or `vertex_index`, any
//!   integer count and index types) as the only property;
//! - any other element: scalar properties only (skipped by its record size).

use std::io::Read;
use std::path::Path;

use ply_rs_bw::ply::{ElementDef, Encoding, Header, PropertyType, ScalarType};

use super::ply_layout::{index_property, push_face, push_strip, FaceKind, Layout, PolygonSoup};
use crate::error::{Error, Result};

/// Byte order of the payload.
trait ByteOrder {
    fn u16(b: [u8; 2]) -> u16;
    fn u32(b: [u8; 4]) -> u32;
    fn u64(b: [u8; 8]) -> u64;
}

struct Little;
struct Big;

impl ByteOrder for Little {
    #[inline]
    fn u16(b: [u8; 2]) -> u16 {
        u16::from_le_bytes(b)
    }
    #[inline]
    fn u32(b: [u8; 4]) -> u32 {
        u32::from_le_bytes(b)
    }
    #[inline]
    fn u64(b: [u8; 8]) -> u64 {
        u64::from_le_bytes(b)
    }
}

impl ByteOrder for Big {
    #[inline]
    fn u16(b: [u8; 2]) -> u16 {
        u16::from_be_bytes(b)
    }
    #[inline]
    fn u32(b: [u8; 4]) -> u32 {
        u32::from_be_bytes(b)
    }
    #[inline]
    fn u64(b: [u8; 8]) -> u64 {
        u64::from_be_bytes(b)
    }
}

fn size_of(t: &ScalarType) -> usize {
    match t {
        ScalarType::Char | ScalarType::UChar => 1,
        ScalarType::Short | ScalarType::UShort => 2,
        ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
        ScalarType::Double => 8,
    }
}

/// Decodes a number of type `t` from the start of `b` (which holds at least
/// `size_of(t)` bytes) as `f64`.
#[inline]
fn decode_f64<O: ByteOrder>(t: &ScalarType, b: &[u8]) -> f64 {
    match t {
        ScalarType::Float => f64::from(f32::from_bits(O::u32(first(b)))),
        ScalarType::Double => f64::from_bits(O::u64(first(b))),
        _ => decode_i64::<O>(t, b) as f64,
    }
}

/// Decodes an integer of type `t` from the start of `b` (floats are truncated; the header
/// check has made sure index lists are integers).
#[inline]
fn decode_i64<O: ByteOrder>(t: &ScalarType, b: &[u8]) -> i64 {
    match t {
        ScalarType::Char => i64::from(b[0] as i8),
        ScalarType::UChar => i64::from(b[0]),
        ScalarType::Short => i64::from(O::u16(first(b)) as i16),
        ScalarType::UShort => i64::from(O::u16(first(b))),
        ScalarType::Int => i64::from(O::u32(first(b)) as i32),
        ScalarType::UInt => i64::from(O::u32(first(b))),
        ScalarType::Float => f32::from_bits(O::u32(first(b))) as i64,
        ScalarType::Double => f64::from_bits(O::u64(first(b))) as i64,
    }
}

#[inline]
fn first<const N: usize>(b: &[u8]) -> [u8; N] {
    let mut a = [0; N];
    a.copy_from_slice(&b[..N]);
    a
}

/// Record size of an element with scalar properties only; `None` if it has a list.
fn record_size(element: &ElementDef) -> Option<usize> {
    element
        .properties
        .values()
        .map(|p| match &p.data_type {
            PropertyType::Scalar(t) => Some(size_of(t)),
            PropertyType::List(..) => None,
        })
        .sum()
}

/// How an element is read on the fast route.
pub(crate) enum Plan<'h> {
    Vertices {
        stride: usize,
        axes: [(usize, &'h ScalarType); 3],
    },
    Lists {
        kind: FaceKind,
        count: &'h ScalarType,
        index: &'h ScalarType,
    },
    Skip {
        stride: usize,
    },
}

fn plan(element: &ElementDef) -> Option<Plan<'_>> {
    let kind = match element.name.as_str() {
        "vertex" => {
            let stride = record_size(element)?;
            let mut axes = [(0, &ScalarType::Float); 3];
            let mut offset = 0;
            for p in element.properties.values() {
                let PropertyType::Scalar(t) = &p.data_type else {
                    return None;
                };
                if let Some(axis) = ["x", "y", "z"].iter().position(|a| *a == p.name) {
                    axes[axis] = (offset, t);
                }
                offset += size_of(t);
            }
            return Some(Plan::Vertices { stride, axes });
        }
        "face" => FaceKind::Polygons,
        "tristrips" => FaceKind::Strips,
        _ => {
            return record_size(element).map(|stride| Plan::Skip { stride });
        }
    };
    let name = index_property(element).ok()??;
    if element.properties.len() != 1 {
        return None;
    }
    let PropertyType::List(count, index) = &element.properties[name].data_type else {
        return None;
    };
    Some(Plan::Lists { kind, count, index })
}

/// The fast-route plan of every element, or `None` when the file is ASCII or not laid
/// out the common way (see the [module docs](self)).
pub(crate) fn plans(header: &Header) -> Option<Vec<Plan<'_>>> {
    if header.encoding == Encoding::Ascii {
        return None;
    }
    header.elements.values().map(plan).collect()
}

/// Reads the payload that follows the header in `input` on the fast route.
pub(crate) fn read_binary<R: Read>(
    header: &Header,
    plans: &[Plan<'_>],
    input: &mut R,
    layout: &Layout,
    path: &Path,
) -> Result<PolygonSoup> {
    let mut input = Chunks::new(input);
    match header.encoding {
        Encoding::BinaryBigEndian => read::<Big, R>(header, plans, &mut input, layout, path),
        _ => read::<Little, R>(header, plans, &mut input, layout, path),
    }
}

/// A read buffer that hands out contiguous byte ranges of the input.
struct Chunks<'r, R: Read> {
    input: &'r mut R,
    buf: Vec<u8>,
    /// Unread bytes are `buf[pos..end]`.
    pos: usize,
    end: usize,
    /// Bytes of the payload before `buf[0]`.
    offset: u64,
}

impl<'r, R: Read> Chunks<'r, R> {
    const SIZE: usize = 1 << 20;

    fn new(input: &'r mut R) -> Self {
        Self {
            input,
            buf: vec![0; Self::SIZE],
            pos: 0,
            end: 0,
            offset: 0,
        }
    }

    /// Unread bytes in the buffer.
    #[inline]
    fn available(&self) -> &[u8] {
        &self.buf[self.pos..self.end]
    }

    #[inline]
    fn consume(&mut self, n: usize) {
        self.pos += n;
    }

    /// Position in the payload.
    fn position(&self) -> u64 {
        self.offset + self.pos as u64
    }

    /// Makes at least `n` bytes available; `false` when the input ends before. The
    /// buffer grows beyond its size only as far as the input really has bytes.
    fn ensure(&mut self, n: usize) -> std::io::Result<bool> {
        if self.end - self.pos >= n {
            return Ok(true);
        }
        self.buf.copy_within(self.pos..self.end, 0);
        self.offset += self.pos as u64;
        self.end -= self.pos;
        self.pos = 0;
        while self.end < n {
            if self.end == self.buf.len() {
                let grown = (2 * self.buf.len()).min(n.max(Self::SIZE));
                self.buf.resize(grown, 0);
            }
            match self.input.read(&mut self.buf[self.end..]) {
                Ok(0) => return Ok(false),
                Ok(k) => self.end += k,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
        Ok(true)
    }
}

fn read<O: ByteOrder, R: Read>(
    header: &Header,
    plans: &[Plan<'_>],
    input: &mut Chunks<'_, R>,
    layout: &Layout,
    path: &Path,
) -> Result<PolygonSoup> {
    let format = |message: String| Error::Format {
        path: path.to_owned(),
        message,
    };
    let format = &format;
    let io = |source: std::io::Error| Error::Io {
        path: path.to_owned(),
        source,
    };
    let truncated = |element: &ElementDef, number: usize, position: u64| {
        format(format!(
            "truncated file: the payload ends in {} {number} of {} (at byte {position} of the payload)",
            element.name, element.count
        ))
    };
    let mut soup = PolygonSoup::default();
    for (element, plan) in header.elements.values().zip(plans) {
        match *plan {
            Plan::Vertices { stride, axes } => {
                soup.positions.reserve(element.count.min(1 << 20));
                let mut number = 0;
                while number < element.count {
                    if !input.ensure(stride).map_err(io)? {
                        return Err(truncated(element, number, input.position()));
                    }
                    let records = (input.available().len() / stride).min(element.count - number);
                    let bytes = &input.available()[..records * stride];
                    soup.positions.extend(bytes.chunks_exact(stride).map(|r| {
                        glam::DVec3::new(
                            decode_f64::<O>(axes[0].1, &r[axes[0].0..]),
                            decode_f64::<O>(axes[1].1, &r[axes[1].0..]),
                            decode_f64::<O>(axes[2].1, &r[axes[2].0..]),
                        )
                    }));
                    input.consume(records * stride);
                    number += records;
                }
            }
            Plan::Skip { stride } => {
                let mut number = 0;
                while stride > 0 && number < element.count {
                    if !input.ensure(stride).map_err(io)? {
                        return Err(truncated(element, number, input.position()));
                    }
                    let records = (input.available().len() / stride).min(element.count - number);
                    input.consume(records * stride);
                    number += records;
                }
            }
            Plan::Lists { kind, count, index } => {
                let (count_size, index_size) = (size_of(count), size_of(index));
                let mut list: Vec<i64> = Vec::new();
                for number in 0..element.count {
                    let start = input.position();
                    if !input.ensure(count_size).map_err(io)? {
                        return Err(truncated(element, number, start));
                    }
                    let n = decode_i64::<O>(count, input.available());
                    input.consume(count_size);
                    let n = usize::try_from(n).map_err(|_| {
                        format(format!(
                            "{} {number} has a negative list length ({n})",
                            element.name
                        ))
                    })?;
                    let bytes = n
                        .checked_mul(index_size)
                        .ok_or_else(|| truncated(element, number, start))?;
                    if !input.ensure(bytes).map_err(io)? {
                        return Err(truncated(element, number, start));
                    }
                    list.clear();
                    list.extend(
                        input.available()[..bytes]
                            .chunks_exact(index_size)
                            .map(|b| decode_i64::<O>(index, b)),
                    );
                    input.consume(bytes);
                    match kind {
                        FaceKind::Polygons => push_face(
                            &mut soup,
                            list.iter().copied(),
                            number,
                            layout.n_vertices,
                            format,
                        )?,
                        FaceKind::Strips => push_strip(
                            &mut soup,
                            list.iter().copied(),
                            number,
                            layout.n_vertices,
                            format,
                        )?,
                    }
                }
            }
        }
    }
    Ok(soup)
}
