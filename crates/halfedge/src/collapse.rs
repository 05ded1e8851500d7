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
//! remembers what the tombstones do not (the outgoing halfedges the collapse re-chose,
//! how many halfedges moved from `v0` to `v1`, the two positions): every link the collapse
//! rewrote named a removed halfedge, whose tombstone still has its `next` and `prev`, so
//! [`Mesh::vertex_split`] restores the same connectivity, orientation and handles, the
//! very `VertexId` of `v0` included. A hierarchy keeps only that compact part (88 bytes
//! per collapse, see `Step`). Splits
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
use crate::mesh::HalfedgeRec;
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
///
/// The links the collapse rewrote are not stored: the removed halfedges keep their
/// fields as tombstones, and the split reads them back from there (see
/// [`Mesh::vertex_split`]).
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
    /// The compact form the split works from.
    step: Step,
    /// The mesh instance the collapse was made on ([`Provenance`](crate::binding::Provenance)'s instance) and its
    /// change count right after the collapse: see `Provenance::is_own_history`.
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

    /// The compact form of the record (what a hierarchy keeps).
    pub(crate) fn step(&self) -> &Step {
        &self.step
    }

    /// The fingerprint the split compares.
    pub(crate) fn fingerprint(&self) -> u64 {
        self.fingerprint
    }
}

/// The compact record of a collapse that a [`crate::Hierarchy`] keeps (88 bytes): slot
/// indices instead of handles, the two positions, and only what the removed halfedges'
/// tombstones do not keep. The two triangles' halfedges and faces are read from the
/// tombstones of `v0v1` and `v1v0` ([`Mesh::sides`]), the rewritten links from those of
/// the removed edges ([`Mesh::links_of`]). The mesh instance and the fingerprint that a
/// checked split compares are kept apart by the hierarchy (once per hierarchy, and in a
/// cold array).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Step {
    /// Position of `v0` when it was collapsed.
    pub(crate) p0: DVec3,
    /// Position of `v1` when the edge was collapsed.
    pub(crate) p1: DVec3,
    /// The collapsed halfedge `v0 → v1` (its opposite is `v0v1 ^ 1`).
    pub(crate) v0v1: u32,
    /// The removed vertex.
    pub(crate) v0: u32,
    /// The surviving vertex.
    pub(crate) v1: u32,
    /// The opposite vertices (`NONE` on a boundary side).
    pub(crate) vl: u32,
    pub(crate) vr: u32,
    /// The outgoing halfedges of `v1`, `vl`, `vr` before the collapse (`v0`'s is kept).
    before: [u32; 3],
    /// Number of halfedges moved from `v0` to `v1`.
    moved: u32,
    /// Bit `i`: the collapse changed the outgoing halfedge of vertex `i` of
    /// `[v1, vl, vr]` (the split writes back only those). Bits [`FACE_LEFT`] and
    /// [`FACE_RIGHT`]: the collapse re-chose the halfedge of the face beyond the removed
    /// edge `vl–v0`, `v0–vr`.
    changed: u8,
}

/// [`Step::changed`]: the face beyond `vl–v0` had `v0 → vl` as its halfedge.
const FACE_LEFT: u8 = 1 << 3;
/// [`Step::changed`]: the face beyond `v0–vr` had `vr → v0` as its halfedge.
const FACE_RIGHT: u8 = 1 << 4;

impl Step {
    /// `v1`, `vl`, `vr`, as far as they exist, with their outgoing halfedges before the
    /// collapse and whether the collapse changed them.
    #[inline]
    fn restored_vertices(&self) -> impl Iterator<Item = (u32, u32, bool)> + '_ {
        [self.v1, self.vl, self.vr]
            .into_iter()
            .zip(self.before)
            .enumerate()
            .filter(|&(_, (v, _))| v != NONE)
            .map(|(i, (v, before))| (v, before, self.changed & (1 << i) != 0))
    }
}

/// The halfedges and faces of a collapse's two triangles (slot indices, `NONE` where a
/// side is on the boundary), as the tombstones of `v0v1` and `v1v0` keep them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Sides {
    pub(crate) fl: u32,
    pub(crate) fr: u32,
    pub(crate) v1vl: u32,
    pub(crate) vlv0: u32,
    pub(crate) v0vr: u32,
    pub(crate) vrv1: u32,
}

impl Sides {
    /// The removed halfedges beside the collapsed edge, `vl → v0` and `v0 → vr`, and the
    /// collapsed halfedge itself.
    #[inline]
    pub(crate) fn removed(&self, v0v1: u32) -> impl Iterator<Item = u32> {
        [v0v1, self.vlv0, self.v0vr]
            .into_iter()
            .filter(|&x| x != NONE)
    }
}

