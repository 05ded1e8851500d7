//! The [`Mesh`] struct: storage, element creation and low-level connectivity.
//!
//! ```text
//!                to_vertex(h)
//!                  /\
//!      next(h)    /  \   prev(h)
//!                / f  \
//!               /  h   \
//!  from_vertex ---------->
//!              <----------
//!               opposite(h)
//! ```
//!
//! Faces are oriented counter-clockwise: `h`, `next(h)`, `next(next(h))` walk around
//! `face(h)` with the face on their left. Boundary halfedges have no face and are linked
//! by `next` along the boundary loop.

use glam::DVec3;

use crate::attributes::AttributeStore;
use crate::binding::{Binding, Bound, Provenance};
use crate::handle::{slot, Slots, NONE};
use crate::{Error, FaceId, HalfedgeId, Result, VertexId};

/// A halfedge's links, as slot indices (`NONE`: no face). Its opposite is the halfedge
/// in the neighbouring slot (`index ^ 1`): edges are created and removed whole.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(C)]
pub(crate) struct HalfedgeRec {
    pub(crate) to: u32,
    pub(crate) next: u32,
    pub(crate) prev: u32,
    pub(crate) face: u32,
}

/// A triangle mesh in half-edge representation.
///
/// Connectivity lives in flat arrays of `u32` slot indices, as in OpenMesh and
/// pmp-library: 16 bytes per halfedge (`to`, `next`, `prev`, `face`; the opposite is
/// the neighbouring slot), 4 bytes per vertex and per face, plus a generation and state
/// per slot. Handles are versioned `slotmap` keys built from the slot index and its
/// generation. Positions and user attributes live in dense arrays indexed by the same
/// slot ([`Mesh::vertex_index`]). Removing elements by [`collapse`](Mesh::collapse)
/// only marks them deleted (tombstones), so that [`vertex_split`](Mesh::vertex_split)
/// revives the very same handles; [`garbage_collection`](Mesh::garbage_collection)
/// frees tombstones for good.
///
/// Navigation methods (`next`, `opposite`, `to_vertex`, …) take handles of this mesh and
/// panic on a handle that was never part of it (a programming error, like an index out of
/// bounds). Operations that take user input (`collapse`, building, IO) return
/// [`Error`]s instead.
#[derive(Default)]
pub struct Mesh {
    /// Outgoing halfedge per vertex slot (`NONE`: isolated).
    pub(crate) vertex_conn: Vec<u32>,
    pub(crate) vertex_slots_: Slots,
    pub(crate) he: Vec<HalfedgeRec>,
    pub(crate) halfedge_slots_: Slots,
    /// A halfedge per face slot.
    pub(crate) face_conn: Vec<u32>,
    pub(crate) face_slots_: Slots,
    pub(crate) positions: Vec<DVec3>,
    pub(crate) n_vertices: usize,
    pub(crate) n_halfedges: usize,
    pub(crate) n_faces: usize,
    /// Who this mesh is and how often it changed: what every [`Binding`] of a value
    /// derived from it is checked against.
    pub(crate) provenance: Provenance,
    pub(crate) vertex_attributes: AttributeStore,
    pub(crate) halfedge_attributes: AttributeStore,
    pub(crate) face_attributes: AttributeStore,
}

impl std::fmt::Debug for Mesh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Mesh")
            .field("vertices", &self.n_vertices)
            .field("edges", &self.n_edges())
            .field("faces", &self.n_faces)
            .finish()
    }
}

