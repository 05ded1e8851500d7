//! Placing the two vertices of a split: everything a refinement does besides the mesh's
//! connectivity. A split's placement reads only positions (the survivor's and its
//! recorded neighbours'), the detail coefficients, the marks and the positions before an
//! edit, and writes only positions; the split itself reads and writes only connectivity.
//! So a long refinement after an edit runs the two apart, on two threads
//! ([`super::Hierarchy::split_beside`]), with the same results bit for bit as one split
//! after the other ([`super::Hierarchy::split_next`]).

use glam::DVec3;

use super::ahead::{DETAIL_PREFETCH_DISTANCE, LIST_PREFETCH_DISTANCE};
use super::detail::{Collapsed, Details, Placement};
use super::marks::{Marks, IN_REGION, UNMARKED};
use super::placements::Placements;
use super::rests::Rest;
use crate::collapse::Step;
use crate::prefetch::prefetch;

/// The parts of a hierarchy that place split vertices (see the module docs).
pub(super) struct Placer<'a> {
    pub(super) steps: &'a [Step],
    pub(super) placements: &'a Placements,
    pub(super) details: &'a Details,
    pub(super) marks: &'a mut Marks,
    pub(super) rests: &'a mut [Rest],
    pub(super) positions: &'a mut [DVec3],
}

