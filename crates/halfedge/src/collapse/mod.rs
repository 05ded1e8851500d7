mod prefetch_steps;
mod record;
mod split;
#[cfg(test)]
mod tests;
mod waiting;

use crate::error::{Error, Result};
use crate::handle::{slot, HalfedgeId, VertexId, NONE};
use crate::mesh::Mesh;

pub use record::CollapseRecord;
pub(crate) use record::Step;
use record::{FACE_LEFT, FACE_RIGHT};
use waiting::Waiting;
pub(crate) use waiting::WaitingCollapses;

/// Why [`Mesh::is_collapse_ok`] refuses a collapse (OpenMesh's
/// `TriConnectivity::is_collapse_ok`, check for check, in this order).
///
/// Halfedge collapse and its exact inverse, the vertex split.
///
/// Collapsing `h = v0v1` (from `v0` to `v1`) removes `v0`, the edge `v0v1`, the faces `fl`
/// (left of `v0v1`) and `fr` (right of it) and, in each of those triangles, the edge that
/// touched `v0` (`vl–v0`, `v0–vr`); every other edge of `v0` is moved to `v1`. `v1`
/// survives (OpenMesh, pmp, CGAL); its position is left unchanged for the caller to set.
///
/// ```text
///            vl                         vl
///          /  |  \                     / |
///         / fl|   \                   /  |
///  ... v0 ---h---> v1 ...   =>   ... v1  |   (v1 takes over the edges of v0)
///         \ fr|   /                   \  |
///          \  |  /                     \ |
///            vr                         vr
/// ```
///
/// Removed elements become tombstones that keep their handles and fields, and the
/// [`CollapseRecord`] (OpenMesh / Hoppe names: `v0v1, v1v0, v0, v1, vl, vr, fl, fr, p0, p1`)
/// remembers what the tombstones do not (the outgoing halfedges the collapse re-chose,
/// how many halfedges moved from `v0` to `v1`, the two positions): every link the collapse
/// rewrote named a removed halfedge, whose tombstone still has its `next` and `prev`, so
/// [`Mesh::vertex_split`] restores the same connectivity, orientation and handles, the
/// very `VertexId` of `v0` included. A hierarchy keeps only that compact part (88 bytes
/// per collapse, see `Step`). Splits undo collapses in reverse order (as a hierarchy
/// does): a record of [`Mesh::collapse`] is refused while a later public collapse still
/// waits for its split (splitting it first could strand the later record), and a record
/// names one collapse event only (once undone and collapsed again, the old record is
/// refused); see `collapse::waiting`.
///
/// **A split whose record does not fit the mesh is refused before anything changes**
/// ([`Error::SplitRefused`], saying why): a record of another mesh instance (a clone made
/// before the collapse shares its history and accepts it; records made on a clone after
/// cloning, or on an unrelated mesh, are refused), a record already split (or whose
/// collapse was undone and made again), a record split out of order, a record
/// whose removed elements were freed by [`Mesh::garbage_collection`], and a record whose
/// neighbourhood changed since the collapse (a later collapse or split nearby that was not
/// undone, [`Mesh::split_edge`], [`Mesh::add_triangle`]). The neighbourhood is compared
/// exactly where the record remembers it (every link, face and vertex halfedge the collapse
/// rewrote) and through a 64-bit fingerprint for the rest: the removed elements as the
/// collapse left them, the halfedges it moved from `v0` to `v1` with their links, and the
/// record's own handles.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CollapseVeto {
    /// The halfedge is removed (or not of this mesh).
    EdgeDeleted,
    /// One of its vertices is removed.
    VertexDeleted,
    /// Both outer edges of the left triangle are boundary edges.
    LeftTriangleOnBoundary,
    /// Both outer edges of the right triangle are boundary edges.
    RightTriangleOnBoundary,
    /// The opposite vertices `vl` and `vr` coincide (or both are missing).
    SameOppositeVertices,
    /// `v0` and `v1` have a common neighbour other than `vl` and `vr` (link condition).
    LinkCondition,
    /// `v0` and `v1` are both boundary vertices but the edge between them is interior.
    BoundaryVerticesInteriorEdge,
}

