//! Sections `MARK` (what the user said about edits at the current level: affine and region
//! marks) and `REST` (the positions edits started from, which refinement interpolates
//! the edits' motion from).

use glam::DAffine3;

use super::bytes::{get_f64, get_u32, put_f64, put_u32, In, Out};
use super::details::{read_arrays, write_arrays};
use crate::error::{Error, Result};
use crate::hierarchy::marks::Marks;
use crate::hierarchy::motion::Motion;
use crate::hierarchy::rests::{Rest, MAX_RESTS};

/// Bytes of one affine map: its 3 × 3 matrix (columns) and translation.
const AFFINE: usize = 12 * 8;

/// Checks that every mark can be written: affine maps can, fields (closures) cannot.
///
/// # Errors
/// [`Error::InvalidArgument`] naming the first vertex slot marked with a field.
pub(super) fn check_marks(marks: &Marks) -> Result<()> {
    let field = |m: u32| matches!(marks.maps.get(m as usize), Some(Motion::Field(_)));
    if let Some(i) = marks.of_vertex.iter().position(|&m| field(m)) {
        return Err(Error::InvalidArgument(format!(
            "save: vertex slot {i} is marked with a field (mark_field), a closure a file \
             cannot hold; refine first (the walk applies it), or clear_marks, or mark the \
             motion with mark_affine / mark_region"
        )));
    }
    Ok(())
}

/// Writes section `MARK` (the caller has called [`check_marks`]: a field no vertex uses
/// any more is written as the identity, which no vertex reads).
pub(super) fn write_marks(marks: &Marks, out: &mut impl Out) {
    out.array(&marks.of_vertex, 4, |&m, b| put_u32(b, m));
    out.array(&marks.maps, AFFINE, |m, b| {
        let a = match m {
            Motion::Affine(a) => *a,
            Motion::Field(_) => DAffine3::IDENTITY,
        };
        for (k, x) in a.to_cols_array().into_iter().enumerate() {
            put_f64(&mut b[8 * k..], x);
        }
    });
    out.usize(marks.compacted());
}

/// Reads section `MARK`: finite maps, every vertex's mark none, the region or one of the
/// maps.
pub(super) fn read_marks(input: &mut In<'_>) -> Result<Marks> {
    let of_vertex = input.array(4, "vertex marks", get_u32)?;
    let maps = input.array(AFFINE, "affine maps", |b| {
        let cols: [f64; 12] = std::array::from_fn(|k| get_f64(&b[8 * k..]));
        DAffine3::from_cols_array(&cols)
    })?;
    let compacted = input.usize("the compacted maps")?;
    input.end()?;
    if let Some(k) = maps.iter().position(|a| !a.is_finite()) {
        return Err(input.error(format!("affine map {k} is not finite")));
    }
    let maps = maps.into_iter().map(Motion::Affine).collect();
    input.check(Marks::from_raw_parts(of_vertex, maps, compacted))
}

/// Writes section `REST`.
pub(super) fn write_rests(rests: &[Rest], out: &mut impl Out) {
    out.usize(rests.len());
    for rest in rests {
        out.usize(rest.floor);
        out.usize(rest.ceil);
        out.usize(rest.synced);
        out.bool(rest.active);
        write_arrays(&rest.positions, out);
    }
}

/// Reads section `REST` for `records` records and `vertex_slots` vertex slots: at most
/// [`MAX_RESTS`] copies, each serving a non-empty range of records within the records,
/// synced at most up to its top, with a finite position per vertex slot.
pub(super) fn read_rests(
    input: &mut In<'_>,
    records: usize,
    vertex_slots: usize,
) -> Result<Vec<Rest>> {
    let n = input.usize_at_most(
        MAX_RESTS,
        "the number of copies of positions before an edit",
    )?;
    let mut rests = Vec::with_capacity(n);
    for k in 0..n {
        let floor = input.usize("a copy's first record")?;
        let ceil = input.usize("a copy's last record")?;
        let synced = input.usize("a copy's synced record")?;
        let active = input.bool("a copy's active flag")?;
        if !(floor < ceil && ceil <= records && synced <= ceil) {
            return Err(input.error(format!(
                "copy {k} serves records {floor}..{ceil} synced to {synced}, of {records} records"
            )));
        }
        let positions = read_arrays(input, "positions before an edit")?;
        if positions.len() != vertex_slots {
            return Err(input.error(format!(
                "copy {k} has {} positions for {vertex_slots} vertex slots",
                positions.len()
            )));
        }
        if positions.iter().flatten().any(|x| !x.is_finite()) {
            return Err(input.error(format!("copy {k} has a position that is not finite")));
        }
        rests.push(Rest {
            positions,
            floor,
            ceil,
            synced,
            active,
            turned_by_edit: None,
        });
    }
    input.end()?;
    Ok(rests)
}
