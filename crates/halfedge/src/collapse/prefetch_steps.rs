//! Prefetching what a split or a collapse some steps ahead will touch (see
//! [`crate::prefetch`]).

use crate::handle::NONE;
use crate::mesh::Mesh;

use super::record::{Step, FACE_LEFT, FACE_RIGHT};

impl Mesh {
    /// Prefetches, for a split or a collapse of `step` some steps ahead, what the record
    /// names directly: the collapsed edge's two halfedges (whose fields give the rest, see
    /// [`prefetch_sides`](Self::prefetch_sides)), its slot state, the two positions, `v0`'s
    /// slot state, and the outgoing halfedges of the record's vertices that the split
    /// writes (`all_vertices`: of all of them, which the collapse reads). A hierarchy
    /// calls this a few steps ahead (see [`crate::prefetch`]).
    #[inline]
    pub(crate) fn prefetch_step(&self, step: &Step, all_vertices: bool) {
        use crate::prefetch::prefetch;
        let h = step.v0v1 as usize;
        prefetch(&self.he, h);
        prefetch(&self.he, h ^ 1);
        self.halfedge_slots_.prefetch_state(h);
        self.vertex_slots_.prefetch_state(step.v0 as usize);
        prefetch(&self.positions, step.v0 as usize);
        prefetch(&self.positions, step.v1 as usize);
        if all_vertices {
            prefetch(&self.vertex_conn, step.v0 as usize);
        }
        for (v, _, changed) in step.restored_vertices() {
            if changed || all_vertices {
                prefetch(&self.vertex_conn, v as usize);
            }
        }
    }

    /// The second stage of [`prefetch_step`](Self::prefetch_step), a few steps later
    /// (it reads the collapsed edge's halfedges): the other halfedges of the two
    /// triangles and their slot states, and the two faces' slot states.
    #[inline]
    pub(crate) fn prefetch_sides(&self, step: &Step) {
        use crate::prefetch::prefetch;
        if self.he.get((step.v0v1 | 1) as usize).is_none() {
            return;
        }
        let s = self.sides(step.v0v1);
        for x in [s.vlv0, s.v0vr] {
            if x != NONE {
                prefetch(&self.he, x as usize);
                prefetch(&self.he, (x ^ 1) as usize);
                self.halfedge_slots_.prefetch_state(x as usize);
            }
        }
        for x in [s.v1vl, s.vrv1] {
            if x != NONE {
                prefetch(&self.he, x as usize);
            }
        }
        for f in [s.fl, s.fr] {
            if f != NONE {
                self.face_slots_.prefetch_state(f as usize);
            }
        }
    }

    /// The third stage, a few steps after [`prefetch_sides`](Self::prefetch_sides) (it
    /// reads the removed edges' halfedges): the neighbours of `v0 → vl` and `vr → v0` in
    /// their outer faces, whose links a collapse or a split rewrites (those of the other
    /// removed halfedges are in the two triangles), and those outer faces' halfedges: for
    /// a collapse (`collapse`), which compares them, both; for a split, those it restores.
    #[inline]
    pub(crate) fn prefetch_links(&self, step: &Step, collapse: bool) {
        use crate::prefetch::prefetch;
        if self.he.get((step.v0v1 | 1) as usize).is_none() {
            return;
        }
        let s = self.sides(step.v0v1);
        for (bit, x) in [(FACE_LEFT, s.vlv0), (FACE_RIGHT, s.v0vr)] {
            if let Some(rec) = self.he.get((x ^ 1) as usize) {
                prefetch(&self.he, rec.prev as usize);
                prefetch(&self.he, rec.next as usize);
                if collapse || step.changed & bit != 0 {
                    prefetch(&self.face_conn, rec.face as usize);
                }
            }
        }
    }

    /// Prefetches the `step`-th halfedge the split of `r` moves back to `v0` (the walk
    /// around `v1` from the halfedge after which they start), reading the earlier ones of
    /// the walk, which an earlier call should have brought into cache: the walk is a chain
    /// of dependent loads, so a hierarchy pipelines it over several splits ahead. The mesh
    /// may not yet be as the split will find it (the splits in between have not run), so
    /// the walk may go astray; that only costs a useless prefetch.
    #[inline]
    pub(crate) fn prefetch_moved(&self, r: &Step, step: u32) {
        if step < r.moved {
            // The walk starts at the successor of `v0v1` (`v1 → vl`, or on the boundary
            // the next boundary halfedge).
            if let Some(rec) = self.he.get(r.v0v1 as usize) {
                self.prefetch_ring(rec.next as usize, step);
            }
        }
    }

    /// Prefetches, for collapsing `r` again, the `step`-th outgoing halfedge after the
    /// one `v0` has (the collapse walks `v0`'s whole ring, a chain of dependent loads like
    /// the split's walk: see [`prefetch_moved`](Self::prefetch_moved)). Step 0 also brings
    /// in the line that tells whether each record vertex is on the boundary.
    #[inline]
    pub(crate) fn prefetch_collapse_ring(&self, r: &Step, step: u32) {
        let Some(&first) = self.vertex_conn.get(r.v0 as usize) else {
            return;
        };
        if step == 0 {
            for v in [r.v0, r.v1, r.vl, r.vr] {
                if let Some(&h) = self.vertex_conn.get(v as usize) {
                    crate::prefetch::prefetch(&self.he, h as usize);
                }
            }
        }
        if step <= r.moved + 1 {
            self.prefetch_ring(first as usize, step);
        }
    }

    /// Walks `step + 1` counter-clockwise rotations (`opposite(prev(k))`) from halfedge
    /// `k` and prefetches the halfedge reached; stops at an index out of range.
    #[inline]
    fn prefetch_ring(&self, mut k: usize, step: u32) {
        for _ in 0..=step {
            match self.he.get(k) {
                Some(rec) => k = (rec.prev ^ 1) as usize,
                None => return,
            }
        }
        crate::prefetch::prefetch(&self.he, k);
    }
}
