//! Section `DETL`: the detail coefficients of every record (the scheme, the neighbour
//! lists and their offsets, the coefficients, and with local frames each record's ring
//! and ring centre).

use super::bytes::{get_u32, get_vec3, put_f64, put_u32, put_vec3, In, Out};
use crate::error::Result;
use crate::hierarchy::detail::{DetailMode, DetailVecs, Details};

/// Writes section `DETL`.
pub(super) fn write(details: &Details, out: &mut impl Out) {
    out.u8(match details.mode() {
        DetailMode::LocalFrame => 0,
        DetailMode::Translation => 1,
    });
    let parts = details.raw_parts();
    out.array(parts.offsets, 4, |&o, b| put_u32(b, o));
    out.array(parts.neighbours, 4, |&i, b| put_u32(b, i));
    out.array(parts.coefficients, 48, |&[a, c], b| {
        put_vec3(b, a);
        put_vec3(&mut b[24..], c);
    });
    out.array(parts.framed, 1, |&r, b| b[0] = r);
    out.array(parts.centres, 24, |&c, b| put_vec3(b, c));
}

/// Reads section `DETL` for `records` records of a mesh with `vertex_slots` vertex slots
/// (see [`Details::from_raw_parts`] for what is checked).
pub(super) fn read(input: &mut In<'_>, records: usize, vertex_slots: usize) -> Result<Details> {
    let mode = match input.u8()? {
        0 => DetailMode::LocalFrame,
        1 => DetailMode::Translation,
        b => return Err(input.error(format!("unknown detail mode {b}"))),
    };
    let offsets = input.array(4, "list offsets", get_u32)?;
    let neighbours = input.array(4, "neighbours", get_u32)?;
    let coefficients = input.array(48, "coefficients", |b| [get_vec3(b), get_vec3(&b[24..])])?;
    let framed = input.array(1, "frame rings", |b| b[0])?;
    let centres = input.array(24, "ring centres", get_vec3)?;
    input.end()?;
    input.check(Details::from_raw_parts(
        mode,
        DetailVecs {
            neighbours,
            offsets,
            coefficients,
            framed,
            centres,
        },
        records,
        vertex_slots,
    ))
}

/// Writes a list of positions given as arrays (the positions before an edit).
pub(super) fn write_arrays(points: &[[f64; 3]], out: &mut impl Out) {
    out.array(points, 24, |p, b| {
        put_f64(b, p[0]);
        put_f64(&mut b[8..], p[1]);
        put_f64(&mut b[16..], p[2]);
    });
}

/// Reads a list written by [`write_arrays`].
pub(super) fn read_arrays(input: &mut In<'_>, what: &str) -> Result<Vec<[f64; 3]>> {
    input.array(24, what, |b| get_vec3(b).to_array())
}
