//! Walking a hierarchy: level by level or record by record, coarser (collapsing again)
//! or finer (splitting, on one thread or two), with prefetching and atomic rollback.

use glam::DVec3;

use super::ahead::{
    prefetch_splits_after, COLLAPSE_LINKS_PREFETCH_DISTANCE, COLLAPSE_PREFETCH_DISTANCE,
    COLLAPSE_SIDES_PREFETCH_DISTANCE, RING_PREFETCH_DISTANCES, SPLIT_BESIDE_MIN,
};
use super::detail::{self, Collapsed, Placement};
use super::marks::Marks;
use super::placer;
use super::rests::Rest;
use super::submesh_labels::LabelBinding;
use super::Hierarchy;
use crate::binding::Binding;
use crate::collapse::Step;
use crate::error::{Error, Result};
use crate::handle::HalfedgeId;
use crate::labels::{self};
use crate::mesh::Mesh;

impl Hierarchy {
    /// Moves to `level` (coarser or finer).
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] for a level that does not exist; a refused split or
    /// collapse if the topology was changed behind the hierarchy's back.
    pub fn go_to_level(&mut self, level: usize) -> Result<()> {
        let end = self.check_level(level)?;
        self.seek(end)
    }

    /// Coarsens to `level` (which must not be finer than the current position).
    ///
    /// # Errors
    /// As [`go_to_level`](Self::go_to_level), and [`Error::InvalidArgument`] when `level`
    /// is finer than the current position.
    pub fn coarsen_to(&mut self, level: usize) -> Result<()> {
        let end = self.check_level(level)?;
        if end < self.applied {
            return Err(Error::InvalidArgument(format!(
                "coarsen_to({level}): the mesh is already coarser than level {level}"
            )));
        }
        self.seek(end)
    }

    /// Refines to `level` (which must not be coarser than the current position).
    ///
    /// # Errors
    /// As [`go_to_level`](Self::go_to_level), and [`Error::InvalidArgument`] when `level`
    /// is coarser than the current position.
    pub fn refine_to(&mut self, level: usize) -> Result<()> {
        let end = self.check_level(level)?;
        if end > self.applied {
            return Err(Error::InvalidArgument(format!(
                "refine_to({level}): the mesh is already finer than level {level}"
            )));
        }
        self.seek(end)
    }

    /// Collapses or splits record by record until `applied` records are collapsed.
    ///
    /// The walk is atomic: when a step is refused (the topology was changed behind the
    /// hierarchy's back), the mesh, its positions and attributes, and the hierarchy are
    /// put back exactly as they were before the walk, and the error is returned.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] when `applied` exceeds the number of records; a refused
    /// split or collapse (the topology was changed behind the hierarchy's back).
    pub fn seek(&mut self, applied: usize) -> Result<()> {
        if applied > self.records.len() {
            return Err(Error::InvalidArgument(format!(
                "seek({applied}): the hierarchy has {} records",
                self.records.len()
            )));
        }
        if self.trusts_mesh() {
            // Every step since the build was the hierarchy's own: no step can be refused.
            return self.walk(applied);
        }
        let saved = Saved::take(self, applied);
        match self.walk(applied) {
            Ok(()) => Ok(()),
            Err(e) => {
                saved.restore(self);
                Err(e)
            }
        }
    }

    /// [`seek`](Self::seek) without the way back.
    pub(super) fn walk(&mut self, applied: usize) -> Result<()> {
        while self.applied < applied {
            self.collapse_next()?;
        }
        let finer = self.applied > applied;
        // A walk finer stops at the level of every copy of the positions before an edit
        // that it passes, to note there the faces the edits turned over (as `split_next`
        // does when it gets there), then goes on.
        let mut stops: Vec<usize> = self
            .rests
            .iter()
            .map(|rest| rest.ceil)
            .filter(|&ceil| applied < ceil && ceil < self.applied)
            .collect();
        stops.sort_unstable_by(|a, b| b.cmp(a));
        stops.dedup();
        stops.push(applied);
        for stop in stops {
            if self.applied > stop {
                self.note_turned_by_edit();
            }
            if self.applied >= stop + SPLIT_BESIDE_MIN
                && self.trusts_mesh()
                && rayon::current_num_threads() > 1
            {
                let clean = self.positions_are_clean();
                self.split_beside(stop, clean)?;
            }
            while self.applied > stop {
                self.split_next()?;
            }
        }
        if finer {
            self.unfold_refinement();
        }
        Ok(())
    }

    /// The attached labels when splitting record `r` must classify its vertex (the labels
    /// were defined at a coarser position).
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] when the label attribute was removed from the mesh.
    fn labels_to_classify(&self, r: usize) -> Result<Option<LabelBinding>> {
        match self.labels.filter(|b| r < b.defined_at) {
            Some(binding) if !self.mesh.has_attribute(binding.attribute) => {
                Err(Error::InvalidArgument(
                    "the label attribute attached to the hierarchy was removed from its mesh \
                     (detach_labels, or attach_labels again)"
                        .into(),
                ))
            }
            labels => Ok(labels),
        }
    }

    /// The parts of the hierarchy that place split vertices ([`placer::Placer`]).
    pub(super) fn placer(&mut self) -> placer::Placer<'_> {
        placer::Placer {
            steps: &self.records.steps,
            placements: &self.placements,
            details: &self.details,
            marks: &mut self.marks,
            rests: &mut self.rests,
            positions: &mut self.mesh.positions,
        }
    }

    /// [`split_next`](Self::split_next) until `applied` records are collapsed, for a
    /// hierarchy that trusts its mesh (`clean`: its positions are as its own steps left
    /// them, so every vertex goes to its recorded position): the placements run on this thread,
    /// the splits (connectivity and labels) on another, each record split once its
    /// placement is known. The two touch disjoint data (see [`placer`]), and the result
    /// is the same bit for bit. A placement that overflows stops the walk just above its
    /// record, as `split_next` does.
    ///
    /// # Errors
    /// [`Error::Overflow`] as `split_next` (the records above it are split); an
    /// [`Error::InvalidArgument`] when the label attribute was removed (nothing changed).
    pub(super) fn split_beside(&mut self, applied: usize, clean: bool) -> Result<()> {
        use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
        let top = self.applied;
        let labels = self.labels_to_classify(applied)?;
        // Every record from `placed` up is placed; `failed`: no more will be.
        let placed = AtomicUsize::new(top);
        let failed = AtomicBool::new(false);
        let mut positions = std::mem::take(&mut self.mesh.positions);
        let steps = &self.records.steps;
        let mut placer = placer::Placer {
            steps,
            placements: &self.placements,
            details: &self.details,
            marks: &mut self.marks,
            rests: &mut self.rests,
            positions: &mut positions,
        };
        let mesh = &mut self.mesh;
        // How far the splits went (read after both threads are done, even after a panic).
        let split_to = AtomicUsize::new(top);
        /// Tells the splitting thread to stop when the placing thread ends early, by an
        /// error or by a panic (a user's field that panics), so that it never waits on.
        struct StopOnExit<'a>(&'a AtomicBool);
        impl Drop for StopOnExit<'_> {
            fn drop(&mut self) {
                self.0.store(true, Ordering::Release);
            }
        }
        let walked = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            rayon::join(
                || -> Result<()> {
                    let _stop = StopOnExit(&failed);
                    for r in (applied..top).rev() {
                        if !clean {
                            placer.prefetch_ahead(r);
                        }
                        let (placement, mark) = placer.placement(r, clean);
                        if let Placement::At([q0, q1]) = placement {
                            if !(q0.is_finite() && q1.is_finite()) {
                                failed.store(true, Ordering::Release);
                                let record = &steps[r];
                                return Err(Error::Overflow(format!(
                                    "splitting vertex {} from {} would put them at {q0} and {q1}",
                                    record.v0, record.v1
                                )));
                            }
                        }
                        placer.settle(r, placement, mark);
                        placed.store(r, Ordering::Release);
                    }
                    Ok(())
                },
                || -> usize {
                    let mut r = top;
                    while r > applied {
                        let next = r - 1;
                        // This thread never gets ahead of the placements: a split is made
                        // only once its record's placement is known to be good.
                        let mut spins = 0u32;
                        while placed.load(Ordering::Acquire) > next {
                            if failed.load(Ordering::Acquire)
                                && placed.load(Ordering::Acquire) > next
                            {
                                return r;
                            }
                            // Waiting long means the placing thread is not running (a busy
                            // machine): give the core back rather than spin.
                            spins += 1;
                            if spins < 1 << 12 {
                                std::hint::spin_loop();
                            } else {
                                std::thread::yield_now();
                            }
                        }
                        prefetch_splits_after(mesh, steps, next);
                        let record = &steps[next];
                        mesh.vertex_split_connectivity(record);
                        if let Some(binding) = labels.filter(|b| next < b.defined_at) {
                            let v0 = mesh.vh(record.v0);
                            // A label attribute removed by the user since it was
                            // attached has nothing left to label.
                            let _removed = labels::classify_split(mesh, binding.attribute, v0);
                        }
                        r = next;
                        split_to.store(r, Ordering::Relaxed);
                    }
                    r
                },
            )
        }));
        // Whatever happened, the mesh gets its positions back and the hierarchy the
        // position its splits reached: every record split was placed first.
        self.mesh.positions = positions;
        let split_to = split_to.into_inner();
        self.applied = split_to;
        self.consistent_from = self.consistent_from.min(split_to);
        self.stamp = Some(self.mesh.binding());
        self.tag_level();
        match walked {
            Ok((placing, _)) => placing,
            Err(panic) => std::panic::resume_unwind(panic),
        }
    }

    /// One step coarser: collapses the next record again. The survivor goes to its build
    /// time position; if an endpoint moved since the record was taken (an edit at a
    /// finer level), it goes to the same place relative to the edge's current endpoints.
    /// The record's detail coefficients are recomputed from the current positions. Drops
    /// the affine marks ([`mark_affine`](Self::mark_affine)). Returns `false` at the
    /// coarsest level.
    ///
    /// # Errors
    /// The kernel's refusal ([`Error::CollapseRefused`]) if the topology was changed
    /// behind the hierarchy's back; nothing is changed then.
    pub fn collapse_next(&mut self) -> Result<bool> {
        let r = self.applied;
        // Decided before the collapse changes the mesh's topology stamp.
        let clean = self.positions_are_clean();
        if r < self.records.len() {
            // A copy of the positions before an edit that has not taken in every split
            // since catches up now: the collapse replaces the record it would read them from.
            for k in 0..self.rests.len() {
                self.placer().sync_rest(k, r);
            }
        }
        let Some(&old) = self.records.get(r) else {
            return Ok(false);
        };
        if !self.trusts_mesh() {
            self.distrust();
        }
        // The edge must still join the record's two vertices (checked on the slot indices,
        // which may be out of range on a mesh the hierarchy cannot vouch for).
        let (i0, i1, hi) = (old.v0 as usize, old.v1 as usize, old.v0v1 as usize);
        let mesh = &self.mesh;
        let joins = mesh.halfedge_slots_.is_live_index(hi)
            && mesh.he.get(hi ^ 1).map(|rec| rec.to) == Some(old.v0)
            && mesh.he.get(hi).map(|rec| rec.to) == Some(old.v1)
            && mesh.vertex_slots_.is_live_index(i0)
            && mesh.vertex_slots_.is_live_index(i1);
        if !joins
            || (self.stamp.is_none() && !self.details.in_bounds(r, self.mesh.positions().len()))
        {
            return Err(Error::CollapseRefused {
                halfedge: if hi < mesh.he.len() {
                    mesh.hh(old.v0v1)
                } else {
                    HalfedgeId::default()
                },
                reason: crate::collapse::CollapseVeto::EdgeDeleted,
            });
        }
        let (v0, v1, h) = (mesh.vh(old.v0), mesh.vh(old.v1), mesh.hh(old.v0v1));
        if let Some(ahead) = self.records.get(r + COLLAPSE_PREFETCH_DISTANCE) {
            self.mesh.prefetch_step(ahead, true);
        }
        if let Some(ahead) = self.records.get(r + COLLAPSE_SIDES_PREFETCH_DISTANCE) {
            self.mesh.prefetch_sides(ahead);
        }
        if let Some(ahead) = self.records.get(r + COLLAPSE_LINKS_PREFETCH_DISTANCE) {
            self.mesh.prefetch_links(ahead, true);
        }
        for (step, distance) in RING_PREFETCH_DISTANCES.into_iter().enumerate() {
            if let Some(ahead) = self.records.get(r + distance) {
                self.mesh.prefetch_collapse_ring(ahead, step as u32);
            }
        }
        let p0 = self.mesh.positions[i0];
        let p1 = self.mesh.positions[i1];
        let p = self.placements.again(r, &old, p0, p1);
        if !p.is_finite() {
            return Err(Error::Overflow(format!(
                "collapsing {v0} → {v1} would put {v1} at {p} (positions {p0} and {p1})"
            )));
        }
        // While the hierarchy trusts its mesh, the topology is exactly the one the build
        // collapsed this record in (every step since was its own, and splits are exact
        // inverses), so the collapse is as legal as it was then.
        let (record, fingerprint) = if self.stamp.is_some() {
            let fingerprint = self.records.fingerprints[r];
            (
                self.mesh.recollapse_unchecked(&old, fingerprint),
                fingerprint,
            )
        } else {
            self.mesh.collapse_checked(h)?
        };
        if !clean {
            self.refreshes.record(r);
            let at = Collapsed {
                p0: record.p0,
                p1: record.p1,
                placed: p,
            };
            self.details.refresh(r, self.mesh.positions(), at);
        }
        self.mesh.positions[i1] = p;
        self.placements.set_placed(r, p);
        self.records.steps[r] = record;
        self.records.fingerprints[r] = fingerprint;
        self.applied += 1;
        // Marks describe motion relative to the records below the current position; a
        // record collapsed again now holds the moved positions.
        self.marks.clear();
        for rest in &mut self.rests {
            rest.ceil = rest.ceil.min(r);
        }
        self.rests.retain(|rest| rest.floor < rest.ceil);
        self.stamp = self.stamp.map(|_| self.mesh.binding());
        self.tag_level();
        Ok(true)
    }

    /// True while positions are exactly as the hierarchy's own steps left them (see
    /// `clean_positions`); false for good after the first outside edit or topology change.
    pub(super) fn positions_are_clean(&mut self) -> bool {
        let clean = self.positions_unedited() && self.trusts_mesh();
        if !clean {
            self.clean_positions = None;
        }
        clean
    }

    /// One step finer: splits the last collapsed record, re-inserting `v0` (same handle)
    /// and placing both endpoints by the detail coefficients (see [`DetailMode`](crate::hierarchy::DetailMode)): at
    /// their recorded positions when the survivor did not move, at the image of them by
    /// the survivor's affine mark when it has one, else by the local frame. Sub-mesh
    /// labels defined at a finer position are kept; otherwise `v0` is classified by the
    /// paper's Fig. 4 rule. Returns `false` at the input level.
    ///
    /// # Errors
    /// The kernel's refusal ([`Error::SplitRefused`]) if the topology was changed behind
    /// the hierarchy's back; nothing is changed then.
    pub fn split_next(&mut self) -> Result<bool> {
        if self.applied == 0 {
            return Ok(false);
        }
        // Leaving the level of an edit: the faces the edit turned over are noted first.
        self.note_turned_by_edit();
        let r = self.applied - 1;
        let trusted = self.trusts_mesh();
        if !trusted {
            self.distrust();
            if !self.details.in_bounds(r, self.mesh.positions().len()) {
                return Err(Error::SplitRefused(format!(
                    "a neighbour recorded for the split of vertex {} from {} is not a \
                     vertex of this mesh",
                    self.records[r].v0, self.records[r].v1
                )));
            }
        }
        let clean = self.positions_are_clean();
        let (placement, mark) = self.placer().placement(r, clean);
        prefetch_splits_after(&self.mesh, &self.records.steps, r);
        if !clean {
            self.placer().prefetch_ahead(r);
        }
        let record = self.records[r];
        // Checked before the split: nothing may change if the step cannot complete.
        if let Placement::At([q0, q1]) = placement {
            if !(q0.is_finite() && q1.is_finite()) {
                return Err(Error::Overflow(format!(
                    "splitting vertex {} from {} would put them at {q0} and {q1}",
                    record.v0, record.v1
                )));
            }
        }
        let classify = self.labels_to_classify(r)?;
        if trusted {
            self.mesh.vertex_split_unchecked(&record);
        } else {
            let fingerprint = self.records.fingerprints[r];
            let Some(public) = self.mesh.public_record(&record, fingerprint, self.origin()) else {
                return Err(Error::SplitRefused(format!(
                    "the record of vertex {} split from {} names elements this mesh does \
                     not have",
                    record.v0, record.v1
                )));
            };
            self.mesh.vertex_split(&public)?;
        }
        // The split put v0 and v1 back at p0 and p1; the placement moves them on.
        self.placer().settle(r, placement, mark);
        self.consistent_from = self.consistent_from.min(r);
        if let Some(binding) = classify {
            let v0 = self.mesh.vh(record.v0);
            // A label attribute removed by the user since it was attached has nothing
            // left to label.
            let _removed = labels::classify_split(&mut self.mesh, binding.attribute, v0);
        }
        self.applied = r;
        self.stamp = self.stamp.map(|_| self.mesh.binding());
        self.tag_level();
        Ok(true)
    }
}

