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
use slotmap::SlotMap;

use crate::attributes::AttributeStore;
use crate::handle::slot;
use crate::{Error, FaceId, HalfedgeId, Result, VertexId};

#[derive(Clone, Copy, Debug)]
pub(crate) struct VertexSlot {
    pub(crate) halfedge: Option<HalfedgeId>,
    pub(crate) deleted: bool,
}

#[derive(Clone, Copy, Debug)]
pub(crate) struct HalfedgeSlot {
    pub(crate) to: VertexId,
    pub(crate) next: HalfedgeId,
    pub(crate) prev: HalfedgeId,
    pub(crate) opposite: HalfedgeId,
    pub(crate) face: Option<FaceId>,
    pub(crate) deleted: bool,
}

#[derive(Clone, Copy, Debug)]
pub(crate) struct FaceSlot {
    pub(crate) halfedge: HalfedgeId,
    pub(crate) deleted: bool,
}

/// A triangle mesh in half-edge representation.
///
/// Connectivity lives in three `slotmap`s (one per element kind); positions and user
/// attributes live in dense arrays indexed by the element's slot
/// ([`Mesh::vertex_index`]), as in pmp-library. Removing elements by
/// [`collapse`](Mesh::collapse) only marks them deleted (tombstones), so that
/// [`vertex_split`](Mesh::vertex_split) revives the very same handles;
/// [`garbage_collection`](Mesh::garbage_collection) frees tombstones for good.
///
/// Navigation methods (`next`, `opposite`, `to_vertex`, …) take handles of this mesh and
/// panic on a handle that was never part of it (a programming error, like an index out of
/// bounds). Operations that take user input (`collapse`, building, IO) return
/// [`Error`]s instead.
#[derive(Clone, Default)]
pub struct Mesh {
    pub(crate) vertices: SlotMap<VertexId, VertexSlot>,
    pub(crate) halfedges: SlotMap<HalfedgeId, HalfedgeSlot>,
    pub(crate) faces: SlotMap<FaceId, FaceSlot>,
    pub(crate) positions: Vec<DVec3>,
    pub(crate) vertex_keys: Vec<VertexId>,
    pub(crate) halfedge_keys: Vec<HalfedgeId>,
    pub(crate) face_keys: Vec<FaceId>,
    pub(crate) n_vertices: usize,
    pub(crate) n_halfedges: usize,
    pub(crate) n_faces: usize,
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
            vertices: SlotMap::with_capacity_and_key(vertices),
            halfedges: SlotMap::with_capacity_and_key(halfedges),
            faces: SlotMap::with_capacity_and_key(faces),
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
        self.halfedge_keys.len()
    }
    /// Length of the per-face arrays: every [`face_index`](Self::face_index) is below it.
    #[inline]
    pub fn face_slots(&self) -> usize {
        self.face_keys.len()
    }

    /// The live vertex with [`vertex_index`](Self::vertex_index) `index`, if any
    /// (vertex `index` of the file for a mesh read from a file).
    #[inline]
    pub fn vertex_at(&self, index: usize) -> Option<VertexId> {
        self.vertex_keys
            .get(index)
            .copied()
            .filter(|&v| self.is_valid_vertex(v))
    }
    /// The live halfedge with [`halfedge_index`](Self::halfedge_index) `index`, if any.
    #[inline]
    pub fn halfedge_at(&self, index: usize) -> Option<HalfedgeId> {
        self.halfedge_keys
            .get(index)
            .copied()
            .filter(|&h| self.is_valid_halfedge(h))
    }
    /// The live face with [`face_index`](Self::face_index) `index`, if any.
    #[inline]
    pub fn face_at(&self, index: usize) -> Option<FaceId> {
        self.face_keys
            .get(index)
            .copied()
            .filter(|&f| self.is_valid_face(f))
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
        self.vertices.get(v).is_some_and(|s| !s.deleted)
    }
    /// True when `h` is a live halfedge of this mesh.
    #[inline]
    pub fn is_valid_halfedge(&self, h: HalfedgeId) -> bool {
        self.halfedges.get(h).is_some_and(|s| !s.deleted)
    }
    /// True when `f` is a live face of this mesh.
    #[inline]
    pub fn is_valid_face(&self, f: FaceId) -> bool {
        self.faces.get(f).is_some_and(|s| !s.deleted)
    }
    /// True when `v` is a tombstone: removed by a collapse, revivable by a split.
    #[inline]
    pub fn is_deleted_vertex(&self, v: VertexId) -> bool {
        self.vertices.get(v).is_some_and(|s| s.deleted)
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
        debug_assert!(self.vertices.contains_key(v), "stale vertex handle {v}");
        self.positions[slot(v)]
    }
    /// Sets the position of a vertex.
    #[inline]
    pub fn set_position(&mut self, v: VertexId, p: DVec3) {
        assert!(self.vertices.contains_key(v), "stale vertex handle {v}");
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
        &mut self.positions
    }
}

/// # Creating elements
impl Mesh {
    /// Adds an isolated vertex.
    pub fn add_vertex(&mut self, p: DVec3) -> VertexId {
        let v = self.vertices.insert(VertexSlot {
            halfedge: None,
            deleted: false,
        });
        let i = slot(v);
        if i == self.positions.len() {
            self.positions.push(p);
            self.vertex_keys.push(v);
        } else {
            self.positions[i] = p;
            self.vertex_keys[i] = v;
        }
        self.vertex_attributes.ensure_len(self.positions.len());
        self.n_vertices += 1;
        v
    }

