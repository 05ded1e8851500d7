//! Element iterators (skipping removed elements) and circulators.
//!
//! Circulators around a vertex turn **counter-clockwise** (seen from outside, with
//! faces oriented counter-clockwise) and start at [`Mesh::vertex_halfedge`], which is the
//! boundary halfedge for a boundary vertex: so on the boundary the first outgoing
//! halfedge has no face and the faces follow in counter-clockwise order. Face
//! circulators start at [`Mesh::face_halfedge`] and follow `next`.

use crate::{FaceId, HalfedgeId, Mesh, VertexId};

/// # Iterating over elements
impl Mesh {
    /// Live vertices, in slot order (file order for a mesh read from a file).
    pub fn vertices(&self) -> impl Iterator<Item = VertexId> + Clone + '_ {
        self.vertices
            .iter()
            .filter(|(_, s)| !s.deleted)
            .map(|(k, _)| k)
    }
    /// Live halfedges, in slot order.
    pub fn halfedges(&self) -> impl Iterator<Item = HalfedgeId> + Clone + '_ {
        self.halfedges
            .iter()
            .filter(|(_, s)| !s.deleted)
            .map(|(k, _)| k)
    }
    /// One halfedge per live edge (the one created first, `a → b` for an edge first
    /// seen as `a → b`).
    pub fn edges(&self) -> impl Iterator<Item = HalfedgeId> + Clone + '_ {
        self.halfedges
            .iter()
            .filter(|(k, s)| {
                !s.deleted && crate::handle::slot(*k) < crate::handle::slot(s.opposite)
            })
            .map(|(k, _)| k)
    }
    /// Live faces, in slot order (file order for a mesh read from a file).
    pub fn faces(&self) -> impl Iterator<Item = FaceId> + Clone + '_ {
        self.faces
            .iter()
            .filter(|(_, s)| !s.deleted)
            .map(|(k, _)| k)
    }
}

/// Outgoing halfedges of a vertex, counter-clockwise (see the module docs).
#[derive(Clone)]
pub struct OutgoingHalfedges<'a> {
    mesh: &'a Mesh,
    start: Option<HalfedgeId>,
    current: Option<HalfedgeId>,
}

impl Iterator for OutgoingHalfedges<'_> {
    type Item = HalfedgeId;
    #[inline]
    fn next(&mut self) -> Option<HalfedgeId> {
        let h = self.current?;
        let n = self.mesh.ccw_rotated(h);
        self.current = if Some(n) == self.start { None } else { Some(n) };
        Some(h)
    }
}

/// Halfedges of a face, following `next`.
#[derive(Clone)]
pub struct FaceHalfedges<'a> {
    mesh: &'a Mesh,
    start: HalfedgeId,
    current: Option<HalfedgeId>,
}

impl Iterator for FaceHalfedges<'_> {
    type Item = HalfedgeId;
    #[inline]
    fn next(&mut self) -> Option<HalfedgeId> {
        let h = self.current?;
        let n = self.mesh.next(h);
        self.current = if n == self.start { None } else { Some(n) };
        Some(h)
    }
}

/// # Circulators
impl Mesh {
    /// Outgoing halfedges of `v`, counter-clockwise from [`vertex_halfedge`](Self::vertex_halfedge).
    #[inline]
    pub fn outgoing_halfedges(&self, v: VertexId) -> OutgoingHalfedges<'_> {
        let start = self.vertex_halfedge(v);
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
        let start = self.face_halfedge(f);
        FaceHalfedges {
            mesh: self,
            start,
            current: Some(start),
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