impl std::fmt::Display for CollapseVeto {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::EdgeDeleted => "the edge is removed",
            Self::VertexDeleted => "a vertex of the edge is removed",
            Self::LeftTriangleOnBoundary => {
                "both outer edges of the left triangle are on the boundary"
            }
            Self::RightTriangleOnBoundary => {
                "both outer edges of the right triangle are on the boundary"
            }
            Self::SameOppositeVertices => "the opposite vertices vl and vr coincide",
            Self::LinkCondition => {
                "the endpoints share a neighbour other than vl and vr (link condition)"
            }
            Self::BoundaryVerticesInteriorEdge => {
                "both endpoints are on the boundary but the edge is interior"
            }
        })
    }
}
/// # Collapse
impl Mesh {
    /// Whether collapsing `h` (`v0 → v1`) keeps the mesh a valid manifold triangle mesh,
    /// with OpenMesh's semantics (`TriConnectivity::is_collapse_ok`), check for check.
    /// Purely topological: geometric tests (normal flips, …) belong to the decimation.
    pub fn is_collapse_ok(&self, h: HalfedgeId) -> Result<(), CollapseVeto> {
        if !self.is_valid_halfedge(h) {
            return Err(CollapseVeto::EdgeDeleted);
        }
        let o = self.opposite(h);
        let v0 = self.to_vertex(o);
        let v1 = self.to_vertex(h);
        if !self.is_valid_vertex(v0) || !self.is_valid_vertex(v1) {
            return Err(CollapseVeto::VertexDeleted);
        }
        let mut vl = None;
        if !self.is_boundary_halfedge(h) {
            let h1 = self.next(h);
            let h2 = self.next(h1);
            vl = Some(self.to_vertex(h1));
            if self.is_boundary_halfedge(self.opposite(h1))
                && self.is_boundary_halfedge(self.opposite(h2))
            {
                return Err(CollapseVeto::LeftTriangleOnBoundary);
            }
        }
        let mut vr = None;
        if !self.is_boundary_halfedge(o) {
            let o1 = self.next(o);
            let o2 = self.next(o1);
            vr = Some(self.to_vertex(o1));
            if self.is_boundary_halfedge(self.opposite(o1))
                && self.is_boundary_halfedge(self.opposite(o2))
            {
                return Err(CollapseVeto::RightTriangleOnBoundary);
            }
        }
        if vl == vr {
            return Err(CollapseVeto::SameOppositeVertices);
        }
        if !self.link_condition(v0, v1, vl, vr) {
            return Err(CollapseVeto::LinkCondition);
        }
        if self.is_boundary_vertex(v0)
            && self.is_boundary_vertex(v1)
            && !self.is_boundary_halfedge(h)
            && !self.is_boundary_halfedge(o)
        {
            return Err(CollapseVeto::BoundaryVerticesInteriorEdge);
        }
        Ok(())
    }

    /// Collapses `h` (`v0 → v1`): `v0` is removed, `v1` survives at its position (set it
    /// afterwards: midpoint, QEM optimum, …). Refused with
    /// [`Error::CollapseRefused`] (nothing changed) when [`is_collapse_ok`](Self::is_collapse_ok)
    /// says no. Returns the record that [`vertex_split`](Self::vertex_split) inverts.
    pub fn collapse(&mut self, h: HalfedgeId) -> Result<CollapseRecord> {
        self.is_collapse_ok(h)
            .map_err(|reason| Error::CollapseRefused {
                halfedge: h,
                reason,
            })?;
        let (step, fingerprint) = self.collapse_step(h, None);
        let (instance, count) = (
            self.provenance.instance(),
            self.provenance.connectivity_count(),
        );
        // (Always a record: the collapse has just made every index it names.)
        let mut record = self
            .public_record(&step, fingerprint, (instance, count))
            .ok_or(Error::CollapseRefused {
                halfedge: h,
                reason: CollapseVeto::EdgeDeleted,
            })?;
        record.tracked = true;
        self.waiting.insert(
            step.v0,
            Waiting {
                instance,
                count,
                v1: step.v1,
            },
        );
        Ok(record)
    }

    /// [`collapse`](Self::collapse) for a hierarchy that does not trust its mesh: checked
    /// the same way, but not kept among the waiting public collapses (the hierarchy
    /// splits its own records in order).
    pub(crate) fn collapse_checked(&mut self, h: HalfedgeId) -> Result<(Step, u64)> {
        self.is_collapse_ok(h)
            .map_err(|reason| Error::CollapseRefused {
                halfedge: h,
                reason,
            })?;
        Ok(self.collapse_step(h, None))
    }