    /// Creates the two halfedges of a new edge `a → b` (returned) and `b → a`,
    /// unlinked (`next`/`prev` point to themselves, no face).
    pub(crate) fn new_edge(&mut self, a: VertexId, b: VertexId) -> HalfedgeId {
        let dummy = HalfedgeSlot {
            to: b,
            next: HalfedgeId::default(),
            prev: HalfedgeId::default(),
            opposite: HalfedgeId::default(),
            face: None,
            deleted: false,
        };
        let h0 = self.halfedges.insert(dummy);
        let h1 = self.halfedges.insert(HalfedgeSlot { to: a, ..dummy });
        {
            let s = &mut self.halfedges[h0];
            s.opposite = h1;
            s.next = h0;
            s.prev = h0;
        }
        {
            let s = &mut self.halfedges[h1];
            s.opposite = h0;
            s.next = h1;
            s.prev = h1;
        }
        for h in [h0, h1] {
            let i = slot(h);
            if i >= self.halfedge_keys.len() {
                self.halfedge_keys.resize(i + 1, HalfedgeId::default());
            }
            self.halfedge_keys[i] = h;
        }
        self.halfedge_attributes
            .ensure_len(self.halfedge_keys.len());
        self.n_halfedges += 2;
        h0
    }

    pub(crate) fn new_face(&mut self, h: HalfedgeId) -> FaceId {
        let f = self.faces.insert(FaceSlot {
            halfedge: h,
            deleted: false,
        });
        let i = slot(f);
        if i >= self.face_keys.len() {
            self.face_keys.resize(i + 1, FaceId::default());
        }
        self.face_keys[i] = f;
        self.face_attributes.ensure_len(self.face_keys.len());
        self.n_faces += 1;
        f
    }

    /// Frees all tombstones left by collapses for good. Handles of removed elements become
    /// stale (and are detected as such); collapse records taken before become useless.
    /// Live handles and the indices of live elements do not change.
    pub fn garbage_collection(&mut self) {
        self.vertices.retain(|_, s| !s.deleted);
        self.halfedges.retain(|_, s| !s.deleted);
        self.faces.retain(|_, s| !s.deleted);
    }
}

/// # Low-level connectivity (pmp / OpenMesh vocabulary)
impl Mesh {
    /// The vertex a halfedge points to.
    #[inline]
    pub fn to_vertex(&self, h: HalfedgeId) -> VertexId {
        self.halfedges[h].to
    }
    /// The vertex a halfedge starts from.
    #[inline]
    pub fn from_vertex(&self, h: HalfedgeId) -> VertexId {
        self.halfedges[self.halfedges[h].opposite].to
    }
    /// The next halfedge around the face (or along the boundary loop).
    #[inline]
    pub fn next(&self, h: HalfedgeId) -> HalfedgeId {
        self.halfedges[h].next
    }
    /// The previous halfedge around the face (or along the boundary loop).
    #[inline]
    pub fn prev(&self, h: HalfedgeId) -> HalfedgeId {
        self.halfedges[h].prev
    }
    /// The other halfedge of the same edge.
    #[inline]
    pub fn opposite(&self, h: HalfedgeId) -> HalfedgeId {
        self.halfedges[h].opposite
    }
    /// The face left of a halfedge; `None` for a boundary halfedge.
    #[inline]
    pub fn face(&self, h: HalfedgeId) -> Option<FaceId> {
        self.halfedges[h].face
    }
    /// An outgoing halfedge of `v`: a boundary halfedge when `v` is on the boundary;
    /// `None` for an isolated vertex.
    #[inline]
    pub fn vertex_halfedge(&self, v: VertexId) -> Option<HalfedgeId> {
        self.vertices[v].halfedge
    }
    /// A halfedge of face `f`.
    #[inline]
    pub fn face_halfedge(&self, f: FaceId) -> HalfedgeId {
        self.faces[f].halfedge
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
        self.halfedges[h].face.is_none()
    }
    /// True when either side of the edge of `h` has no face.
    #[inline]
    pub fn is_boundary_edge(&self, h: HalfedgeId) -> bool {
        self.is_boundary_halfedge(h) || self.is_boundary_halfedge(self.opposite(h))
    }
    /// True when `v` is on the boundary or isolated (as in OpenMesh and pmp).
    #[inline]
    pub fn is_boundary_vertex(&self, v: VertexId) -> bool {
        match self.vertices[v].halfedge {
            None => true,
            Some(h) => self.is_boundary_halfedge(h),
        }
    }
    /// True when `v` has no incident edge.
    #[inline]
    pub fn is_isolated(&self, v: VertexId) -> bool {
        self.vertices[v].halfedge.is_none()
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
        let h0 = self.faces[f].halfedge;
        let h1 = self.next(h0);
        let h2 = self.next(h1);
        [self.to_vertex(h0), self.to_vertex(h1), self.to_vertex(h2)]
    }

    #[inline]
    pub(crate) fn set_next(&mut self, h: HalfedgeId, n: HalfedgeId) {
        self.halfedges[h].next = n;
        self.halfedges[n].prev = h;
    }
    #[inline]
    pub(crate) fn set_face(&mut self, h: HalfedgeId, f: Option<FaceId>) {
        self.halfedges[h].face = f;
    }
    #[inline]
    pub(crate) fn set_vertex_halfedge(&mut self, v: VertexId, h: Option<HalfedgeId>) {
        self.vertices[v].halfedge = h;
    }

    /// Makes the vertex halfedge of `v` a boundary halfedge when there is one (the
    /// invariant every boundary query relies on). Searches clockwise, as OpenMesh does.
    pub(crate) fn adjust_outgoing_halfedge(&mut self, v: VertexId) {
        let Some(start) = self.vertices[v].halfedge else {
            return;
        };
        let mut h = start;
        loop {
            if self.is_boundary_halfedge(h) {
                self.vertices[v].halfedge = Some(h);
                return;
            }
            h = self.cw_rotated(h);
            if h == start {
                return;
            }
        }
    }
}