/// A clone is a mesh instance of its own: same contents, its own [`Provenance`].
/// Values derived from the mesh before the clone (collapse records, per-vertex data,
/// editing areas) fit either until its connectivity changes; values made afterwards fit
/// only the mesh they were made on. A mesh remembers its last 16 ancestors.
impl Clone for Mesh {
    fn clone(&self) -> Self {
        Self {
            vertex_conn: self.vertex_conn.clone(),
            vertex_slots_: self.vertex_slots_.clone(),
            he: self.he.clone(),
            halfedge_slots_: self.halfedge_slots_.clone(),
            face_conn: self.face_conn.clone(),
            face_slots_: self.face_slots_.clone(),
            positions: self.positions.clone(),
            n_vertices: self.n_vertices,
            n_halfedges: self.n_halfedges,
            n_faces: self.n_faces,
            provenance: self.provenance.clone(),
            vertex_attributes: self.vertex_attributes.clone(),
            halfedge_attributes: self.halfedge_attributes.clone(),
            face_attributes: self.face_attributes.clone(),
        }
    }
}

/// # Slot indices and handles (crate-internal)
impl Mesh {
    /// Records that the connectivity changed: bindings made before stop fitting.
    #[inline]
    pub(crate) fn touch_topology(&mut self) {
        self.provenance.connectivity_changed();
    }
    /// Vertex handle of slot `i`.
    #[inline]
    pub(crate) fn vh(&self, i: u32) -> VertexId {
        self.vertex_slots_.key(i)
    }
    /// Halfedge handle of slot `i`.
    #[inline]
    pub(crate) fn hh(&self, i: u32) -> HalfedgeId {
        self.halfedge_slots_.key(i)
    }
    /// Face handle of slot `i`.
    #[inline]
    pub(crate) fn fh(&self, i: u32) -> FaceId {
        self.face_slots_.key(i)
    }
    /// Face handle of slot `i`, `None` for `NONE`.
    #[inline]
    pub(crate) fn fh_opt(&self, i: u32) -> Option<FaceId> {
        (i != NONE).then(|| self.fh(i))
    }
    /// The record of halfedge `h`.
    #[inline]
    pub(crate) fn rec(&self, h: HalfedgeId) -> &HalfedgeRec {
        self.check_halfedge(h);
        &self.he[slot(h)]
    }
    /// The record of halfedge `h`, mutable.
    #[inline]
    pub(crate) fn rec_mut(&mut self, h: HalfedgeId) -> &mut HalfedgeRec {
        self.check_halfedge(h);
        &mut self.he[slot(h)]
    }
    /// Refuses a handle that names no vertex of this mesh (never made here, or freed by
    /// garbage collection: a reused slot has another generation), in release builds too,
    /// so a stale handle never reads another element's data. Tombstones (collapsed
    /// vertices) pass: their data is kept for the split that revives them. Until garbage
    /// collection first frees a slot this is one predictable branch (a handle past the
    /// arrays is still refused, by the indexing's bounds check).
    #[inline(always)]
    pub(crate) fn check_vertex(&self, v: VertexId) {
        if self.vertex_slots_.collected() {
            self.vertex_slots_.check_collected(v, "vertex");
        }
    }
    /// [`check_vertex`](Self::check_vertex) for halfedges.
    #[inline(always)]
    pub(crate) fn check_halfedge(&self, h: HalfedgeId) {
        if self.halfedge_slots_.collected() {
            self.halfedge_slots_.check_collected(h, "halfedge");
        }
    }
    /// [`check_vertex`](Self::check_vertex) for faces.
    #[inline(always)]
    pub(crate) fn check_face(&self, f: FaceId) {
        if self.face_slots_.collected() {
            self.face_slots_.check_collected(f, "face");
        }
    }
    /// Slot index of a handle as `u32`.
    #[inline]
    pub(crate) fn ix<K: slotmap::Key>(k: K) -> u32 {
        slot(k) as u32
    }
    /// Slot index of an optional handle, `NONE` for `None`.
    #[inline]
    pub(crate) fn ix_opt<K: slotmap::Key>(k: Option<K>) -> u32 {
        k.map_or(NONE, |k| slot(k) as u32)
    }
}

/// # Counts and storage
impl Mesh {
    /// An empty mesh.
    pub fn new() -> Self {
        Self::default()
    }