    /// True when `v0` and `v1` share no neighbour other than `vl` and `vr` (the link
    /// condition). `v1`'s ring is gathered once into a small stack array.
    fn link_condition(
        &self,
        v0: VertexId,
        v1: VertexId,
        vl: Option<VertexId>,
        vr: Option<VertexId>,
    ) -> bool {
        const RING: usize = 32;
        let mut ring = [VertexId::default(); RING];
        let mut n = 0;
        for u in self.adjacent_vertices(v1) {
            if n == RING {
                // A very high valence: compare ring against ring.
                return !self.adjacent_vertices(v0).any(|w| {
                    Some(w) != vl && Some(w) != vr && self.adjacent_vertices(v1).any(|u| u == w)
                });
            }
            ring[n] = u;
            n += 1;
        }
        let ring = &ring[..n];
        !self
            .adjacent_vertices(v0)
            .any(|w| Some(w) != vl && Some(w) != vr && ring.contains(&w))
    }

    /// [`collapse`](Self::collapse) without the [`is_collapse_ok`](Self::is_collapse_ok)
    /// test, for callers that have just made it (the hierarchy's legality layer): the
    /// compact record and its fingerprint.
    pub(crate) fn collapse_unchecked(&mut self, h: HalfedgeId) -> (Step, u64) {
        self.collapse_step(h, None)
    }

    /// [`collapse_unchecked`](Self::collapse_unchecked) of the edge of `old` again, for a
    /// hierarchy that knows the connectivity is exactly the one `old` was made in (its
    /// mesh kept its connectivity (its [`binding`](Self::binding)) since its own last step, and
    /// splits are exact inverses): the new record's fingerprint is `old`'s
    /// (`fingerprint`), so it is not computed again.
    pub(crate) fn recollapse_unchecked(&mut self, old: &Step, fingerprint: u64) -> Step {
        let h = self.hh(old.v0v1);
        let (step, _) = self.collapse_step(h, Some(fingerprint));
        debug_assert_eq!(self.split_fingerprint(&step), Some(fingerprint));
        step
    }