/// What a checked split compares beyond the record's own fields, derived from the record
/// and the tombstones of the removed halfedges (so the same at the collapse and at the
/// split when nothing changed in between).
struct Derived {
    sides: Sides,
    /// The rewritten links, in the collapse's order.
    links: [Link; 4],
    n_links: usize,
    /// `[face, halfedge before, halfedge after]` for faces whose halfedge was re-chosen.
    face_halfedges: [[u32; 3]; 2],
    /// `[before, after]` outgoing halfedge of `v0`, `v1`, `vl` (or `v1`), `vr` (or `v1`).
    vertex_halfedges: [[u32; 2]; 4],
    /// Outgoing halfedge of `v1` after which the moved halfedges start (counter-clockwise).
    start: u32,
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
        let (step, fingerprint) = self.collapse_step(h, None);
        // (Always a record: the collapse has just made every index it names.)
        self.public_record(
            &step,
            fingerprint,
            (
                self.provenance.instance(),
                self.provenance.connectivity_count(),
            ),
        )
        .ok_or(Error::CollapseRefused {
            halfedge: h,
            reason: CollapseVeto::EdgeDeleted,
        })
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

    /// The public record of `step` (made on mesh instance `mesh` at change count
    /// `count`), with its handles; `None` when an index of the step is out of range.
    pub(crate) fn public_record(
        &self,
        step: &Step,
        fingerprint: u64,
        (mesh, count): (u64, u64),
    ) -> Option<CollapseRecord> {
        let s = self.sides_checked(step.v0v1)?;
        let (nv, nh, nf) = (self.vertex_conn.len(), self.he.len(), self.face_conn.len());
        let v_ok = |i: u32| i == NONE || (i as usize) < nv;
        let h_ok = |i: u32| i == NONE || (i as usize) < nh;
        let f_ok = |i: u32| i == NONE || (i as usize) < nf;
        if !([step.v0, step.v1].iter().all(|&i| (i as usize) < nv)
            && [step.vl, step.vr].into_iter().all(v_ok)
            && [s.v1vl, s.vlv0, s.v0vr, s.vrv1].into_iter().all(h_ok)
            && [s.fl, s.fr].into_iter().all(f_ok))
        {
            return None;
        }
        let vh = |i: u32| (i != NONE).then(|| self.vh(i));
        let hh = |i: u32| (i != NONE).then(|| self.hh(i));
        Some(CollapseRecord {
            v0v1: self.hh(step.v0v1),
            v1v0: self.hh(step.v0v1 ^ 1),
            v0: self.vh(step.v0),
            v1: self.vh(step.v1),
            vl: vh(step.vl),
            vr: vh(step.vr),
            fl: self.fh_opt(s.fl),
            fr: self.fh_opt(s.fr),
            p0: step.p0,
            p1: step.p1,
            v1vl: hh(s.v1vl),
            vlv0: hh(s.vlv0),
            v0vr: hh(s.v0vr),
            vrv1: hh(s.vrv1),
            step: *step,
            mesh,
            count,
            fingerprint,
        })
    }

    /// The two triangles of the collapse of halfedge `h` (slot index), read from `h` and
    /// its opposite: before the collapse from the live halfedges, after it from their
    /// tombstones (which keep their fields), the same either way.
    #[inline]
    pub(crate) fn sides(&self, h: u32) -> Sides {
        let (a, b) = (&self.he[h as usize], &self.he[(h ^ 1) as usize]);
        let (l, r) = (a.face != NONE, b.face != NONE);
        Sides {
            fl: a.face,
            fr: b.face,
            v1vl: if l { a.next } else { NONE },
            vlv0: if l { a.prev } else { NONE },
            v0vr: if r { b.next } else { NONE },
            vrv1: if r { b.prev } else { NONE },
        }
    }

    /// [`sides`](Self::sides), bounds-checked.
    fn sides_checked(&self, h: u32) -> Option<Sides> {
        self.he.get((h | 1) as usize)?;
        Some(self.sides(h))
    }