    /// An empty mesh with room for the given numbers of elements.
    pub fn with_capacity(vertices: usize, faces: usize) -> Self {
        let halfedges = 2 * (vertices + faces + 2);
        Self {
            vertex_conn: Vec::with_capacity(vertices),
            vertex_slots_: Slots::with_capacity(vertices),
            he: Vec::with_capacity(halfedges),
            halfedge_slots_: Slots::with_capacity(halfedges),
            face_conn: Vec::with_capacity(faces),
            face_slots_: Slots::with_capacity(faces),
            positions: Vec::with_capacity(vertices),
            ..Self::default()
        }
    }

    /// Number of live vertices (isolated vertices included).
    #[inline]
    pub fn n_vertices(&self) -> usize {
        self.n_vertices
    }
    /// Number of live halfedges.
    #[inline]
    pub fn n_halfedges(&self) -> usize {
        self.n_halfedges
    }
    /// Number of live edges (half the halfedges).
    #[inline]
    pub fn n_edges(&self) -> usize {
        self.n_halfedges / 2
    }
    /// Number of live faces.
    #[inline]
    pub fn n_faces(&self) -> usize {
        self.n_faces
    }
    /// The binding of a value derived from this mesh now (see [`Binding`]).
    #[inline]
    pub fn binding(&self) -> Binding {
        self.provenance.binding()
    }
    /// True when the mesh has no live vertex.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.n_vertices == 0
    }

    /// Length of the per-vertex arrays (live vertices, tombstones and free slots):
    /// every [`vertex_index`](Self::vertex_index) is below it.
    #[inline]
    pub fn vertex_slots(&self) -> usize {
        self.positions.len()
    }
    /// Length of the per-halfedge arrays: every [`halfedge_index`](Self::halfedge_index) is below it.
    #[inline]
    pub fn halfedge_slots(&self) -> usize {
        self.he.len()
    }
    /// Length of the per-face arrays: every [`face_index`](Self::face_index) is below it.
    #[inline]
    pub fn face_slots(&self) -> usize {
        self.face_conn.len()
    }

    /// The live vertex with [`vertex_index`](Self::vertex_index) `index`, if any
    /// (vertex `index` of the file for a mesh read from a file).
    #[inline]
    pub fn vertex_at(&self, index: usize) -> Option<VertexId> {
        self.vertex_slots_
            .is_live_index(index)
            .then(|| self.vh(index as u32))
    }
    /// The live halfedge with [`halfedge_index`](Self::halfedge_index) `index`, if any.
    #[inline]
    pub fn halfedge_at(&self, index: usize) -> Option<HalfedgeId> {
        self.halfedge_slots_
            .is_live_index(index)
            .then(|| self.hh(index as u32))
    }
    /// The live face with [`face_index`](Self::face_index) `index`, if any.
    #[inline]
    pub fn face_at(&self, index: usize) -> Option<FaceId> {
        self.face_slots_
            .is_live_index(index)
            .then(|| self.fh(index as u32))
    }

    /// Dense index of a vertex in per-vertex arrays such as [`positions`](Self::positions).
    /// For a mesh read from a file, vertex `i` of the file has index `i`.
    #[inline]
    pub fn vertex_index(&self, v: VertexId) -> usize {
        slot(v)
    }
    /// Dense index of a halfedge in per-halfedge arrays.
    #[inline]
    pub fn halfedge_index(&self, h: HalfedgeId) -> usize {
        slot(h)
    }
    /// Dense index of a face in per-face arrays; faces built from a file keep file order
    /// (after triangulation).
    #[inline]
    pub fn face_index(&self, f: FaceId) -> usize {
        slot(f)
    }

    /// True when `v` is a live vertex of this mesh.
    #[inline]
    pub fn is_valid_vertex(&self, v: VertexId) -> bool {
        self.vertex_slots_.is_live(v)
    }
    /// True when `h` is a live halfedge of this mesh.
    #[inline]
    pub fn is_valid_halfedge(&self, h: HalfedgeId) -> bool {
        self.halfedge_slots_.is_live(h)
    }
    /// True when `f` is a live face of this mesh.
    #[inline]
    pub fn is_valid_face(&self, f: FaceId) -> bool {
        self.face_slots_.is_live(f)
    }
    /// True when `v` is a tombstone: removed by a collapse, revivable by a split.
    #[inline]
    pub fn is_deleted_vertex(&self, v: VertexId) -> bool {
        self.vertex_slots_.is_tombstone(v)
    }

    /// Returns `Err(InvalidHandle)` unless `v` is live.
    pub fn ensure_vertex(&self, v: VertexId) -> Result<()> {
        if self.is_valid_vertex(v) {
            Ok(())
        } else {
            Err(Error::InvalidHandle(format!("vertex {v}")))
        }
    }
    /// Returns `Err(InvalidHandle)` unless `h` is live.
    pub fn ensure_halfedge(&self, h: HalfedgeId) -> Result<()> {
        if self.is_valid_halfedge(h) {
            Ok(())
        } else {
            Err(Error::InvalidHandle(format!("halfedge {h}")))
        }
    }
    /// Returns `Err(InvalidHandle)` unless `f` is live.
    pub fn ensure_face(&self, f: FaceId) -> Result<()> {
        if self.is_valid_face(f) {
            Ok(())
        } else {
            Err(Error::InvalidHandle(format!("face {f}")))
        }
    }
}

