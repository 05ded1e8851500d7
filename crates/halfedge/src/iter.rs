//! Element iterators (skipping removed elements) and circulators.
//!
//! Circulators around a vertex turn **counter-clockwise** (seen from outside, with
//! faces oriented counter-clockwise) and start at [`Mesh::vertex_halfedge`], which is the
//! boundary halfedge for a boundary vertex: so on the boundary the first outgoing
//! halfedge has no face and the faces follow in counter-clockwise order. Face
//! circulators start at [`Mesh::face_halfedge`] and follow `next`.

use crate::handle::NONE;
use crate::{FaceId, HalfedgeId, Mesh, VertexId};

/// # Iterating over elements
impl Mesh {
    /// Live vertices, in slot order (file order for a mesh read from a file).
    pub fn vertices(&self) -> impl Iterator<Item = VertexId> + Clone + '_ {
        self.vertex_slots_.live_indices().map(|i| self.vh(i))
    }
    /// Live halfedges, in slot order.
    pub fn halfedges(&self) -> impl Iterator<Item = HalfedgeId> + Clone + '_ {
        self.halfedge_slots_.live_indices().map(|i| self.hh(i))
    }
    /// One halfedge per live edge (the one created first, `a → b` for an edge first
    /// seen as `a → b`).
    pub fn edges(&self) -> impl Iterator<Item = HalfedgeId> + Clone + '_ {
        self.halfedge_slots_
            .live_indices()
            .filter(|i| i % 2 == 0)
            .map(|i| self.hh(i))
    }
    /// Live faces, in slot order (file order for a mesh read from a file).
    pub fn faces(&self) -> impl Iterator<Item = FaceId> + Clone + '_ {
        self.face_slots_.live_indices().map(|i| self.fh(i))
    }
}

/// Outgoing halfedges of a vertex, counter-clockwise (see the module docs).
#[derive(Clone)]
pub struct OutgoingHalfedges<'a> {
    mesh: &'a Mesh,
    start: u32,
    current: u32,
}

impl Iterator for OutgoingHalfedges<'_> {
    type Item = HalfedgeId;
    #[inline]
    fn next(&mut self) -> Option<HalfedgeId> {
        let h = self.current;
        if h == NONE {
            return None;
        }
        // ccw: opposite(prev(h))
        let n = self.mesh.he[h as usize].prev ^ 1;
        self.current = if n == self.start { NONE } else { n };
        Some(self.mesh.hh(h))
    }
}

/// Halfedges of a face, following `next`.
#[derive(Clone)]
pub struct FaceHalfedges<'a> {
    mesh: &'a Mesh,
    start: u32,
    current: u32,
}

impl Iterator for FaceHalfedges<'_> {
    type Item = HalfedgeId;
    #[inline]
    fn next(&mut self) -> Option<HalfedgeId> {
        let h = self.current;
        if h == NONE {
            return None;
        }
        let n = self.mesh.he[h as usize].next;
        self.current = if n == self.start { NONE } else { n };
        Some(self.mesh.hh(h))
    }
}

/// # Circulators
impl Mesh {
    /// Outgoing halfedges of `v`, counter-clockwise from [`vertex_halfedge`](Self::vertex_halfedge).
    #[inline]
    pub fn outgoing_halfedges(&self, v: VertexId) -> OutgoingHalfedges<'_> {
        let start = self.vertex_conn[crate::handle::slot(v)];
        OutgoingHalfedges {
            mesh: self,
            start,
            current: start,
        }
    }
    /// Incoming halfedges of `v` (the opposites of the outgoing ones, same order).
    pub fn incoming_halfedges(&self, v: VertexId) -> impl Iterator<Item = HalfedgeId> + Clone + '_ {
        self.outgoing_halfedges(v).map(move |h| self.opposite(h))
    }
    /// The one-ring neighbours of `v`, counter-clockwise.
    #[inline]
    pub fn adjacent_vertices(&self, v: VertexId) -> impl Iterator<Item = VertexId> + Clone + '_ {
        self.outgoing_halfedges(v).map(move |h| self.to_vertex(h))
    }
    /// The faces around `v`, counter-clockwise (boundary gaps skipped).
    #[inline]
    pub fn adjacent_faces(&self, v: VertexId) -> impl Iterator<Item = FaceId> + Clone + '_ {
        self.outgoing_halfedges(v).filter_map(move |h| self.face(h))
    }
    /// The halfedges of `f`, starting at [`face_halfedge`](Self::face_halfedge).
    #[inline]
    pub fn face_halfedges(&self, f: FaceId) -> FaceHalfedges<'_> {
        let start = self.face_conn[crate::handle::slot(f)];
        FaceHalfedges {
            mesh: self,
            start,
            current: start,
        }
    }
    /// The vertices of `f`, counter-clockwise, starting at `to_vertex(face_halfedge(f))`.
    #[inline]
    pub fn face_vertices(&self, f: FaceId) -> impl Iterator<Item = VertexId> + Clone + '_ {
        self.face_halfedges(f).map(move |h| self.to_vertex(h))
    }
    /// The faces sharing an edge with `f` (boundary edges skipped).
    pub fn face_neighbors(&self, f: FaceId) -> impl Iterator<Item = FaceId> + Clone + '_ {
        self.face_halfedges(f)
            .filter_map(move |h| self.face(self.opposite(h)))
    }
}
