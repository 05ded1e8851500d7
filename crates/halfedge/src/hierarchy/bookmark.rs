use glam::DVec3;

use super::marks::Marks;
use super::Hierarchy;
use crate::binding::{Binding, Stale};
use crate::error::Result;

/// Where a hierarchy was: its level, the positions there, its marks and bookkeeping
/// ([`Hierarchy::bookmark`]), for [`Hierarchy::return_to`] (see the
/// [docs above](Self)).
///
/// Going back exactly to where a hierarchy was: an undo of a level change.
///
/// A walk coarser collapses the current mesh *again*: each record is made anew from the
/// current positions (so an edit made at a finer level is carried to the coarser ones,
/// as the seed paper wants). That is the wrong thing for an undo. Edit at level 2, walk
/// to level 0, undo the walk and undo the edit: the records now hold the edited fine
/// positions, and refining again no longer gives the input. A [`LevelBookmark`] remembers
/// the level, the positions there and the hierarchy's bookkeeping;
/// [`Hierarchy::return_to`] walks back with the records as they are (a split changes no
/// record, so after a walk finer they are still those of the bookmark) and puts the rest
/// back, bit for bit. Whatever was done at the finer levels in between is dropped.
#[derive(Clone, Debug)]
pub struct LevelBookmark {
    hierarchy: u64,
    /// The mesh as the bookmark found it (for the [`Stale`] error that refuses it).
    binding: Binding,
    /// The hierarchy's [`Refreshes::count`] when it was taken.
    refreshes: u64,
    applied: usize,
    positions: Vec<DVec3>,
    marks: Marks,
    consistent_from: usize,
    clean: bool,
}

impl LevelBookmark {
    /// The number of records collapsed at the bookmark (see [`Hierarchy::applied`]).
    pub fn applied(&self) -> usize {
        self.applied
    }

    /// The positions at the bookmark, by vertex slot.
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// Heap bytes held (the positions and the marks).
    pub fn heap_bytes(&self) -> usize {
        self.positions.capacity() * std::mem::size_of::<DVec3>()
            + self.marks.of_vertex.capacity() * std::mem::size_of::<u32>()
    }
}

impl Hierarchy {
    /// A bookmark of where the hierarchy is now, to come back to it exactly with
    /// [`return_to`](Self::return_to) (an undo of a level change). Holds a copy of the
    /// positions.
    pub fn bookmark(&self) -> LevelBookmark {
        LevelBookmark {
            hierarchy: self.id,
            binding: self.mesh.binding(),
            refreshes: self.refreshes.count,
            applied: self.applied,
            positions: self.mesh.positions.clone(),
            marks: self.marks.clone(),
            consistent_from: self.consistent_from,
            clean: self.positions_unedited(),
        }
    }

    /// Puts the hierarchy back where `bookmark` was taken, bit for bit: at its level, with
    /// the positions, marks and bookkeeping it had then. Whatever was done at finer
    /// levels since is dropped: unlike a walk coarser ([`seek`](Self::seek)), the records
    /// are not made again from the current mesh (see the [docs above](Self)). Walking
    /// back finer than the current level is a plain walk, then the positions are put back.
    ///
    /// # Errors
    /// [`Error::Stale`](crate::Error::Stale) when the bookmark is of another hierarchy (a clone, a
    /// rebuild: [`edit_input`](Self::edit_input),
    /// [`constrain_to_labels`](Self::constrain_to_labels)), when records were made again
    /// below its level since it was taken (a walk coarser from a finer edited level), or
    /// when the hierarchy does not trust its mesh (its connectivity was changed behind its
    /// back). Nothing is changed then: [`seek`](Self::seek) to the bookmark's
    /// [`applied`](LevelBookmark::applied) is the way back that remains. Walking back
    /// finer can fail as [`seek`](Self::seek) can (a marked field that overflows).
    pub fn return_to(&mut self, bookmark: &LevelBookmark) -> Result<()> {
        let refuse = |what: &'static str| -> Result<()> {
            Err(Stale::new(what, bookmark.binding, self.mesh.binding()).into())
        };
        if bookmark.hierarchy != self.id {
            return refuse("the bookmark (taken on another hierarchy)");
        }
        if !self
            .refreshes
            .kept_below(bookmark.refreshes, bookmark.applied)
        {
            return refuse(
                "the bookmark (records below its level were made again since it was taken)",
            );
        }
        if !self.trusts_mesh() {
            return refuse(
                "the bookmark (the mesh's connectivity was changed behind the hierarchy's back)",
            );
        }
        if bookmark.applied > self.records.len()
            || bookmark.positions.len() != self.mesh.positions.len()
        {
            // Cannot happen for a bookmark of this hierarchy whose records were kept.
            return refuse("the bookmark (it does not fit the hierarchy)");
        }
        if bookmark.applied < self.applied {
            // A walk finer changes no record: the walk itself is the way back.
            self.walk(bookmark.applied)?;
        }
        while self.applied < bookmark.applied {
            self.collapse_keeping_record();
        }
        self.mesh.positions.copy_from_slice(&bookmark.positions);
        self.marks = bookmark.marks.clone();
        self.consistent_from = bookmark.consistent_from;
        // Clean only if no record was made again since: records above the bookmark's
        // level made again from an edit hold that edit, so the next walk coarser must make
        // them again from these positions.
        let remade = self.refreshes.count != bookmark.refreshes;
        self.clean_positions = (bookmark.clean && !remade).then_some(self.mesh.binding());
        self.tag_level();
        Ok(())
    }

    /// Collapses the next record again as it is (the hierarchy trusts its mesh): the
    /// record, its placement and its coefficients stay, the survivor goes to its recorded
    /// placement, and the copies of the positions before an edit that took in the
    /// record's split give it back.
    fn collapse_keeping_record(&mut self) {
        let r = self.applied;
        let old = self.records.steps[r];
        let fingerprint = self.records.fingerprints[r];
        self.mesh.recollapse_unchecked(&old, fingerprint);
        let placed = self.placements.placed(r, &old);
        self.mesh.positions[old.v1 as usize] = placed;
        for rest in &mut self.rests {
            // The split of `r` put `p0` and `p1` in (see `Placer::settle`); before it the
            // survivor was at its placement there.
            if rest.serves(r) && rest.synced <= r {
                if let Some(q) = rest.positions.get_mut(old.v1 as usize) {
                    *q = placed.to_array();
                }
                rest.synced = r + 1;
            }
        }
        self.applied += 1;
        self.stamp = Some(self.mesh.binding());
    }
}