/// # Positions
impl Mesh {
    /// Position of a vertex.
    #[inline]
    pub fn position(&self, v: VertexId) -> DVec3 {
        self.check_vertex(v);
        self.positions[slot(v)]
    }
    /// Sets the position of a vertex.
    #[inline]
    pub fn set_position(&mut self, v: VertexId, p: DVec3) {
        self.check_vertex(v);
        self.provenance.positions_changed();
        self.positions[slot(v)] = p;
    }
    /// All positions, indexed by [`vertex_index`](Self::vertex_index). Entries of removed
    /// vertices are kept (a collapsed vertex keeps its last position).
    #[inline]
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }
    /// Mutable positions, indexed by [`vertex_index`](Self::vertex_index); use it for
    /// parallel per-vertex updates (`par_iter_mut`).
    #[inline]
    pub fn positions_mut(&mut self) -> &mut [DVec3] {
        self.provenance.positions_changed();
        &mut self.positions
    }
}

/// # Creating elements
impl Mesh {
    /// Adds an isolated vertex.
    pub fn add_vertex(&mut self, p: DVec3) -> VertexId {
        let (i, reused) = self.vertex_slots_.allocate();
        if reused {
            self.positions[i as usize] = p;
            self.vertex_conn[i as usize] = NONE;
        } else {
            self.positions.push(p);
            self.vertex_conn.push(NONE);
        }
        self.vertex_attributes.ensure_len(self.positions.len());
        self.n_vertices += 1;
        self.touch_topology();
        self.vh(i)
    }

    /// Creates the two halfedges of a new edge `a → b` (returned) and `b → a`,
    /// unlinked (`next`/`prev` point to themselves, no face).
    pub(crate) fn new_edge(&mut self, a: VertexId, b: VertexId) -> HalfedgeId {
        let (i, reused) = self.halfedge_slots_.allocate_pair();
        let pair = [
            HalfedgeRec {
                to: Self::ix(b),
                next: i,
                prev: i,
                face: NONE,
            },
            HalfedgeRec {
                to: Self::ix(a),
                next: i + 1,
                prev: i + 1,
                face: NONE,
            },
        ];
        if reused {
            self.he[i as usize..i as usize + 2].copy_from_slice(&pair);
        } else {
            self.he.extend_from_slice(&pair);
        }
        self.halfedge_attributes.ensure_len(self.he.len());
        self.n_halfedges += 2;
        self.touch_topology();
        self.hh(i)
    }