impl Hierarchy {
    /// Tags the mesh with this hierarchy and its position, while the hierarchy trusts it
    /// (see [`crate::Binding`]).
    #[inline]
    pub(super) fn tag_level(&mut self) {
        if self.stamp.is_some() {
            self.mesh.provenance.tag_level(self.id, self.applied);
        }
    }
}

/// What a walk of a hierarchy that does not trust its mesh may change, saved to undo a
/// refused walk ([`Hierarchy::seek`]).
struct Saved {
    pub(super) mesh: Mesh,
    pub(super) range: std::ops::Range<usize>,
    pub(super) records: Vec<Step>,
    pub(super) fingerprints: Vec<u64>,
    pub(super) placements: (Vec<u8>, Vec<(DVec3, f64)>),
    pub(super) details: detail::SavedRange,
    pub(super) marks: Marks,
    pub(super) rests: Vec<Rest>,
    pub(super) consistent_from: usize,
    pub(super) applied: usize,
    pub(super) clean_positions: Option<Binding>,
}

impl Saved {
    pub(super) fn take(h: &Hierarchy, applied: usize) -> Self {
        let range = h.applied.min(applied)..h.applied.max(applied);
        Self {
            mesh: h.mesh.clone(),
            records: h.records.steps[range.clone()].to_vec(),
            fingerprints: h.records.fingerprints[range.clone()].to_vec(),
            placements: h.placements.save(range.clone()),
            details: h.details.save(range.clone()),
            range,
            marks: h.marks.clone(),
            rests: h.rests.clone(),
            consistent_from: h.consistent_from,
            applied: h.applied,
            clean_positions: h.clean_positions,
        }
    }

    pub(super) fn restore(self, h: &mut Hierarchy) {
        // The mesh keeps its identity; its topology changed and changed back, so it gets
        // a new stamp (nobody who saw the walk's stamps may trust it).
        let previous = std::mem::replace(&mut h.mesh, self.mesh);
        h.mesh.provenance.succeed(&previous.provenance);
        h.records.steps[self.range.clone()].copy_from_slice(&self.records);
        h.records.fingerprints[self.range.clone()].copy_from_slice(&self.fingerprints);
        h.placements.restore(self.range.clone(), self.placements);
        h.details.restore(self.range, self.details);
        h.marks = self.marks;
        h.rests = self.rests;
        h.consistent_from = self.consistent_from;
        h.applied = self.applied;
        h.clean_positions = self.clean_positions;
        h.distrust();
    }
}
