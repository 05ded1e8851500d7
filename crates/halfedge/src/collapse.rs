//! Halfedge collapse and its exact inverse, the vertex split.
//!
//! Collapsing `h = v0v1` (from `v0` to `v1`) removes `v0`, the edge `v0v1`, the faces `fl`
//! (left of `v0v1`) and `fr` (right of it) and, in each of those triangles, the edge that
//! touched `v0` (`vl–v0`, `v0–vr`); every other edge of `v0` is moved to `v1`. `v1`
//! survives (OpenMesh, pmp, CGAL); its position is left unchanged for the caller to set.
//!
//! ```text
//!            vl                         vl
//!          /  |  \                     / |
//!         / fl|   \                   /  |
//!  ... v0 ---h---> v1 ...   =>   ... v1  |   (v1 takes over the edges of v0)
//!         \ fr|   /                   \  |
//!          \  |  /                     \ |
//!            vr                         vr
//! ```
//!
//! Removed elements become tombstones that keep their handles and fields, and the
//! [`CollapseRecord`] (OpenMesh / Hoppe names: `v0v1, v1v0, v0, v1, vl, vr, fl, fr, p0, p1`)
//! remembers every link the collapse rewrote, so [`Mesh::vertex_split`] restores the same
//! connectivity, orientation and handles, the very `VertexId` of `v0` included. Splits
//! undo collapses in reverse order (as a hierarchy does), or out of order where the
//! collapses in between did not touch the record's neighbourhood.
//!
//! **A split whose record does not fit the mesh is refused before anything changes**
//! ([`Error::SplitRefused`], saying why): a record of another mesh instance (a clone made
//! before the collapse shares its history and accepts it; records made on a clone after
//! cloning, or on an unrelated mesh, are refused), a record already split, a record
//! whose removed elements were freed by [`Mesh::garbage_collection`], and a record whose
//! neighbourhood changed since the collapse (a later collapse or split nearby that was not
//! undone, [`Mesh::split_edge`], [`Mesh::add_triangle`]). The neighbourhood is compared
//! exactly where the record remembers it (every link, face and vertex halfedge the collapse
//! rewrote) and through a 64-bit fingerprint for the rest: the removed elements as the
//! collapse left them, the halfedges it moved from `v0` to `v1` with their links, and the
//! record's own handles.

use glam::DVec3;

use crate::handle::{slot, NONE};
use crate::{Error, FaceId, HalfedgeId, Mesh, Result, VertexId};

/// Why [`Mesh::is_collapse_ok`] refuses a collapse (OpenMesh's
/// `TriConnectivity::is_collapse_ok`, check for check, in this order).
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

/// One rewritten `next` link, as slot indices: `[halfedge, next before, next after]`.
type Link = [u32; 3];

/// A multilinear hash of a fixed sequence of words: `Σ word_i · K_i` with distinct odd
/// constants, so that any change of a single word changes the sum, and the words are
/// independent of each other (no dependency chain).
#[derive(Default)]
struct Multilinear {
    sum: u64,
    i: u64,
}

impl Multilinear {
    #[inline]
    fn add(&mut self, word: u64) {
        self.i += 1;
        let k = self.i.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
        self.sum = self.sum.wrapping_add(word.wrapping_mul(k));
    }
}

/// A handle as a word of the fingerprint (0 for none).
#[inline]
fn word<K: slotmap::Key>(k: Option<K>) -> u64 {
    k.map_or(0, |k| k.data().as_ffi())
}

