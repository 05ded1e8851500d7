//! Section `META`: the build's method and options, the level table, the position in the
//! sequence, the bookkeeping a walk reads, how the build ended and whether labels are
//! attached.

use super::bytes::{In, Out};
use crate::error::Result;
use crate::hierarchy::bookmark::Refreshes;
use crate::hierarchy::detail::DetailMode;
use crate::hierarchy::options::{HierarchyOptions, Method, SurvivorPlacement};
use crate::hierarchy::outcome::{BuildOutcome, Refusals, Relaxation, StopReason};
use crate::hierarchy::Hierarchy;

/// What section `META` holds, read back (checked on its own; [`super::validate`] checks
/// it against the other sections).
pub(super) struct Meta {
    pub(super) method: Method,
    pub(super) options: HierarchyOptions,
    pub(super) applied: usize,
    pub(super) consistent_from: usize,
    /// No position was changed since the build but by the hierarchy's own steps.
    pub(super) clean: bool,
    pub(super) level_ends: Vec<usize>,
    pub(super) level_faces: Vec<usize>,
    /// The record count when the attached labels were defined, when labels are attached.
    pub(super) labels_defined_at: Option<usize>,
    pub(super) outcome: BuildOutcome,
    pub(super) refreshes: Refreshes,
}

fn method_byte(method: Method) -> u8 {
    match method {
        Method::Rounds => 0,
        Method::Qem => 1,
    }
}

fn mode_byte(mode: DetailMode) -> u8 {
    match mode {
        DetailMode::LocalFrame => 0,
        DetailMode::Translation => 1,
    }
}

/// Writes section `META` of `h`.
pub(super) fn write(h: &Hierarchy, out: &mut impl Out) {
    out.u8(method_byte(h.method));
    let o = &h.options;
    // The options' method byte carries the survivor placement too (2 more for the
    // quadric's): files of the paper's placement read as before.
    out.u8(method_byte(o.method) + 2 * u8::from(o.placement == SurvivorPlacement::Quadric));
    for x in [
        o.max_normal_deviation,
        o.max_flip_angle,
        o.level_ratio,
        o.boundary_weight,
    ] {
        out.f64(x);
    }
    out.usize(o.target_faces);
    out.usize(o.max_levels);
    out.f64(o.max_error);
    out.f64(o.min_level_reduction);
    out.u8(mode_byte(o.detail_mode));
    out.bool(o.respect_labels);
    out.bool(o.relax_when_stalled);
    out.usize(h.applied);
    out.usize(h.consistent_from);
    out.bool(h.positions_unedited());
    let as_u64 = |x: &usize, b: &mut [u8]| super::bytes::put_u64(b, *x as u64);
    out.array(&h.level_ends, 8, as_u64);
    out.array(&h.level_faces, 8, as_u64);
    match h.labels {
        Some(binding) => {
            out.bool(true);
            out.usize(binding.defined_at);
        }
        None => out.bool(false),
    }
    let outcome = &h.outcome;
    out.usize(outcome.target_faces);
    out.usize(outcome.faces);
    let (stop, refusals) = match &outcome.stop {
        StopReason::TargetReached => (0, None),
        StopReason::MaxLevels => (1, None),
        StopReason::Exhausted { refusals } => (2, *refusals),
        StopReason::Stalled { refusals } => (3, *refusals),
    };
    out.u8(stop);
    match refusals {
        Some(r) => {
            out.bool(true);
            for x in [r.locked, r.planarity, r.topology, r.error_bound, r.geometry] {
                out.usize(x);
            }
        }
        None => out.bool(false),
    }
    out.array(&outcome.relaxations, 32, |r, b| {
        super::bytes::put_u64(b, r.level as u64);
        super::bytes::put_u64(&mut b[8..], r.faces as u64);
        super::bytes::put_f64(&mut b[16..], r.max_normal_deviation);
        super::bytes::put_f64(&mut b[24..], r.max_flip_angle);
    });
    let (count, runs, forgotten_before) = h.refreshes.raw_parts();
    out.u64(count);
    out.array(runs, 24, |&(first, record, len), b| {
        super::bytes::put_u64(b, first);
        super::bytes::put_u64(&mut b[8..], record as u64);
        super::bytes::put_u64(&mut b[16..], len as u64);
    });
    out.u64(forgotten_before);
}

fn method_of(input: &In<'_>, byte: u8) -> Result<Method> {
    match byte {
        0 => Ok(Method::Rounds),
        1 => Ok(Method::Qem),
        b => Err(input.error(format!("unknown method {b}"))),
    }
}