    /// The `next` links the collapse of halfedge `h` rewrites, `[halfedge, next before,
    /// next after]`, in the collapse's order. Reads only the `next` and `prev` of the
    /// removed halfedges, which their tombstones keep: so it gives the same before the
    /// collapse (which writes them) and after it (the split, which restores them).
    /// `None` when an index is out of range.
    #[inline]
    fn links_of(&self, h: u32, s: &Sides) -> Option<([Link; 4], usize)> {
        let o = h ^ 1;
        let flip = |x: u32| if x == NONE { NONE } else { x ^ 1 };
        let (v0vl, vrv0) = (flip(s.vlv0), flip(s.v0vr));
        // The halfedge that takes the place of `y` in its cycle: `Some(NONE)` when `y` is
        // skipped, `None` when `y` stays.
        let replacement = |y: u32| -> Option<u32> {
            if y == NONE {
                None
            } else if y == v0vl {
                Some(s.v1vl)
            } else if y == vrv0 {
                Some(s.vrv1)
            } else if (s.fl == NONE && y == h) || (s.fr == NONE && y == o) {
                Some(NONE)
            } else {
                None
            }
        };
        let next = |y: u32| self.he.get(y as usize).map(|r| r.next);
        let resolve = |mut y: u32| -> Option<u32> {
            // At most the two boundary halfedges of the edge are skipped.
            for _ in 0..4 {
                match replacement(y) {
                    Some(NONE) => y = next(y)?,
                    Some(r) => return Some(r),
                    None => return Some(y),
                }
            }
            None
        };
        let leaving = [
            v0vl,
            vrv0,
            if s.fl == NONE { h } else { NONE },
            if s.fr == NONE { o } else { NONE },
        ];
        let mut links: [Link; 4] = [[NONE; 3]; 4];
        let mut n = 0;
        for y in leaving.into_iter().filter(|&y| y != NONE) {
            let x = self.he.get(y as usize)?.prev;
            if replacement(x).is_none() {
                *links.get_mut(n)? = [x, y, resolve(y)?];
                n += 1;
            }
            if let Some(r) = replacement(y).filter(|&r| r != NONE) {
                // `next(r)` before the collapse: `v1vl → vlv0`, `vrv1 → v1v0`.
                let old = if y == v0vl { s.vlv0 } else { o };
                *links.get_mut(n)? = [r, old, resolve(next(y)?)?];
                n += 1;
            }
        }
        Some((links, n))
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

    /// What a checked split compares beyond the record, derived from `step` and the
    /// tombstones of the removed halfedges (bounds-checked: the mesh may not be the
    /// record's; the caller has checked that it shares the record's history).
    fn derive(&self, step: &Step) -> Option<Derived> {
        let sides = self.sides_checked(step.v0v1)?;
        let (links, n_links) = self.links_of(step.v0v1, &sides)?;
        let mut face_halfedges = [[NONE; 3]; 2];
        for (k, (bit, x, r)) in [
            (FACE_LEFT, sides.vlv0, sides.v1vl),
            (FACE_RIGHT, sides.v0vr, sides.vrv1),
        ]
        .into_iter()
        .enumerate()
        {
            if x != NONE && step.changed & bit != 0 {
                let y = x ^ 1;
                let g = self.he.get(y as usize)?.face;
                face_halfedges[k] = [g, y, r];
            }
        }
        let now = |v: u32| self.vertex_conn.get(v as usize).copied();
        let v0_out = now(step.v0)?;
        let v1_out = now(step.v1)?;
        let side = |v: u32, before: u32| -> Option<[u32; 2]> {
            if v == NONE {
                Some([step.before[0], v1_out])
            } else {
                Some([before, now(v)?])
            }
        };
        let vertex_halfedges = [
            [v0_out, v0_out],
            [step.before[0], v1_out],
            side(step.vl, step.before[1])?,
            side(step.vr, step.before[2])?,
        ];
        // `v1 → vl`, or on the boundary the next boundary halfedge: the successor of v0v1.
        let start = self.he.get(step.v0v1 as usize)?.next;
        Some(Derived {
            sides,
            links,
            n_links,
            face_halfedges,
            vertex_halfedges,
            start,
        })
    }

    /// The fingerprint of everything a split of `step` reads or restores beyond what the
    /// checked split compares exactly: the record's handles (so that a record whose fields
    /// were changed does not fit), and, as they are in the mesh now, both halfedges of
    /// every edge the split relinks, revives or walks over (the removed edges, the kept
    /// edges `v1vl`, `vrv1`, the rewritten links, the vertex halfedges before and after,
    /// the halfedges moved from `v0` to `v1`), the halfedges of the removed faces and of
    /// the faces beside the removed edges, and the outgoing halfedges of the record's
    /// vertices. The collapse stores it; the split recomputes it and compares. `None`
    /// when an index leaves the mesh (only possible on a mesh the record does not fit).
    fn split_fingerprint(&self, step: &Step) -> Option<u64> {
        let d = self.derive(step)?;
        let s = &d.sides;
        let mut m = Multilinear::default();
        let (nv, nh, nf) = (self.vertex_conn.len(), self.he.len(), self.face_conn.len());
        let vk = |i: u32| -> Option<u64> {
            Some(if i == NONE {
                0
            } else {
                ((i as usize) < nv).then(|| word(Some(self.vh(i))))?
            })
        };
        let hk = |i: u32| -> Option<u64> {
            Some(if i == NONE {
                0
            } else {
                ((i as usize) < nh).then(|| word(Some(self.hh(i))))?
            })
        };
        let fk = |i: u32| -> Option<u64> {
            Some(if i == NONE {
                0
            } else {
                ((i as usize) < nf).then(|| word(Some(self.fh(i))))?
            })
        };
        for w in [
            hk(step.v0v1)?,
            hk(step.v0v1 ^ 1)?,
            vk(step.v0)?,
            vk(step.v1)?,
            vk(step.vl)?,
            vk(step.vr)?,
            fk(s.fl)?,
            fk(s.fr)?,
            hk(s.v1vl)?,
            hk(s.vlv0)?,
            hk(s.v0vr)?,
            hk(s.vrv1)?,
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
        for x in [step.v0v1, s.vlv0, s.v0vr, s.v1vl, s.vrv1] {
            if x != NONE {
                edge(&mut m, x)?;
            }
        }
        for &[x, old, new] in &d.links[..d.n_links] {
            for i in [x, old, new] {
                edge(&mut m, i)?;
            }
        }
        for &[g, _, _] in &d.face_halfedges {
            if g != NONE {
                m.add(u64::from(*self.face_conn.get(g as usize)?));
            }
        }
        for f in [s.fl, s.fr] {
            if f != NONE {
                m.add(u64::from(*self.face_conn.get(f as usize)?));
            }
        }
        // The faces beside the removed edges, whose loops the split gives back their
        // removed halfedge: the faces of `v1vl` and `vrv1` now.
        for x in [s.v1vl, s.vrv1] {
            if x != NONE {
                let g = self.he.get(x as usize)?.face;
                if g != NONE {
                    m.add(u64::from(*self.face_conn.get(g as usize)?));
                }
            }
        }
        let vertices = [
            step.v0,
            step.v1,
            if step.vl == NONE { step.v1 } else { step.vl },
            if step.vr == NONE { step.v1 } else { step.vr },
        ];
        for (v, &[old, new]) in vertices.into_iter().zip(&d.vertex_halfedges) {
            m.add(u64::from(*self.vertex_conn.get(v as usize)?));
            for i in [old, new] {
                if i != NONE {
                    edge(&mut m, i)?;
                }
            }
        }
        // The walk the split makes around v1.
        let mut k = d.start;
        edge(&mut m, k)?;
        for _ in 0..step.moved {
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
    /// collection, its fields changed, or its neighbourhood changed since the collapse.
    /// Nothing is changed then.
    pub fn vertex_split(&mut self, r: &CollapseRecord) -> Result<()> {
        if let Err(why) = self.split_fits(r) {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generators;

    #[test]
    fn a_hierarchy_keeps_88_bytes_per_collapse_record() {
        // The compact record is what a hierarchy stores per collapse (its fingerprint
        // apart): slot indices, the two positions, and nothing the tombstones keep.
        assert_eq!(std::mem::size_of::<Step>(), 88);
    }

    #[test]
    fn a_record_whose_fields_were_changed_is_refused() {
        let mut mesh = generators::icosphere(2);
        let v = mesh.vertices().nth(5).unwrap();
        let h = mesh.vertex_halfedge(v).unwrap();
        let r = mesh.collapse(h).unwrap();
        let before = mesh.binding();
        for edit in 0..3 {
            let mut bad = r.clone();
            match edit {
                0 => bad.p0.x += 1.0,
                1 => bad.v1 = bad.vl.unwrap(),
                _ => bad.fl = None,
            }
            let e = mesh.vertex_split(&bad).unwrap_err();
            assert!(e.to_string().contains("fields were changed"), "{e}");
            assert!(before.same_connectivity(&mesh));
        }
        mesh.vertex_split(&r).unwrap();
        mesh.check().unwrap();
        assert_eq!(mesh.position(r.v0), r.p0);
    }

    #[test]
    fn the_split_reads_back_what_the_collapse_rewrote_from_the_tombstones() {
        // Every edge of a mesh with a boundary, collapsed and split again: the two
        // triangles and the links derived from the removed halfedges are what the
        // collapse used, and the split restores every field bit for bit.
        let mesh = generators::grid(5, 4, 1.0, 1.0);
        for h in mesh.halfedges().collect::<Vec<_>>() {
            let mut m = mesh.clone();
            if m.is_collapse_ok(h).is_err() {
                continue;
            }
            let (he, vc, fc) = (m.he.clone(), m.vertex_conn.clone(), m.face_conn.clone());
            let hi = Mesh::ix(h);
            let sides = m.sides(hi);
            let links = m.links_of(hi, &sides);
            let (step, _) = m.collapse_unchecked(h);
            assert_eq!(m.sides(hi), sides);
            assert_eq!(m.links_of(hi, &sides), links);
            m.vertex_split_unchecked(&step);
            assert!(m.he == he && m.vertex_conn == vc && m.face_conn == fc);
            m.check().unwrap();
        }
    }
}