    pub(crate) fn new_face(&mut self, h: HalfedgeId) -> FaceId {
        let (i, reused) = self.face_slots_.allocate();
        if reused {
            self.face_conn[i as usize] = Self::ix(h);
        } else {
            self.face_conn.push(Self::ix(h));
        }
        self.face_attributes.ensure_len(self.face_conn.len());
        self.n_faces += 1;
        self.touch_topology();
        self.fh(i)
    }

    /// Frees all tombstones left by collapses for good: their slots are reused by
    /// elements created later, under new versions. Handles of removed elements become
    /// stale (and are detected as such); collapse records taken before become useless.
    /// Live handles and the indices of live elements do not change.
    pub fn garbage_collection(&mut self) {
        let freed = self.vertex_slots_.free_tombstones();
        self.vertex_slots_.push_free(freed.into_iter().rev());
        let freed = self.halfedge_slots_.free_tombstones();
        self.halfedge_slots_
            .push_free(freed.into_iter().rev().filter(|i| i % 2 == 0));
        let freed = self.face_slots_.free_tombstones();
        self.face_slots_.push_free(freed.into_iter().rev());
        self.touch_topology();
    }
}

/// # Low-level connectivity (pmp / OpenMesh vocabulary)
impl Mesh {
    /// The vertex a halfedge points to.
    #[inline]
    pub fn to_vertex(&self, h: HalfedgeId) -> VertexId {
        self.vh(self.rec(h).to)
    }
    /// The vertex a halfedge starts from.
    #[inline]
    pub fn from_vertex(&self, h: HalfedgeId) -> VertexId {
        self.check_halfedge(h);
        self.vh(self.he[slot(h) ^ 1].to)
    }
    /// The next halfedge around the face (or along the boundary loop).
    #[inline]
    pub fn next(&self, h: HalfedgeId) -> HalfedgeId {
        self.hh(self.rec(h).next)
    }
    /// The previous halfedge around the face (or along the boundary loop).
    #[inline]
    pub fn prev(&self, h: HalfedgeId) -> HalfedgeId {
        self.hh(self.rec(h).prev)
    }
    /// The other halfedge of the same edge.
    #[inline]
    pub fn opposite(&self, h: HalfedgeId) -> HalfedgeId {
        self.check_halfedge(h);
        self.hh(Self::ix(h) ^ 1)
    }
    /// The face left of a halfedge; `None` for a boundary halfedge.
    #[inline]
    pub fn face(&self, h: HalfedgeId) -> Option<FaceId> {
        self.fh_opt(self.rec(h).face)
    }
    /// An outgoing halfedge of `v`: a boundary halfedge when `v` is on the boundary;
    /// `None` for an isolated vertex.
    #[inline]
    pub fn vertex_halfedge(&self, v: VertexId) -> Option<HalfedgeId> {
        self.check_vertex(v);
        let h = self.vertex_conn[slot(v)];
        (h != NONE).then(|| self.hh(h))
    }
    /// A halfedge of face `f`.
    #[inline]
    pub fn face_halfedge(&self, f: FaceId) -> HalfedgeId {
        self.check_face(f);
        self.hh(self.face_conn[slot(f)])
    }
    /// The next outgoing halfedge of `from_vertex(h)`, counter-clockwise:
    /// `opposite(prev(h))`.
    #[inline]
    pub fn ccw_rotated(&self, h: HalfedgeId) -> HalfedgeId {
        self.opposite(self.prev(h))
    }
    /// The next outgoing halfedge of `from_vertex(h)`, clockwise: `next(opposite(h))`.
    #[inline]
    pub fn cw_rotated(&self, h: HalfedgeId) -> HalfedgeId {
        self.next(self.opposite(h))
    }
    /// True when `h` has no face.
    #[inline]
    pub fn is_boundary_halfedge(&self, h: HalfedgeId) -> bool {
        self.rec(h).face == NONE
    }
    /// True when either side of the edge of `h` has no face.
    #[inline]
    pub fn is_boundary_edge(&self, h: HalfedgeId) -> bool {
        self.is_boundary_halfedge(h) || self.is_boundary_halfedge(self.opposite(h))
    }
    /// True when `v` is on the boundary or isolated (as in OpenMesh and pmp).
    #[inline]
    pub fn is_boundary_vertex(&self, v: VertexId) -> bool {
        self.check_vertex(v);
        match self.vertex_conn[slot(v)] {
            NONE => true,
            h => self.he[h as usize].face == NONE,
        }
    }
    /// True when `v` has no incident edge.
    #[inline]
    pub fn is_isolated(&self, v: VertexId) -> bool {
        self.check_vertex(v);
        self.vertex_conn[slot(v)] == NONE
    }
    /// True when some edge of `f` is on the boundary.
    pub fn is_boundary_face(&self, f: FaceId) -> bool {
        self.face_halfedges(f)
            .any(|h| self.is_boundary_halfedge(self.opposite(h)))
    }
    /// Number of edges incident to `v` (0 for an isolated vertex).
    pub fn valence(&self, v: VertexId) -> usize {
        self.outgoing_halfedges(v).count()
    }
    /// The halfedge `a → b`, if the edge exists.
    pub fn find_halfedge(&self, a: VertexId, b: VertexId) -> Option<HalfedgeId> {
        self.outgoing_halfedges(a).find(|&h| self.to_vertex(h) == b)
    }
    /// The three vertices of a triangle, starting at `to_vertex(face_halfedge(f))`.
    #[inline]
    pub fn triangle(&self, f: FaceId) -> [VertexId; 3] {
        self.check_face(f);
        let h0 = self.face_conn[slot(f)];
        let r0 = &self.he[h0 as usize];
        let r1 = &self.he[r0.next as usize];
        let r2 = &self.he[r1.next as usize];
        [self.vh(r0.to), self.vh(r1.to), self.vh(r2.to)]
    }

