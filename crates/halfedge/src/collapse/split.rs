//! The vertex split: the checked inverse of a collapse ([`Mesh::vertex_split`]) and the
//! unchecked one a hierarchy uses.

use crate::error::{Error, Result};
use crate::handle::{HalfedgeId, VertexId, NONE};
use crate::mesh::{HalfedgeRec, Mesh};

use super::record::{CollapseRecord, Step, FACE_LEFT, FACE_RIGHT};

/// # Vertex split
impl Mesh {
    /// The first outgoing halfedge of `v` counter-clockwise after `h` that is not `h`.
    pub(super) fn next_outgoing_alive(&self, v: VertexId, h: HalfedgeId) -> Option<HalfedgeId> {
        self.outgoing_halfedges(v)
            .find(|&k| k != h && self.halfedge_slots_.is_live(k))
    }

    /// Undoes [`collapse`](Self::collapse): revives `v0` (same handle), its edges and the
    /// faces `fl`, `fr`, restores every link, and puts `v0` at `p0` and `v1` at `p1`.
    ///
    /// # Errors
    /// [`Error::SplitRefused`], saying why, when the record does not fit the mesh (see
    /// the [`CollapseRecord`](crate::CollapseRecord) docs): made on another mesh, already split, freed by garbage
    /// collection, its fields changed, or its neighbourhood changed since the collapse.
    /// Nothing is changed then.
    pub fn vertex_split(&mut self, r: &CollapseRecord) -> Result<()> {
        if let Err(why) = self.split_fits(r) {
            return Err(Error::SplitRefused(format!(
                "{why} (record of {} → {})",
                r.v0, r.v1
            )));
        }
        if let Some(why) = self.split_event_conflict(r.step.v0, r.mesh, r.count, r.tracked) {
            return Err(Error::SplitRefused(format!(
                "{why} (record of {} → {})",
                r.v0, r.v1
            )));
        }
        self.vertex_split_unchecked(&r.step);
        Ok(())
    }