/// The records made again from the current mesh ([`Hierarchy::collapse_next`] after an
/// edit), as runs of consecutive records made one after the other, the latest
/// [`MAX_RUNS`]: enough to tell whether a record below a bookmark's level was made again
/// since it was taken.
#[derive(Clone, Debug, Default)]
pub(crate) struct Refreshes {
    /// Records made again so far; the `k`-th (from 1) is the event `k`.
    count: u64,
    /// `(first event, first record, length)`: events `first + j` made record
    /// `record + j` again, for `j < length`.
    runs: Vec<(u64, usize, usize)>,
    /// Events before this one were dropped from `runs`.
    forgotten_before: u64,
}

/// Runs of records made again kept by [`Refreshes`] (a run is a walk coarser, one user
/// action).
const MAX_RUNS: usize = 256;

impl Refreshes {
    /// Record `r` was made again.
    pub(crate) fn record(&mut self, r: usize) {
        self.count += 1;
        let event = self.count;
        match self.runs.last_mut() {
            Some((first, record, len)) if *first + *len as u64 == event && *record + *len == r => {
                *len += 1;
            }
            _ => {
                if self.runs.len() == MAX_RUNS {
                    let (first, _, len) = self.runs.remove(0);
                    self.forgotten_before = first + len as u64;
                }
                self.runs.push((event, r, 1));
            }
        }
    }

    /// The count, the runs and where the runs kept start (for the hierarchy file).
    pub(crate) fn raw_parts(&self) -> (u64, &[(u64, usize, usize)], u64) {
        (self.count, &self.runs, self.forgotten_before)
    }

    /// The bookkeeping from [`raw_parts`](Self::raw_parts) read back from a file,
    /// checked: at most [`MAX_RUNS`] runs, each non-empty, in order, within `count`
    /// events and starting at or after `forgotten_before`. Says what is wrong otherwise.
    pub(crate) fn from_raw_parts(
        count: u64,
        runs: Vec<(u64, usize, usize)>,
        forgotten_before: u64,
    ) -> Result<Self, String> {
        if runs.len() > MAX_RUNS {
            return Err(format!(
                "{} runs of records made again (at most {MAX_RUNS})",
                runs.len()
            ));
        }
        if count > 1 << 62 {
            return Err(format!("{count} records made again"));
        }
        let mut next = forgotten_before.max(1);
        for &(first, record, len) in &runs {
            let end = (len as u64).checked_add(first);
            if len == 0
                || first < next
                || end.is_none_or(|e| e > count + 1)
                || record.checked_add(len).is_none()
            {
                return Err(format!(
                    "a run of records made again ({first}, {record}, {len}) is out of order or range"
                ));
            }
            next = first + len as u64;
        }
        if forgotten_before > count + 1 {
            return Err(format!("{forgotten_before} events forgotten of {count}"));
        }
        Ok(Self {
            count,
            runs,
            forgotten_before,
        })
    }

    /// True when no record below `applied` was made again after the first `seen`
    /// events.
    fn kept_below(&self, seen: u64, applied: usize) -> bool {
        if seen + 1 < self.forgotten_before {
            return false;
        }
        self.runs.iter().all(|&(first, record, len)| {
            // The first of the run's events after `seen`.
            let k = (seen + 1).saturating_sub(first);
            k >= len as u64 || record + k as usize >= applied
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refreshes_tell_which_records_were_made_again_after_a_bookmark() {
        let mut r = Refreshes::default();
        // A walk coarser from record 10 to 15, another from 3 to 5.
        for k in 10..15 {
            r.record(k);
        }
        let mid_walk = r.count; // after records 10..15
        for k in 3..5 {
            r.record(k);
        }
        assert_eq!(r.runs.len(), 2);
        // Before anything: records 3 and 4 were made again.
        assert!(r.kept_below(0, 3));
        assert!(!r.kept_below(0, 4));
        // After the first walk: only 3 and 4 count.
        assert!(r.kept_below(mid_walk, 3));
        assert!(!r.kept_below(mid_walk, 5));
        // Taken in the middle of the first walk (after records 10, 11): 12 is the lowest.
        let mut s = Refreshes::default();
        for k in 10..15 {
            s.record(k);
        }
        assert!(s.kept_below(2, 12));
        assert!(!s.kept_below(2, 13));
        assert!(s.kept_below(s.count, usize::MAX));
    }

    #[test]
    fn refreshes_forget_old_runs_and_then_refuse_old_bookmarks() {
        let mut r = Refreshes::default();
        for k in 0..MAX_RUNS + 3 {
            // Separate runs: each one record, far apart.
            r.record(1000 * k + 7);
        }
        assert_eq!(r.runs.len(), MAX_RUNS);
        assert!(!r.kept_below(0, 0), "a bookmark older than what is kept");
        assert!(r.kept_below(r.count, usize::MAX));
    }
}