    /// The collapse; the fingerprint is `fingerprint` if known, else computed.
    fn collapse_step(&mut self, h: HalfedgeId, fingerprint: Option<u64>) -> (Step, u64) {
        debug_assert_eq!(self.is_collapse_ok(h), Ok(()));
        let o = self.opposite(h);
        let v0 = self.to_vertex(o);
        let v1 = self.to_vertex(h);
        let hi = Self::ix(h);
        let s = self.sides(hi);
        let opt = |i: u32| (i != NONE).then(|| self.hh(i));
        let (fl, fr) = (self.fh_opt(s.fl), self.fh_opt(s.fr));
        let (v1vl, vlv0, v0vr, vrv1) = (opt(s.v1vl), opt(s.vlv0), opt(s.v0vr), opt(s.vrv1));
        let vl = v1vl.map(|x| self.to_vertex(x));
        let vr = v0vr.map(|x| self.to_vertex(x));
        let v0vl = vlv0.map(|x| self.opposite(x));
        let vrv0 = v0vr.map(|x| self.opposite(x));
        let ix = Self::ix::<HalfedgeId>;
        let (links, n_links) = self.links_of(hi, &s).unwrap_or(([[NONE; 3]; 4], 0));
        // Faces beyond the removed edges whose halfedge is a removed one: it is re-chosen.
        let mut face_halfedges = [[NONE; 3]; 2];
        for (k, (y, r)) in [(v0vl, s.v1vl), (vrv0, s.vrv1)].into_iter().enumerate() {
            if let Some(y) = y {
                let g = self.he[slot(y)].face;
                if g != NONE && self.face_conn[g as usize] == ix(y) {
                    face_halfedges[k] = [g, ix(y), r];
                }
            }
        }

        // The halfedges that move from v0 to v1 (all outgoing but these).
        let removed_out = [Some(h), v0vl, v0vr];
        let record_vertices = [v1, vl.unwrap_or(v1), vr.unwrap_or(v1)];
        let before = record_vertices.map(|v| self.vertex_conn[slot(v)]);
        // Only a boundary vertex can need its outgoing halfedge re-chosen afterwards: a
        // collapse never puts an interior vertex on the boundary.
        let on_boundary =
            [v0, v1, vl.unwrap_or(v1), vr.unwrap_or(v1)].map(|v| self.is_boundary_vertex(v));
        #[cfg(debug_assertions)]
        let v0_out = self.vertex_conn[slot(v0)];

        // --- mutate ---
        self.touch_topology();
        // Rotating around v0 reads `prev` and `opposite` only, which this loop keeps.
        let mut moved = 0u32;
        let first = self.vertex_halfedge(v0).expect("v0 has edges");
        let mut k = first;
        loop {
            let next = self.ccw_rotated(k);
            if !removed_out.contains(&Some(k)) {
                let ko = self.opposite(k);
                self.set_to_vertex(ko, v1);
                moved += 1;
            }
            k = next;
            if k == first {
                break;
            }
        }
        for &[x, _, n] in &links[..n_links] {
            self.set_next_ix(x, n);
        }
        if let (Some(r), Some(y)) = (v1vl, v0vl) {
            self.rec_mut(r).face = self.rec(y).face;
        }
        if let (Some(r), Some(y)) = (vrv1, vrv0) {
            self.rec_mut(r).face = self.rec(y).face;
        }
        for &[g, _, r] in &face_halfedges {
            if g != NONE {
                self.face_conn[g as usize] = r;
            }
        }
        // Vertex halfedges: v1 and the opposite vertices may have pointed at removed halfedges.
        let v1_out = v1vl
            .or_else(|| self.next_outgoing_alive(v1, o))
            .expect("v1 keeps an edge");
        self.set_vertex_halfedge(v1, Some(v1_out));
        if on_boundary[0] || on_boundary[1] {
            self.adjust_outgoing_halfedge(v1);
        }
        if let (Some(vl), Some(r)) = (vl, v1vl) {
            if self.vertex_halfedge(vl) == vlv0 {
                self.set_vertex_halfedge(vl, Some(self.opposite(r)));
            }
            if on_boundary[2] {
                self.adjust_outgoing_halfedge(vl);
            }
        }
        if let (Some(vr), Some(r)) = (vr, vrv1) {
            if self.vertex_halfedge(vr) == vrv0 {
                self.set_vertex_halfedge(vr, Some(r));
            }
            if on_boundary[3] {
                self.adjust_outgoing_halfedge(vr);
            }
        }
        // Tombstones.
        self.vertex_slots_.bury(slot(v0));
        self.n_vertices -= 1;
        for x in [Some(h), Some(o), vlv0, v0vl, v0vr, vrv0]
            .into_iter()
            .flatten()
        {
            self.halfedge_slots_.bury(slot(x));
            self.n_halfedges -= 1;
        }
        for f in [fl, fr].into_iter().flatten() {
            self.face_slots_.bury(slot(f));
            self.n_faces -= 1;
        }
        let mut changed = 0u8;
        for (bit, [g, _, _]) in [FACE_LEFT, FACE_RIGHT].into_iter().zip(face_halfedges) {
            if g != NONE {
                changed |= bit;
            }
        }
        for (i, (&v, &old)) in record_vertices.iter().zip(&before).enumerate() {
            if self.vertex_conn[slot(v)] != old {
                changed |= 1 << i;
            }
        }
        let step = Step {
            p0: self.positions[self.vertex_index(v0)],
            p1: self.positions[self.vertex_index(v1)],
            v0v1: hi,
            v0: Self::ix(v0),
            v1: Self::ix(v1),
            vl: Self::ix_opt(vl),
            vr: Self::ix_opt(vr),
            before,
            moved,
            changed,
        };
        // What the split derives from the tombstones is what the collapse just used.
        #[cfg(debug_assertions)]
        {
            debug_assert_eq!(self.vertex_conn[slot(v0)], v0_out);
            debug_assert_eq!(self.sides(hi), s);
            debug_assert_eq!(self.links_of(hi, &s), Some((links, n_links)));
        }
        // (Never `None` on the mesh the collapse has just left; 0 would only make the
        // split refuse.)
        let fingerprint =
            fingerprint.unwrap_or_else(|| self.split_fingerprint(&step).unwrap_or_default());
        (step, fingerprint)
    }
}