/// Everything [`Mesh::vertex_split`] needs to undo a [`Mesh::collapse`], with OpenMesh's
/// names for the parts of the collapse.
#[derive(Clone, Debug)]
pub struct CollapseRecord {
    /// The collapsed halfedge, `v0 → v1`.
    pub v0v1: HalfedgeId,
    /// Its opposite, `v1 → v0`.
    pub v1v0: HalfedgeId,
    /// The removed vertex.
    pub v0: VertexId,
    /// The surviving vertex.
    pub v1: VertexId,
    /// The third vertex of the left face (`None` when `v0v1` is a boundary halfedge).
    pub vl: Option<VertexId>,
    /// The third vertex of the right face (`None` when `v1v0` is a boundary halfedge).
    pub vr: Option<VertexId>,
    /// The face left of `v0v1`.
    pub fl: Option<FaceId>,
    /// The face right of `v0v1` (left of `v1v0`).
    pub fr: Option<FaceId>,
    /// Position of `v0` when it was collapsed.
    pub p0: DVec3,
    /// Position of `v1` when the edge was collapsed (before the caller moved it).
    pub p1: DVec3,
    /// `v1 → vl`, kept: it takes the place of the removed `v0 → vl`.
    pub v1vl: Option<HalfedgeId>,
    /// `vl → v0`, removed with its opposite.
    pub vlv0: Option<HalfedgeId>,
    /// `v0 → vr`, removed with its opposite.
    pub v0vr: Option<HalfedgeId>,
    /// `vr → v1`, kept: it takes the place of the removed `vr → v0`.
    pub vrv1: Option<HalfedgeId>,
    // The links the collapse rewrote, as slot indices (`NONE`: no element), kept compact
    // since a hierarchy stores one record per vertex.
    links: [Link; 4],
    n_links: u8,
    /// `[face, halfedge before, halfedge after]` for faces whose halfedge was re-chosen.
    face_halfedges: [[u32; 3]; 2],
    /// `[before, after]` outgoing halfedge of `v0`, `v1`, `vl` (or `v1`), `vr` (or `v1`).
    vertex_halfedges: [[u32; 2]; 4],
    /// Outgoing halfedge of `v1` after which the moved halfedges start (counter-clockwise).
    start: u32,
    /// Number of halfedges moved from `v0` to `v1`.
    moved: u32,
    /// The mesh instance the collapse was made on ([`Mesh::topology_stamp`]'s id) and its
    /// change count right after the collapse: see `Mesh::is_own_history`.
    mesh: u64,
    count: u64,
    /// Fingerprint of what the split relies on beyond the fields above (see
    /// [`Mesh::split_fingerprint`]), as the collapse left it.
    fingerprint: u64,
}

impl CollapseRecord {
    /// The vertices that were neighbours of `v0` or `v1` when the edge collapsed,
    /// `v0` and `v1` excluded, are what the centroid detail coefficients need; this gives
    /// the two opposite vertices that are always among them.
    pub fn opposite_vertices(&self) -> impl Iterator<Item = VertexId> {
        self.vl.into_iter().chain(self.vr)
    }

    /// `v0`, `v1`, `vl` (or `v1`), `vr` (or `v1`): the vertices whose outgoing halfedge
    /// the record remembers, in the order of `vertex_halfedges`.
    fn record_vertices(&self) -> [VertexId; 4] {
        [
            self.v0,
            self.v1,
            self.vl.unwrap_or(self.v1),
            self.vr.unwrap_or(self.v1),
        ]
    }
}