    /// Whether [`vertex_split_unchecked`](Self::vertex_split_unchecked) of `r` gives back
    /// exactly the neighbourhood the collapse of `r` removed, and so a valid mesh: every
    /// element the split reads or restores is as the collapse left it. Reads only
    /// (bounds-checked where the mesh might not be the record's).
    fn split_fits(&self, r: &CollapseRecord) -> std::result::Result<(), &'static str> {
        if !self.provenance.is_own_history(r.mesh, r.count) {
            return Err(
                "the record was made on another mesh (another instance, or a clone \
                        made after the collapse)",
            );
        }
        // From here on the record's slot indices are in range: the mesh's arrays only
        // grow, and they were this long when the collapse was made.
        if self.is_valid_vertex(r.v0) {
            return Err("v0 is live: the record was already split");
        }
        if !self.is_deleted_vertex(r.v0) {
            return Err("v0 is not a removed vertex any more (freed by garbage_collection)");
        }
        if !self.is_valid_vertex(r.v1) {
            return Err("v1 is not a live vertex (a later collapse removed it)");
        }
        let hs = &self.halfedge_slots_;
        if !hs.is_tombstone(r.v0v1) || !hs.is_tombstone(r.v1v0) {
            return Err("a halfedge the collapse removed is live again or was freed");
        }
        // The tombstones of v0v1 and v1v0 are as the collapse left them: the record's
        // fields must agree with them and with its compact form.
        let st = &r.step;
        let Some(d) = self.derive(st) else {
            return Err("the record's halfedges are not in this mesh");
        };
        let s = &d.sides;
        match self.public_record(st, r.fingerprint, (r.mesh, r.count)) {
            Some(p)
                if (p.v0v1, p.v1v0, p.v0, p.v1, p.vl, p.vr, p.fl, p.fr)
                    == (r.v0v1, r.v1v0, r.v0, r.v1, r.vl, r.vr, r.fl, r.fr)
                    && (p.v1vl, p.vlv0, p.v0vr, p.vrv1) == (r.v1vl, r.vlv0, r.v0vr, r.vrv1)
                    && (p.p0.to_array(), p.p1.to_array()) == (r.p0.to_array(), r.p1.to_array()) => {
            }
            _ => return Err("the record's fields were changed"),
        }
        for x in [s.vlv0, s.v0vr] {
            if x != NONE && (!hs.is_tombstone(self.hh(x)) || !hs.is_tombstone(self.hh(x ^ 1))) {
                return Err("a halfedge the collapse removed is live again or was freed");
            }
        }
        for f in [r.fl, r.fr].into_iter().flatten() {
            if !self.face_slots_.is_tombstone(f) {
                return Err("a face the collapse removed is live again or was freed");
            }
        }
        for x in [r.v1vl, r.vrv1].into_iter().flatten() {
            if !hs.is_live(x) {
                return Err("an edge the collapse kept was removed since");
            }
        }
        if !(r.p0.is_finite() && r.p1.is_finite()) {
            return Err("the record's positions are not finite");
        }
        let live = |i: u32| hs.is_live_index(i as usize);
        for &[x, _, new] in &d.links[..d.n_links] {
            if !live(x) || self.he[x as usize].next != new {
                return Err(
                    "a link the collapse wrote has changed (a later collapse, split \
                            or edit nearby was not undone)",
                );
            }
        }
        for &[g, _, new] in &d.face_halfedges {
            if g != NONE
                && (!self.face_slots_.is_live_index(g as usize)
                    || self.face_conn[g as usize] != new)
            {
                return Err("a face beside the collapsed edge has changed");
            }
        }
        let revived = |i: u32| s.removed(st.v0v1).any(|x| x & !1 == i & !1);
        let vertices = [
            st.v0,
            st.v1,
            if st.vl == NONE { st.v1 } else { st.vl },
            if st.vr == NONE { st.v1 } else { st.vr },
        ];
        for (v, &[old, new]) in vertices.into_iter().zip(&d.vertex_halfedges) {
            if v != st.v0 && !self.vertex_slots_.is_live_index(v as usize) {
                return Err("a neighbour vertex was removed");
            }
            if self.vertex_conn[v as usize] != new {
                return Err("a vertex halfedge the collapse set has changed");
            }
            if old != NONE && !live(old) && !revived(old) {
                return Err("a halfedge the split would give back to a vertex was removed");
            }
        }
        let start = d.start as usize;
        if !live(d.start) || self.he[start ^ 1].to != st.v1 {
            return Err("the anchor halfedge around v1 has changed");
        }
        let mut k = start;
        for _ in 0..st.moved {
            match self.he.get(k) {
                Some(rec) if live(rec.prev) => k = (rec.prev ^ 1) as usize,
                _ => return Err("the ring of v1 is broken"),
            }
            if k == start || self.he[k ^ 1].to != st.v1 {
                return Err("v1 has fewer edges than the collapse moved to it");
            }
        }
        if self.split_fingerprint(st) != Some(r.fingerprint) {
            return Err(
                "the neighbourhood of the collapsed edge has changed since the \
                        collapse (the ring of v1, the edges beside the removed ones, or the \
                        removed elements)",
            );
        }
        Ok(())
    }

    /// The split of `step` without its checks, for a caller that knows the connectivity
    /// is what the collapse left (a hierarchy whose mesh kept its
    /// connectivity (its [`binding`](Self::binding)) since its own last step, or
    /// [`vertex_split`](Self::vertex_split) once it checked). The two triangles and the
    /// rewritten links are read back from the tombstones of the removed halfedges.
    pub(crate) fn vertex_split_unchecked(&mut self, step: &Step) {
        self.vertex_split_connectivity(step);
        self.positions[step.v0 as usize] = step.p0;
        self.positions[step.v1 as usize] = step.p1;
    }

    /// [`vertex_split_unchecked`](Self::vertex_split_unchecked) without the positions:
    /// the connectivity alone (the caller places `v0` and `v1`; the positions are not
    /// read, so they may be held elsewhere meanwhile).
    pub(crate) fn vertex_split_connectivity(&mut self, step: &Step) {
        self.touch_topology();
        self.waiting.remove(step.v0);
        let h = step.v0v1;
        let s = self.sides(h);
        // `v1 → vl`, or on the boundary the next boundary halfedge.
        let start = self.he[h as usize].next;
        self.vertex_slots_.revive(step.v0 as usize);
        self.n_vertices += 1;
        for x in s.removed(h) {
            self.halfedge_slots_.revive(x as usize);
            self.halfedge_slots_.revive((x ^ 1) as usize);
            self.n_halfedges += 2;
        }
        for f in [s.fl, s.fr] {
            if f != NONE {
                self.face_slots_.revive(f as usize);
                self.n_faces += 1;
            }
        }
        // The same walk as the check: reviving changed no `prev` or `opposite`.
        let v0 = step.v0;
        let mut k = start as usize;
        for _ in 0..step.moved {
            k = (self.he[k].prev ^ 1) as usize;
            self.he[k ^ 1].to = v0;
        }
        // The removed halfedges kept their `next` and `prev` as tombstones, and every
        // link the collapse rewrote (the `links_of` the collapse) was a `next` or a
        // `prev` that named one of them: pointing their neighbours back at them restores
        // every link.
        for x in s.removed(h) {
            for k in [x, x ^ 1] {
                let HalfedgeRec { next, prev, .. } = self.he[k as usize];
                self.he[prev as usize].next = k;
                self.he[next as usize].prev = k;
            }
        }
        // The kept halfedges return to their faces.
        if s.fl != NONE {
            self.he[s.v1vl as usize].face = s.fl;
        }
        if s.fr != NONE {
            self.he[s.vrv1 as usize].face = s.fr;
        }
        // A face beyond a removed edge whose halfedge the collapse re-chose (from the
        // removed `v0 → vl` to the kept `v1 → vl`, or from `vr → v0` to `vr → v1`) gets
        // the removed one back.
        for (bit, x) in [(FACE_LEFT, s.vlv0), (FACE_RIGHT, s.v0vr)] {
            if step.changed & bit != 0 {
                let y = x ^ 1;
                let g = self.he[y as usize].face;
                self.face_conn[g as usize] = y;
            }
        }
        for (v, before, changed) in step.restored_vertices() {
            // Most of these did not change; not writing them saves fetching their lines.
            if changed {
                self.vertex_conn[v as usize] = before;
            }
        }
    }
}