impl Placer<'_> {
    /// Where splitting record `r` puts `v0` and `v1` (the positions are those before the
    /// split), and the mark both take: at their recorded positions when the positions are
    /// `clean` (as the hierarchy's own steps left them), at the image of them by the
    /// survivor's affine map or field when it has one that fits, else by the local frame.
    #[inline]
    pub(super) fn placement(&mut self, r: usize, clean: bool) -> (Placement, u32) {
        let record = &self.steps[r];
        let at = Collapsed {
            p0: record.p0,
            p1: record.p1,
            placed: self.placements.placed(r, record),
        };
        let i1 = record.v1 as usize;
        let mut mark = UNMARKED;
        let placement = match self.positions.get(i1) {
            Some(&anchor) if !clean => {
                mark = self.marks.of(i1);
                let motion = (mark < IN_REGION)
                    .then(|| Details::motion_placement(&self.marks.maps[mark as usize], anchor, at))
                    .flatten();
                match motion {
                    Some(both) => Placement::At(both),
                    None => {
                        // An affine mark that does not fit still says "in the region".
                        if mark != UNMARKED {
                            mark = IN_REGION;
                        }
                        let free = mark == IN_REGION;
                        self.place(r, anchor, at, free)
                    }
                }
            }
            _ => Placement::Recorded,
        };
        (placement, mark)
    }

    /// After the split of record `r`: puts `v0` and `v1` where `placement` says (their
    /// recorded positions for [`Placement::Recorded`]), gives both the survivor's `mark`,
    /// and brings the positions before the edit along.
    #[inline]
    pub(super) fn settle(&mut self, r: usize, placement: Placement, mark: u32) {
        let record = &self.steps[r];
        let (i0, i1) = (record.v0 as usize, record.v1 as usize);
        let [q0, q1] = match placement {
            Placement::At(both) => both,
            Placement::Recorded | Placement::NeedsBefore => [record.p0, record.p1],
        };
        if let (Some(_), Some(_)) = (self.positions.get(i0), self.positions.get(i1)) {
            self.positions[i0] = q0;
            self.positions[i1] = q1;
        }
        if !self.marks.is_empty() {
            self.marks.set(i0, mark);
            self.marks.set(i1, mark);
        }
        if let Some(rest) = self.rests.iter_mut().rev().find(|rest| rest.serves(r)) {
            // Where the record's baseline has them (the positions the edits started from),
            // once the copy is in use (else `sync_rest` catches up when it is needed).
            if rest.active && rest.synced == r + 1 {
                if let (Some(_), Some(_)) = (rest.positions.get(i0), rest.positions.get(i1)) {
                    rest.positions[i0] = record.p0.to_array();
                    rest.positions[i1] = record.p1.to_array();
                }
                rest.synced = r;
            }
        }
    }

    /// Prefetches what placing the records a few splits after `r` will read: their
    /// neighbours' positions, the survivor's position and its baseline, and further ahead
    /// their neighbour lists, coefficients and placements (see [`crate::prefetch`]).
    #[inline]
    pub(super) fn prefetch_ahead(&self, r: usize) {
        if let Some(ahead) = r.checked_sub(DETAIL_PREFETCH_DISTANCE) {
            self.details.prefetch(ahead, self.positions);
            let record = &self.steps[ahead];
            prefetch(self.positions, record.v1 as usize);
            if let Some(rest) = self.rests.last().filter(|rest| rest.active) {
                for v in [record.v0, record.v1] {
                    prefetch(&rest.positions, v as usize);
                }
            }
        }
        if let Some(far) = r.checked_sub(LIST_PREFETCH_DISTANCE) {
            self.details.prefetch_record(far);
            self.placements.prefetch(far);
        }
    }

    /// Where splitting record `r` puts its vertices (local frames, no affine mark that
    /// fits): the survivor is at `anchor`, `in_region` when it is in an edit's region.
    /// Brings the positions before the edit up to date first when the split needs them.
    fn place(&mut self, r: usize, anchor: DVec3, at: Collapsed, in_region: bool) -> Placement {
        let serving = self.rests.iter().rposition(|rest| rest.serves(r));
        let synced = serving.is_some_and(|k| self.rests[k].active && self.rests[k].synced == r + 1);
        let given = serving.filter(|_| synced);
        let first = self.place_with(r, anchor, at, in_region, given, given.is_none());
        match (first, serving) {
            (Placement::NeedsBefore, Some(k)) => {
                self.sync_rest(k, r + 1);
                self.rests[k].active = true;
                self.place_with(r, anchor, at, in_region, Some(k), false)
            }
            (Placement::NeedsBefore, None) => {
                self.place_with(r, anchor, at, in_region, None, false)
            }
            (placement, _) => placement,
        }
    }

    /// [`Details::placement`] with the positions before the edit of `self.rests[rest]`
    /// (or, with `None` and `can_ask`, asking for them when a copy serves the record).
    fn place_with(
        &self,
        r: usize,
        anchor: DVec3,
        at: Collapsed,
        in_region: bool,
        rest: Option<usize>,
        can_ask: bool,
    ) -> Placement {
        let can_ask = can_ask && self.rests.iter().any(|rest| rest.serves(r));
        let rest = rest.map(|k| &self.rests[k]);
        let (marks, positions) = (&*self.marks, &*self.positions);
        // The motion of a link vertex's whole cluster when it is exact: none for a vertex
        // that stayed and is in no region; its affine map's motion at the point for a
        // vertex whose affine mark fits it (its whole cluster lands on that map); `None`
        // for the others (they interpolate).
        let exact = |i: u32, p: DVec3| -> Option<DVec3> {
            let i = i as usize;
            let at_rest = rest?.positions.get(i).map(|&q| DVec3::from_array(q))?;
            let mark = marks.of(i);
            if mark == UNMARKED {
                return (positions[i] == at_rest).then_some(DVec3::ZERO);
            }
            let map = marks.maps.get(mark as usize)?;
            let at = Collapsed {
                p0: p,
                p1: p,
                placed: at_rest,
            };
            Details::motion_placement(map, positions[i], at).map(|[q, _]| q - p)
        };
        let before = rest.map(|rest| {
            (
                rest.positions.as_slice(),
                &exact as &dyn Fn(u32, DVec3) -> Option<DVec3>,
            )
        });
        self.details
            .placement(r, positions, before, anchor, at, in_region, can_ask)
    }

    /// Puts into `self.rests[k]` the positions of the splits it has not taken in yet,
    /// down to record `down_to` (as the splits would have, in their order).
    pub(super) fn sync_rest(&mut self, k: usize, down_to: usize) {
        let rest = &mut self.rests[k];
        if rest.synced <= down_to {
            return;
        }
        for record in self.steps[down_to..rest.synced].iter().rev() {
            let (i0, i1) = (record.v0 as usize, record.v1 as usize);
            if let (Some(_), Some(_)) = (rest.positions.get(i0), rest.positions.get(i1)) {
                rest.positions[i0] = record.p0.to_array();
                rest.positions[i1] = record.p1.to_array();
            }
        }
        rest.synced = down_to;
    }
}