/// # Collapse and vertex split
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
        Ok(self.collapse_unchecked(h))
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
    /// test, for callers that have just made it (the hierarchy's legality layer).
    pub(crate) fn collapse_unchecked(&mut self, h: HalfedgeId) -> CollapseRecord {
        self.collapse_with(h, None)
    }

    /// [`collapse_unchecked`](Self::collapse_unchecked) of the edge of `old` again, for a
    /// hierarchy that knows the connectivity is exactly the one `old` was made in (its
    /// mesh kept its [`topology_stamp`](Self::topology_stamp) since its own last step, and
    /// splits are exact inverses): the new record's fingerprint is `old`'s, so it is not
    /// computed again.
    pub(crate) fn recollapse_unchecked(&mut self, old: &CollapseRecord) -> CollapseRecord {
        let record = self.collapse_with(old.v0v1, Some(old.fingerprint));
        debug_assert_eq!(self.split_fingerprint(&record), Some(old.fingerprint));
        record
    }

    /// The collapse; the record's fingerprint is `fingerprint` if known, else computed.
    fn collapse_with(&mut self, h: HalfedgeId, fingerprint: Option<u64>) -> CollapseRecord {
        debug_assert_eq!(self.is_collapse_ok(h), Ok(()));
        let o = self.opposite(h);
        let v0 = self.to_vertex(o);
        let v1 = self.to_vertex(h);
        let fl = self.face(h);
        let fr = self.face(o);
        let (mut v1vl, mut vlv0, mut v0vr, mut vrv1) = (None, None, None, None);
        if fl.is_some() {
            v1vl = Some(self.next(h));
            vlv0 = Some(self.next(self.next(h)));
        }
        if fr.is_some() {
            v0vr = Some(self.next(o));
            vrv1 = Some(self.next(self.next(o)));
        }
        let vl = v1vl.map(|x| self.to_vertex(x));
        let vr = v0vr.map(|x| self.to_vertex(x));
        // Halfedges leaving the cycles they are in, with their replacements (None: skipped).
        let v0vl = vlv0.map(|x| self.opposite(x));
        let vrv0 = v0vr.map(|x| self.opposite(x));
        let replacement = |y: HalfedgeId| -> Option<Option<HalfedgeId>> {
            if Some(y) == v0vl {
                Some(v1vl)
            } else if Some(y) == vrv0 {
                Some(vrv1)
            } else if (fl.is_none() && y == h) || (fr.is_none() && y == o) {
                Some(None)
            } else {
                None
            }
        };
        let resolve = |mut y: HalfedgeId| -> HalfedgeId {
            loop {
                match replacement(y) {
                    Some(Some(r)) => return r,
                    Some(None) => y = self.next(y),
                    None => return y,
                }
            }
        };
        let leaving: [Option<HalfedgeId>; 4] = [
            v0vl,
            vrv0,
            fl.is_none().then_some(h),
            fr.is_none().then_some(o),
        ];
        let ix = Self::ix::<HalfedgeId>;
        let mut links: [Link; 4] = [[NONE; 3]; 4];
        let mut n_links = 0;
        let mut face_halfedges = [[NONE; 3]; 2];
        for y in leaving.into_iter().flatten() {
            let x = self.prev(y);
            if replacement(x).is_none() {
                links[n_links] = [ix(x), ix(self.next(x)), ix(resolve(y))];
                n_links += 1;
            }
            if let Some(Some(r)) = replacement(y) {
                links[n_links] = [ix(r), ix(self.next(r)), ix(resolve(self.next(y)))];
                n_links += 1;
                if let Some(g) = self.face(y) {
                    if self.face_halfedge(g) == y {
                        face_halfedges[usize::from(Some(y) == vrv0)] = [Self::ix(g), ix(y), ix(r)];
                    }
                }
            }
        }

        // The halfedges that move from v0 to v1 (all outgoing but these), and where they
        // start around v1.
        let removed_out = [Some(h), v0vl, v0vr];
        let start = match v1vl {
            Some(x) => x,
            None => self.next(h),
        };

        let record_vertices = [v0, v1, vl.unwrap_or(v1), vr.unwrap_or(v1)];
        let old_vertex_halfedges = record_vertices.map(|v| self.vertex_conn[slot(v)]);
        // Only a boundary vertex can need its outgoing halfedge re-chosen afterwards: a
        // collapse never puts an interior vertex on the boundary.
        let on_boundary = record_vertices.map(|v| self.is_boundary_vertex(v));

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
        let mut vertex_halfedges = [[NONE; 2]; 4];
        for i in 0..4 {
            vertex_halfedges[i] = [
                old_vertex_halfedges[i],
                self.vertex_conn[slot(record_vertices[i])],
            ];
        }
        let mut record = CollapseRecord {
            v0v1: h,
            v1v0: o,
            v0,
            v1,
            vl,
            vr,
            fl,
            fr,
            p0: self.positions[self.vertex_index(v0)],
            p1: self.positions[self.vertex_index(v1)],
            v1vl,
            vlv0,
            v0vr,
            vrv1,
            links,
            n_links: n_links as u8,
            face_halfedges,
            vertex_halfedges,
            start: ix(start),
            moved,
            mesh: self.stamp_id,
            count: self.stamp_count,
            fingerprint: 0,
        };
        // (Never `None` on the mesh the collapse has just left; 0 would only make the
        // split refuse.)
        record.fingerprint =
            fingerprint.unwrap_or_else(|| self.split_fingerprint(&record).unwrap_or_default());
        record
    }

    /// The fingerprint of everything a split of `r` reads or restores beyond what the
    /// record compares exactly: the record's public handles (so that a record whose fields
    /// were changed does not fit), and, as they are in the mesh now, both halfedges of
    /// every edge the split relinks, revives or walks over (the removed edges, the kept
    /// edges `v1vl`, `vrv1`, the rewritten links, the vertex halfedges before and after,
    /// the halfedges moved from `v0` to `v1`), the halfedges of the removed faces and of
    /// the faces beside the removed edges, and the outgoing halfedges of the record's
    /// vertices. The collapse stores it; the split recomputes it and compares. `None` when the walk around `v1` leaves the mesh (only
    /// possible on a mesh the record does not fit); otherwise the record's slots must
    /// exist.
    fn split_fingerprint(&self, r: &CollapseRecord) -> Option<u64> {
        let mut m = Multilinear::default();
        for w in [
            word(Some(r.v0v1)),
            word(Some(r.v1v0)),
            word(Some(r.v0)),
            word(Some(r.v1)),
            word(r.vl),
            word(r.vr),
            word(r.fl),
            word(r.fr),
            word(r.v1vl),
            word(r.vlv0),
            word(r.v0vr),
            word(r.vrv1),
        ] {
            m.add(w);
        }
        let edge = |m: &mut Multilinear, i: u32| -> Option<()> {
            let i = (i & !1) as usize;
            for rec in self.he.get(i..i + 2)? {
                m.add(u64::from(rec.to) << 32 | u64::from(rec.next));
                m.add(u64::from(rec.prev) << 32 | u64::from(rec.face));
            }
            Some(())
        };
        for x in [Some(r.v0v1), r.vlv0, r.v0vr, r.v1vl, r.vrv1]
            .into_iter()
            .flatten()
        {
            edge(&mut m, Self::ix(x))?;
        }
        for &[x, old, new] in &r.links[..usize::from(r.n_links)] {
            for i in [x, old, new] {
                edge(&mut m, i)?;
            }
        }
        for &[g, _, _] in &r.face_halfedges {
            if g != NONE {
                m.add(u64::from(*self.face_conn.get(g as usize)?));
            }
        }
        for f in [r.fl, r.fr].into_iter().flatten() {
            m.add(u64::from(self.face_conn[slot(f)]));
        }
        // The faces beside the removed edges, whose loops the split gives back their
        // removed halfedge: the faces of `v1vl` and `vrv1` now.
        for x in [r.v1vl, r.vrv1].into_iter().flatten() {
            let g = self.he[slot(x)].face;
            if g != NONE {
                m.add(u64::from(*self.face_conn.get(g as usize)?));
            }
        }
        for (v, &[old, new]) in r.record_vertices().into_iter().zip(&r.vertex_halfedges) {
            m.add(u64::from(self.vertex_conn[slot(v)]));
            for i in [old, new] {
                if i != NONE {
                    edge(&mut m, i)?;
                }
            }
        }
        // The walk the split makes around v1.
        let mut k = r.start;
        edge(&mut m, k)?;
        for _ in 0..r.moved {
            k = self.he.get(k as usize)?.prev ^ 1;
            edge(&mut m, k)?;
        }
        Some(m.sum)
    }

    /// The first outgoing halfedge of `v` counter-clockwise after `h` that is not `h`.
    fn next_outgoing_alive(&self, v: VertexId, h: HalfedgeId) -> Option<HalfedgeId> {
        self.outgoing_halfedges(v)
            .find(|&k| k != h && self.halfedge_slots_.is_live(k))
    }

    /// Undoes [`collapse`](Self::collapse): revives `v0` (same handle), its edges and the
    /// faces `fl`, `fr`, restores every link, and puts `v0` at `p0` and `v1` at `p1`.
    ///
    /// # Errors
    /// [`Error::SplitRefused`], saying why, when the record does not fit the mesh (see
    /// the [module docs](self)): made on another mesh, already split, freed by garbage
    /// collection, or its neighbourhood changed since the collapse. Nothing is changed
    /// then.
    pub fn vertex_split(&mut self, r: &CollapseRecord) -> Result<()> {
        if let Err(why) = self.split_fits(r) {
            return Err(Error::SplitRefused(format!(
                "{why} (record of {} → {})",
                r.v0, r.v1
            )));
        }
        self.vertex_split_unchecked(r);
        Ok(())
    }

    /// Whether [`vertex_split_unchecked`](Self::vertex_split_unchecked) of `r` gives back
    /// exactly the neighbourhood the collapse of `r` removed, and so a valid mesh: every
    /// element the split reads or restores is as the collapse left it. Reads only
    /// (bounds-checked where the mesh might not be the record's).
    fn split_fits(&self, r: &CollapseRecord) -> std::result::Result<(), &'static str> {
        if !self.is_own_history(r.mesh, r.count) {
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
        for x in [Some(r.v0v1), Some(r.v1v0), r.vlv0, r.v0vr]
            .into_iter()
            .flatten()
        {
            if !hs.is_tombstone(x) || !hs.is_tombstone(self.hh(Self::ix(x) ^ 1)) {
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
        for &[x, _, new] in &r.links[..usize::from(r.n_links)] {
            if !live(x) || self.he[x as usize].next != new {
                return Err(
                    "a link the collapse wrote has changed (a later collapse, split \
                            or edit nearby was not undone)",
                );
            }
        }
        for &[g, _, new] in &r.face_halfedges {
            if g != NONE
                && (!self.face_slots_.is_live_index(g as usize)
                    || self.face_conn[g as usize] != new)
            {
                return Err("a face beside the collapsed edge has changed");
            }
        }
        let revived = |i: u32| {
            [Some(r.v0v1), r.vlv0, r.v0vr]
                .into_iter()
                .flatten()
                .any(|x| Self::ix(x) & !1 == i & !1)
        };
        for (v, &[old, new]) in r.record_vertices().into_iter().zip(&r.vertex_halfedges) {
            if v != r.v0 && !self.is_valid_vertex(v) {
                return Err("a neighbour vertex was removed");
            }
            if self.vertex_conn[slot(v)] != new {
                return Err("a vertex halfedge the collapse set has changed");
            }
            if old != NONE && !live(old) && !revived(old) {
                return Err("a halfedge the split would give back to a vertex was removed");
            }
        }
        let start = r.start as usize;
        if !live(r.start) || self.he[start ^ 1].to != Self::ix(r.v1) {
            return Err("the anchor halfedge around v1 has changed");
        }
        let mut k = start;
        for _ in 0..r.moved {
            match self.he.get(k) {
                Some(rec) if live(rec.prev) => k = (rec.prev ^ 1) as usize,
                _ => return Err("the ring of v1 is broken"),
            }
            if k == start || self.he[k ^ 1].to != Self::ix(r.v1) {
                return Err("v1 has fewer edges than the collapse moved to it");
            }
        }
        if self.split_fingerprint(r) != Some(r.fingerprint) {
            return Err(
                "the neighbourhood of the collapsed edge has changed since the \
                        collapse (the ring of v1, the edges beside the removed ones, or the \
                        removed elements)",
            );
        }
        Ok(())
    }

    /// Prefetches what [`vertex_split_unchecked`](Self::vertex_split_unchecked) of `r`
    /// will touch first: the halfedges it revives and relinks, the slot states it flips,
    /// the face and vertex halfedges it restores and the two positions it writes. A
    /// hierarchy calls this a few splits ahead (see [`crate::prefetch`]).
    #[inline]
    pub(crate) fn prefetch_split(&self, r: &CollapseRecord) {
        self.prefetch_record(r);
        for (v, &[old, new]) in r.record_vertices().into_iter().zip(&r.vertex_halfedges) {
            if old != new {
                crate::prefetch::prefetch(&self.vertex_conn, slot(v));
            }
        }
    }

    /// Prefetches what collapsing the edge of `r` again will touch first (as
    /// [`prefetch_split`](Self::prefetch_split), and the outgoing halfedges of all four
    /// record vertices, which the collapse reads).
    #[inline]
    pub(crate) fn prefetch_collapse(&self, r: &CollapseRecord) {
        self.prefetch_record(r);
        for v in r.record_vertices() {
            crate::prefetch::prefetch(&self.vertex_conn, slot(v));
        }
    }

    /// The elements both a collapse and a split of `r` touch.
    #[inline]
    fn prefetch_record(&self, r: &CollapseRecord) {
        use crate::prefetch::prefetch;
        let he = &self.he;
        prefetch(he, r.start as usize);
        for x in [Some(r.v0v1), r.vlv0, r.v0vr].into_iter().flatten() {
            // Both halfedges of the edge: a pair may straddle two cache lines.
            prefetch(he, slot(x));
            prefetch(he, slot(x) ^ 1);
            self.halfedge_slots_.prefetch_state(slot(x));
        }
        for x in [r.v1vl, r.vrv1].into_iter().flatten() {
            prefetch(he, slot(x));
        }
        for &[x, _, new] in &r.links[..usize::from(r.n_links)] {
            prefetch(he, x as usize);
            prefetch(he, new as usize);
        }
        self.vertex_slots_.prefetch_state(slot(r.v0));
        for f in [r.fl, r.fr].into_iter().flatten() {
            self.face_slots_.prefetch_state(slot(f));
        }
        for &[g, _, _] in &r.face_halfedges {
            prefetch(&self.face_conn, g as usize);
        }
        prefetch(&self.positions, slot(r.v0));
        prefetch(&self.positions, slot(r.v1));
    }

    /// Prefetches the `step`-th halfedge the split of `r` moves back to `v0` (the walk
    /// around `v1` from `r.start`), reading the earlier ones of the walk, which an earlier
    /// call should have brought into cache: the walk is a chain of dependent loads, so a
    /// hierarchy pipelines it over several splits ahead. The mesh may not yet be as the
    /// split will find it (the splits in between have not run), so the walk may go astray;
    /// that only costs a useless prefetch.
    #[inline]
    pub(crate) fn prefetch_moved(&self, r: &CollapseRecord, step: u32) {
        if step < r.moved {
            self.prefetch_ring(r.start as usize, step);
        }
    }

    /// Prefetches, for collapsing `r` again, the `step`-th outgoing halfedge after the
    /// one `v0` had when `r` was collapsed (the collapse walks `v0`'s whole ring, a chain
    /// of dependent loads like the split's walk: see
    /// [`prefetch_moved`](Self::prefetch_moved)). Step 0 also brings in the line that
    /// tells whether each record vertex is on the boundary.
    #[inline]
    pub(crate) fn prefetch_collapse_ring(&self, r: &CollapseRecord, step: u32) {
        if step == 0 {
            for v in r.record_vertices() {
                if let Some(&h) = self.vertex_conn.get(slot(v)) {
                    crate::prefetch::prefetch(&self.he, h as usize);
                }
            }
            // The faces beyond the two removed edges, whose halfedge may be re-chosen.
            for x in [r.vlv0, r.v0vr].into_iter().flatten() {
                if let Some(rec) = self.he.get(slot(x) ^ 1) {
                    crate::prefetch::prefetch(&self.face_conn, rec.face as usize);
                }
            }
        }
        if step <= r.moved + 1 {
            self.prefetch_ring(r.vertex_halfedges[0][0] as usize, step);
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

    /// [`vertex_split`](Self::vertex_split) without its checks, for a caller that knows
    /// the connectivity is what the collapse left (a hierarchy whose mesh kept its
    /// [`topology_stamp`](Self::topology_stamp) since its own last step).
    pub(crate) fn vertex_split_unchecked(&mut self, r: &CollapseRecord) {
        self.touch_topology();
        let start = r.start as usize;
        self.vertex_slots_.revive(slot(r.v0));
        self.n_vertices += 1;
        for x in [Some(r.v0v1), r.vlv0, r.v0vr].into_iter().flatten() {
            self.halfedge_slots_.revive(slot(x));
            self.halfedge_slots_.revive(slot(x) ^ 1);
            self.n_halfedges += 2;
        }
        for f in [r.fl, r.fr].into_iter().flatten() {
            self.face_slots_.revive(slot(f));
            self.n_faces += 1;
        }
        // The same walk as the check above: reviving changed no `prev` or `opposite`.
        let v0 = Self::ix(r.v0);
        let mut k = start;
        for _ in 0..r.moved {
            k = (self.he[k].prev ^ 1) as usize;
            self.he[k ^ 1].to = v0;
        }
        for &[x, old, _] in &r.links[..usize::from(r.n_links)] {
            self.set_next_ix(x, old);
        }
        // The kept halfedges return to their faces; the removed cycles are intact tombstones.
        if let (Some(x), Some(next)) = (r.v1vl, r.vlv0) {
            self.set_face(x, r.fl);
            self.set_next(r.v0v1, x);
            self.set_next(x, next);
            self.set_next(next, r.v0v1);
        }
        if let (Some(x), Some(prev)) = (r.vrv1, r.v0vr) {
            self.set_face(x, r.fr);
            self.set_next(r.v1v0, prev);
            self.set_next(prev, x);
            self.set_next(x, r.v1v0);
        }
        // Tombstones kept their `next`, but the collapse re-pointed the `prev` of their
        // successors: make `prev` agree with `next` again around every revived halfedge.
        for x in [Some(r.v0v1), r.vlv0, r.v0vr].into_iter().flatten() {
            for k in [x, self.opposite(x)] {
                let n = self.next(k);
                self.rec_mut(n).prev = Self::ix(k);
            }
        }
        for &[g, old, _] in &r.face_halfedges {
            if g != NONE {
                self.face_conn[g as usize] = old;
            }
        }
        for (v, &[old, new]) in r.record_vertices().into_iter().zip(&r.vertex_halfedges) {
            // Most of these did not change; not writing them saves fetching their lines.
            if old != new {
                self.vertex_conn[slot(v)] = old;
            }
        }
        let (i0, i1) = (self.vertex_index(r.v0), self.vertex_index(r.v1));
        self.positions[i0] = r.p0;
        self.positions[i1] = r.p1;
    }
}
