//! The record of a collapse: the public [`CollapseRecord`], the compact `Step` a
//! hierarchy keeps, and what a checked split compares (the fingerprint and the links
//! derived from the tombstones).

use glam::DVec3;

use crate::handle::{FaceId, HalfedgeId, VertexId, NONE};
use crate::mesh::Mesh;

/// One rewritten `next` link, as slot indices: `[halfedge, next before, next after]`.
pub(super) type Link = [u32; 3];

/// A multilinear hash of a fixed sequence of words: `Σ word_i · K_i` with distinct odd
/// constants, so that any change of a single word changes the sum, and the words are
/// independent of each other (no dependency chain).
#[derive(Default)]
pub(super) struct Multilinear {
    pub(super) sum: u64,
    pub(super) i: u64,
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
pub(super) fn word<K: slotmap::Key>(k: Option<K>) -> u64 {
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
    pub(super) step: Step,
    /// The mesh instance the collapse was made on ([`Provenance`](crate::binding::Provenance)'s instance) and its
    /// change count right after the collapse: see `Provenance::is_own_history`.
    pub(super) mesh: u64,
    pub(super) count: u64,
    /// Fingerprint of what the split relies on beyond the fields above (see
    /// [`Mesh::split_fingerprint`]), as the collapse left it.
    pub(crate) fingerprint: u64,
    /// Made by [`Mesh::collapse`] and kept among its waiting collapses (see
    /// `collapse::waiting`), not by a hierarchy.
    pub(super) tracked: bool,
}

impl CollapseRecord {
    /// The vertices that were neighbours of `v0` or `v1` when the edge collapsed,
    /// `v0` and `v1` excluded, are what the centroid detail coefficients need; this gives
    /// the two opposite vertices that are always among them.
    pub fn opposite_vertices(&self) -> impl Iterator<Item = VertexId> {
        self.vl.into_iter().chain(self.vr)
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
    pub(super) before: [u32; 3],
    /// Number of halfedges moved from `v0` to `v1`.
    pub(super) moved: u32,
    /// Bit `i`: the collapse changed the outgoing halfedge of vertex `i` of
    /// `[v1, vl, vr]` (the split writes back only those). Bits [`FACE_LEFT`] and
    /// [`FACE_RIGHT`]: the collapse re-chose the halfedge of the face beyond the removed
    /// edge `vl–v0`, `v0–vr`.
    pub(super) changed: u8,
}

/// [`Step::changed`]: the face beyond `vl–v0` had `v0 → vl` as its halfedge.
pub(super) const FACE_LEFT: u8 = 1 << 3;
/// [`Step::changed`]: the face beyond `v0–vr` had `vr → v0` as its halfedge.
pub(super) const FACE_RIGHT: u8 = 1 << 4;

impl Step {
    /// The fields only the split reads: the outgoing halfedges of `v1`, `vl`, `vr`
    /// before the collapse, the number of halfedges moved and the changed bits (for the
    /// hierarchy file).
    pub(crate) fn split_fields(&self) -> ([u32; 3], u32, u8) {
        (self.before, self.moved, self.changed)
    }

    /// A record from its fields, as [`split_fields`](Self::split_fields) and the public
    /// fields give them (a record read back from a file; the caller checks its indices).
    pub(crate) fn from_fields(
        [p0, p1]: [DVec3; 2],
        [v0v1, v0, v1, vl, vr]: [u32; 5],
        (before, moved, changed): ([u32; 3], u32, u8),
    ) -> Self {
        Self {
            p0,
            p1,
            v0v1,
            v0,
            v1,
            vl,
            vr,
            before,
            moved,
            changed,
        }
    }

    /// The largest value of the changed bits: three vertices and two faces.
    pub(crate) const CHANGED_BITS: u8 = (1 << 5) - 1;

    /// `v1`, `vl`, `vr`, as far as they exist, with their outgoing halfedges before the
    /// collapse and whether the collapse changed them.
    #[inline]
    pub(super) fn restored_vertices(&self) -> impl Iterator<Item = (u32, u32, bool)> + '_ {
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
pub(super) struct Derived {
    pub(super) sides: Sides,
    /// The rewritten links, in the collapse's order.
    pub(super) links: [Link; 4],
    pub(super) n_links: usize,
    /// `[face, halfedge before, halfedge after]` for faces whose halfedge was re-chosen.
    pub(super) face_halfedges: [[u32; 3]; 2],
    /// `[before, after]` outgoing halfedge of `v0`, `v1`, `vl` (or `v1`), `vr` (or `v1`).
    pub(super) vertex_halfedges: [[u32; 2]; 4],
    /// Outgoing halfedge of `v1` after which the moved halfedges start (counter-clockwise).
    pub(super) start: u32,
}

/// # Records
impl Mesh {
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
            tracked: false,
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
    pub(super) fn links_of(&self, h: u32, s: &Sides) -> Option<([Link; 4], usize)> {
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

    /// What a checked split compares beyond the record, derived from `step` and the
    /// tombstones of the removed halfedges (bounds-checked: the mesh may not be the
    /// record's; the caller has checked that it shares the record's history).
    pub(super) fn derive(&self, step: &Step) -> Option<Derived> {
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
    pub(super) fn split_fingerprint(&self, step: &Step) -> Option<u64> {
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
}
