//! The fast route for binary PLY: the payload is decoded in place.
//!
//! Why it exists: `ply-rs-bw` reads element by element through a `Read` trait, looks
//! every value's property name up in the destination struct and builds one `Vec` per
//! face. On a 1.6-million-face binary PLY (nefertiti subdivided twice) that took about
//! 0.17 s of parsing alone, on top of building the mesh, while OpenMesh's whole load
//! (parse and build) takes about 0.36 s; decoding the bytes in place takes a few
//! hundredths of a second and brings the whole load under OpenMesh's.
//!
//! It takes the common layout only, and returns `None` for anything else (which then
//! goes the general `ply-rs-bw` route):
//! - `vertex`: scalar properties only (any types; `x`, `y`, `z` anywhere among them);
//! - `face` / `tristrips`: the index list (`vertex_indices` or `vertex_index`, any
//!   integer count and index types) as the only property;
//! - any other element: scalar properties only (skipped by its record size).

use ply_rs_bw::ply::{ElementDef, Encoding, Header, PropertyType, ScalarType};

use super::ply::{index_property, push_face, push_strip, FaceKind, Layout, PolygonSoup};
use crate::{Error, Result};

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

/// Reads a binary payload on the fast route, or returns `None` when the layout is not
/// the common one (see the [module docs](self)).
pub(crate) fn read_binary(
    header: &Header,
    payload: &[u8],
    layout: &Layout,
    format: &dyn Fn(String) -> Error,
) -> Result<Option<PolygonSoup>> {
    match header.encoding {
        Encoding::BinaryLittleEndian => read::<Little>(header, payload, layout, format),
        Encoding::BinaryBigEndian => read::<Big>(header, payload, layout, format),
        Encoding::Ascii => Ok(None),
    }
}

/// How an element is read on the fast route.
enum Plan<'h> {
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

fn read<O: ByteOrder>(
    header: &Header,
    payload: &[u8],
    layout: &Layout,
    format: &dyn Fn(String) -> Error,
) -> Result<Option<PolygonSoup>> {
    let Some(plans) = header
        .elements
        .values()
        .map(plan)
        .collect::<Option<Vec<_>>>()
    else {
        return Ok(None);
    };
    let mut soup = PolygonSoup::default();
    let mut pos = 0usize;
    let truncated = |element: &ElementDef, number: usize, pos: usize| {
        format(format!(
            "truncated file: the payload ends in {} {number} of {} (at byte {pos} of the payload)",
            element.name, element.count
        ))
    };
    for (element, plan) in header.elements.values().zip(plans) {
        match plan {
            Plan::Vertices { stride, axes } => {
                let bytes = element
                    .count
                    .checked_mul(stride)
                    .filter(|&n| n <= payload.len() - pos)
                    .ok_or_else(|| {
                        truncated(element, (payload.len() - pos) / stride.max(1), pos)
                    })?;
                let records = &payload[pos..pos + bytes];
                pos += bytes;
                if stride == 0 {
                    // Only possible with no properties at all, which the header check rejects.
                    return Ok(None);
                }
                soup.positions.reserve(element.count);
                soup.positions.extend(records.chunks_exact(stride).map(|r| {
                    glam::DVec3::new(
                        decode_f64::<O>(axes[0].1, &r[axes[0].0..]),
                        decode_f64::<O>(axes[1].1, &r[axes[1].0..]),
                        decode_f64::<O>(axes[2].1, &r[axes[2].0..]),
                    )
                }));
            }
            Plan::Skip { stride } => {
                let bytes = element
                    .count
                    .checked_mul(stride)
                    .filter(|&n| n <= payload.len() - pos)
                    .ok_or_else(|| {
                        truncated(element, (payload.len() - pos) / stride.max(1), pos)
                    })?;
                pos += bytes;
            }
            Plan::Lists { kind, count, index } => {
                let (count_size, index_size) = (size_of(count), size_of(index));
                if kind == FaceKind::Polygons {
                    // Room for triangles, never more than the payload can hold.
                    let faces = element
                        .count
                        .min((payload.len() - pos) / (count_size + 3 * index_size));
                    soup.indices.reserve(3 * faces);
                }
                let mut list: Vec<i64> = Vec::new();
                for number in 0..element.count {
                    let start = pos;
                    if payload.len() - pos < count_size {
                        return Err(truncated(element, number, start));
                    }
                    let n = decode_i64::<O>(count, &payload[pos..]);
                    pos += count_size;
                    let n = usize::try_from(n).map_err(|_| {
                        format(format!(
                            "{} {number} has a negative list length ({n})",
                            element.name
                        ))
                    })?;
                    let bytes = n
                        .checked_mul(index_size)
                        .filter(|&b| b <= payload.len() - pos)
                        .ok_or_else(|| truncated(element, number, start))?;
                    list.clear();
                    list.extend(
                        payload[pos..pos + bytes]
                            .chunks_exact(index_size)
                            .map(|b| decode_i64::<O>(index, b)),
                    );
                    pos += bytes;
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
    Ok(Some(soup))
}