    #[inline]
    pub(crate) fn set_next(&mut self, h: HalfedgeId, n: HalfedgeId) {
        self.rec_mut(h).next = Self::ix(n);
        self.rec_mut(n).prev = Self::ix(h);
    }
    /// `next(x) = n` and `prev(n) = x`, on slot indices.
    #[inline]
    pub(crate) fn set_next_ix(&mut self, x: u32, n: u32) {
        self.he[x as usize].next = n;
        self.he[n as usize].prev = x;
    }
    #[inline]
    pub(crate) fn set_face(&mut self, h: HalfedgeId, f: Option<FaceId>) {
        self.rec_mut(h).face = Self::ix_opt(f);
    }
    #[inline]
    pub(crate) fn set_vertex_halfedge(&mut self, v: VertexId, h: Option<HalfedgeId>) {
        self.vertex_conn[slot(v)] = Self::ix_opt(h);
    }
    #[inline]
    pub(crate) fn set_face_halfedge(&mut self, f: FaceId, h: HalfedgeId) {
        self.face_conn[slot(f)] = Self::ix(h);
    }
    #[inline]
    pub(crate) fn set_to_vertex(&mut self, h: HalfedgeId, v: VertexId) {
        self.rec_mut(h).to = Self::ix(v);
    }

    /// Makes the vertex halfedge of `v` a boundary halfedge when there is one (the
    /// invariant every boundary query relies on). Searches clockwise, as OpenMesh does.
    pub(crate) fn adjust_outgoing_halfedge(&mut self, v: VertexId) {
        let start = self.vertex_conn[slot(v)];
        if start == NONE {
            return;
        }
        let mut h = start;
        loop {
            if self.he[h as usize].face == NONE {
                self.vertex_conn[slot(v)] = h;
                return;
            }
            // cw: next(opposite(h))
            h = self.he[(h ^ 1) as usize].next;
            if h == start {
                return;
            }
        }
    }
}

impl Bound for Mesh {
    #[inline]
    fn provenance(&self) -> &Provenance {
        &self.provenance
    }
}