/// Reads section `META`: every field in its range, the options valid, the level table
/// starting at 0 and strictly increasing.
pub(super) fn read(input: &mut In<'_>) -> Result<Meta> {
    let byte = input.u8()?;
    let method = method_of(input, byte)?;
    let byte = input.u8()?;
    let (options_method, placement) = match byte {
        0 | 1 => (method_of(input, byte)?, SurvivorPlacement::Midpoint),
        2 | 3 => (method_of(input, byte - 2)?, SurvivorPlacement::Quadric),
        b => return Err(input.error(format!("unknown method and placement {b}"))),
    };
    let max_normal_deviation = input.f64()?;
    let max_flip_angle = input.f64()?;
    let level_ratio = input.f64()?;
    let boundary_weight = input.f64()?;
    let target_faces = input.usize("target_faces")?;
    let max_levels = input.usize("max_levels")?;
    let max_error = input.f64()?;
    let min_level_reduction = input.f64()?;
    let detail_mode = match input.u8()? {
        0 => DetailMode::LocalFrame,
        1 => DetailMode::Translation,
        b => return Err(input.error(format!("unknown detail mode {b}"))),
    };
    let respect_labels = input.bool("respect_labels")?;
    let relax_when_stalled = input.bool("relax_when_stalled")?;
    let options = HierarchyOptions {
        method: options_method,
        max_normal_deviation,
        max_flip_angle,
        level_ratio,
        boundary_weight,
        target_faces,
        max_levels,
        max_error,
        min_level_reduction,
        detail_mode,
        respect_labels,
        relax_when_stalled,
        placement,
    };
    if let Err(e) = options.validate() {
        return Err(input.error(format!("the build options: {e}")));
    }
    let applied = input.usize("the records collapsed")?;
    let consistent_from = input.usize("consistent_from")?;
    let clean = input.bool("the clean-positions flag")?;
    let level_ends = input.array(8, "level ends", super::bytes::get_u64)?;
    let level_faces = input.array(8, "level face counts", super::bytes::get_u64)?;
    let to_usize = |v: Vec<u64>, what: &str| -> Result<Vec<usize>> {
        v.into_iter()
            .map(|x| usize::try_from(x).map_err(|_| input.error(format!("{what} {x} too large"))))
            .collect()
    };
    let level_ends = to_usize(level_ends, "level end")?;
    let level_faces = to_usize(level_faces, "level face count")?;
    if level_ends.first() != Some(&0) || level_ends.windows(2).any(|w| w[0] >= w[1]) {
        return Err(
            input.error("the level table does not start at record 0 or is not strictly increasing")
        );
    }
    if level_faces.len() != level_ends.len() {
        return Err(input.error(format!(
            "{} level face counts for {} levels",
            level_faces.len(),
            level_ends.len()
        )));
    }
    let labels_defined_at = if input.bool("the labels flag")? {
        Some(input.usize("the labels' position")?)
    } else {
        None
    };
    let outcome_target = input.usize("the outcome's target")?;
    let outcome_faces = input.usize("the outcome's faces")?;
    let stop = input.u8()?;
    let refusals = if input.bool("the refusals flag")? {
        let mut r = [0usize; 5];
        for x in &mut r {
            *x = input.usize("a refusal count")?;
        }
        Some(Refusals {
            locked: r[0],
            planarity: r[1],
            topology: r[2],
            error_bound: r[3],
            geometry: r[4],
        })
    } else {
        None
    };
    let stop = match stop {
        0 => StopReason::TargetReached,
        1 => StopReason::MaxLevels,
        2 => StopReason::Exhausted { refusals },
        3 => StopReason::Stalled { refusals },
        b => return Err(input.error(format!("unknown stop reason {b}"))),
    };
    let relaxations = input.array(32, "relaxations", |b| Relaxation {
        level: super::bytes::get_u64(b) as usize,
        faces: super::bytes::get_u64(&b[8..]) as usize,
        max_normal_deviation: super::bytes::get_f64(&b[16..]),
        max_flip_angle: super::bytes::get_f64(&b[24..]),
    })?;
    let count = input.u64()?;
    let runs = input.array(24, "runs of records made again", |b| {
        (
            super::bytes::get_u64(b),
            super::bytes::get_u64(&b[8..]) as usize,
            super::bytes::get_u64(&b[16..]) as usize,
        )
    })?;
    let forgotten_before = input.u64()?;
    let refreshes = input.check(Refreshes::from_raw_parts(count, runs, forgotten_before))?;
    input.end()?;
    Ok(Meta {
        method,
        options,
        applied,
        consistent_from,
        clean,
        level_ends,
        level_faces,
        labels_defined_at,
        outcome: BuildOutcome {
            target_faces: outcome_target,
            faces: outcome_faces,
            stop,
            relaxations,
        },
        refreshes,
    })
}
