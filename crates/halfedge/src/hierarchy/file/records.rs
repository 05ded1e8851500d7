//! Sections `RECS` (the compact collapse records and their fingerprints) and `PLAC`
//! (where each collapse put its survivor).

use super::bytes::{get_u32, get_u64, get_vec3, put_u32, put_u64, put_vec3, In, Out};
use crate::collapse::Step;
use crate::error::Result;
use crate::handle::NONE;
use crate::hierarchy::placements::Placements;
use crate::hierarchy::records::Records;

/// Bytes of one record in the file: `p0`, `p1`, then `v0v1`, `v0`, `v1`, `vl`, `vr`, the
/// three halfedges before the collapse, the moved count (all `u32`), the changed bits.
pub(super) const STEP: usize = 48 + 9 * 4 + 1;

/// Writes section `RECS`.
pub(super) fn write(records: &Records, out: &mut impl Out) {
    out.array(&records.steps, STEP, |s, b| {
        put_vec3(b, s.p0);
        put_vec3(&mut b[24..], s.p1);
        let (before, moved, changed) = s.split_fields();
        for (k, x) in [
            s.v0v1, s.v0, s.v1, s.vl, s.vr, before[0], before[1], before[2], moved,
        ]
        .into_iter()
        .enumerate()
        {
            put_u32(&mut b[48 + 4 * k..], x);
        }
        b[84] = changed;
    });
    out.array(&records.fingerprints, 8, |&f, b| put_u64(b, f));
}

fn decode_step(b: &[u8]) -> Step {
    let u = |k: usize| get_u32(&b[48 + 4 * k..]);
    Step::from_fields(
        [get_vec3(b), get_vec3(&b[24..])],
        [u(0), u(1), u(2), u(3), u(4)],
        ([u(5), u(6), u(7)], u(8), b[84]),
    )
}

/// Reads section `RECS` for a mesh of `(vertex, halfedge)` slot counts: every index of
/// every record in range (`NONE` only where a side may be missing), `v0 != v1`, known
/// changed bits, finite positions, one fingerprint per record.
pub(super) fn read(input: &mut In<'_>, (nv, nh): (usize, usize)) -> Result<Records> {
    let steps = input.array(STEP, "records", decode_step)?;
    let fingerprints = input.array(8, "fingerprints", get_u64)?;
    input.end()?;
    if fingerprints.len() != steps.len() {
        return Err(input.error(format!(
            "{} fingerprints for {} records",
            fingerprints.len(),
            steps.len()
        )));
    }
    let v = |i: u32| (i as usize) < nv;
    let v_or_none = |i: u32| i == NONE || v(i);
    let h_or_none = |i: u32| i == NONE || (i as usize) < nh;
    for (r, s) in steps.iter().enumerate() {
        let (before, moved, changed) = s.split_fields();
        let sound = v(s.v0)
            && v(s.v1)
            && s.v0 != s.v1
            && v_or_none(s.vl)
            && v_or_none(s.vr)
            && (s.v0v1 as usize) < nh
            && before.into_iter().all(h_or_none)
            && (moved as usize) <= nh
            && changed <= Step::CHANGED_BITS
            && s.p0.is_finite()
            && s.p1.is_finite();
        if !sound {
            return Err(input.error(format!(
                "record {r} names an element out of range, or a position that is not finite"
            )));
        }
    }
    Ok(Records {
        steps,
        fingerprints,
        origin: None,
    })
}

/// Writes section `PLAC`.
pub(super) fn write_placements(placements: &Placements, out: &mut impl Out) {
    let (rules, stored) = placements.raw_parts();
    out.array(rules, 1, |&r, b| b[0] = r);
    out.array(stored, 32, |&(p, t), b| {
        put_vec3(b, p);
        super::bytes::put_f64(&mut b[24..], t);
    });
}

/// Reads section `PLAC` for `records` records: a known rule per record, a finite stored
/// placement for every record whose rule says so.
pub(super) fn read_placements(input: &mut In<'_>, records: usize) -> Result<Placements> {
    let rules = input.array(1, "placement rules", |b| b[0])?;
    let stored = input.array(32, "stored placements", |b| {
        (get_vec3(b), super::bytes::get_f64(&b[24..]))
    })?;
    input.end()?;
    if let Some(r) = stored
        .iter()
        .position(|(p, t)| !(p.is_finite() && t.is_finite()))
    {
        return Err(input.error(format!("stored placement {r} is not finite")));
    }
    input.check(Placements::from_raw_parts(rules, stored, records))
}
