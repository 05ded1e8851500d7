//! The add-face algorithm of OpenMesh's `PolyConnectivity::add_face` (pmp's
//! `SurfaceMesh::add_face`), written once over a small [`Connectivity`] trait so that it
//! runs both on [`Mesh`] (for [`Mesh::add_triangle`]) and on the compact arrays that
//! [`Mesh::from_polygons`] builds with (see [`crate::compact_build`]). Either way the
//! steps, and so the resolution of non-manifold input, are OpenMesh's.
//!
//! It refuses a *complex vertex* (a face vertex that is not on the boundary), a *complex
//! edge* (a face edge whose halfedge already has a face) and a failed patch re-linking.
//! Next links are collected first and written at the end, so a refused face changes
//! nothing.

use crate::handle::{FaceId, HalfedgeId, VertexId};

use crate::mesh::Mesh;

/// The connectivity operations the add-face algorithm needs.
pub(crate) trait Connectivity {
    /// Vertex handle.
    type V: Copy + Eq;
    /// Halfedge handle.
    type H: Copy + Eq;
    /// Face handle.
    type F: Copy;
    fn vertex_halfedge(&self, v: Self::V) -> Option<Self::H>;
    fn set_vertex_halfedge(&mut self, v: Self::V, h: Self::H);
    fn to_vertex(&self, h: Self::H) -> Self::V;
    fn next(&self, h: Self::H) -> Self::H;
    fn prev(&self, h: Self::H) -> Self::H;
    fn opposite(&self, h: Self::H) -> Self::H;
    fn is_boundary_halfedge(&self, h: Self::H) -> bool;
    /// Sets `next(h) = n` and `prev(n) = h`.
    fn set_next(&mut self, h: Self::H, n: Self::H);
    fn set_face(&mut self, h: Self::H, f: Self::F);
    /// Creates the halfedges `a → b` (returned) and `b → a`, unlinked and without face.
    fn new_edge(&mut self, a: Self::V, b: Self::V) -> Self::H;
    fn new_face(&mut self, h: Self::H) -> Self::F;
    /// Called when face `f` has been added completely.
    #[inline]
    fn face_added(&mut self, _f: Self::F) {}
    /// Makes the vertex halfedge of `v` a boundary halfedge when there is one, searching
    /// clockwise as OpenMesh does.
    fn adjust_outgoing_halfedge(&mut self, v: Self::V) {
        let Some(start) = self.vertex_halfedge(v) else {
            return;
        };
        let mut h = start;
        loop {
            if self.is_boundary_halfedge(h) {
                self.set_vertex_halfedge(v, h);
                return;
            }
            h = self.next(self.opposite(h));
            if h == start {
                return;
            }
        }
    }
}

/// Why the add-face algorithm refused a face (generic over the vertex handle).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Refusal<V> {
    ComplexVertex(V),
    ComplexEdge(V, V),
    PatchRelinkingFailed(V),
}

/// Scratch space of the add-face algorithm, reused between faces.
pub(crate) struct Scratch<H> {
    halfedges: Vec<Option<H>>,
    is_new: Vec<bool>,
    needs_adjust: Vec<bool>,
    next_cache: Vec<(H, H)>,
    hs: Vec<H>,
    vertex_halfedges: Vec<Option<H>>,
}

impl<H> Default for Scratch<H> {
    fn default() -> Self {
        Self {
            halfedges: Vec::new(),
            is_new: Vec::new(),
            needs_adjust: Vec::new(),
            next_cache: Vec::new(),
            hs: Vec::new(),
            vertex_halfedges: Vec::new(),
        }
    }
}

/// `find_halfedge` circulating clockwise from `start` (an outgoing halfedge of the
/// vertex) like OpenMesh (the order matters only for speed: there is at most one
/// halfedge `a → b`).
#[inline]
fn find_halfedge_from<M: Connectivity>(m: &M, start: M::H, b: M::V) -> Option<M::H> {
    let mut h = start;
    loop {
        if m.to_vertex(h) == b {
            return Some(h);
        }
        h = m.next(m.opposite(h));
        if h == start {
            return None;
        }
    }
}

/// Adds the polygon `vs` (counter-clockwise) by OpenMesh's add-face algorithm, step for
/// step.
pub(crate) fn add_face<M: Connectivity>(
    m: &mut M,
    vs: &[M::V],
    s: &mut Scratch<M::H>,
) -> Result<M::F, Refusal<M::V>> {
    let n = vs.len();
    s.halfedges.clear();
    s.is_new.clear();
    s.needs_adjust.clear();
    s.next_cache.clear();
    // The vertex halfedges are loaded first, all of them, so that their cache misses
    // overlap (building is bound by memory latency); the checks then run in OpenMesh's
    // order and return the same refusal.
    s.vertex_halfedges.clear();
    s.vertex_halfedges
        .extend(vs.iter().map(|&v| m.vertex_halfedge(v)));
    for i in 0..n {
        let ii = (i + 1) % n;
        let start = s.vertex_halfedges[i];
        if start.is_some_and(|h| !m.is_boundary_halfedge(h)) {
            return Err(Refusal::ComplexVertex(vs[i]));
        }
        let h = start.and_then(|start| find_halfedge_from(m, start, vs[ii]));
        if let Some(h) = h {
            if !m.is_boundary_halfedge(h) {
                return Err(Refusal::ComplexEdge(vs[i], vs[ii]));
            }
        }
        s.halfedges.push(h);
        s.is_new.push(h.is_none());
        s.needs_adjust.push(false);
    }

    // Re-link patches where two consecutive old edges are not consecutive yet.
    for i in 0..n {
        let ii = (i + 1) % n;
        if let (Some(inner_prev), Some(inner_next)) = (s.halfedges[i], s.halfedges[ii]) {
            if m.next(inner_prev) != inner_next {
                // Search a free gap between boundary_prev and boundary_next.
                let outer_prev = m.opposite(inner_next);
                let mut boundary_prev = outer_prev;
                loop {
                    boundary_prev = m.opposite(m.next(boundary_prev));
                    if m.is_boundary_halfedge(boundary_prev) {
                        break;
                    }
                }
                let boundary_next = m.next(boundary_prev);
                if boundary_prev == inner_prev {
                    return Err(Refusal::PatchRelinkingFailed(vs[ii]));
                }
                let patch_start = m.next(inner_prev);
                let patch_end = m.prev(inner_next);
                s.next_cache.push((boundary_prev, patch_start));
                s.next_cache.push((patch_end, boundary_next));
                s.next_cache.push((inner_prev, inner_next));
            }
        }
    }

    // Create missing edges.
    s.hs.clear();
    for i in 0..n {
        let h = match s.halfedges[i] {
            Some(h) => h,
            None => m.new_edge(vs[i], vs[(i + 1) % n]),
        };
        s.hs.push(h);
    }
    let hs = &s.hs;

    let f = m.new_face(hs[n - 1]);
    for i in 0..n {
        let ii = (i + 1) % n;
        let vh = vs[ii];
        let inner_prev = hs[i];
        let inner_next = hs[ii];
        let id = usize::from(s.is_new[i]) | (usize::from(s.is_new[ii]) << 1);
        if id != 0 {
            let outer_prev = m.opposite(inner_next);
            let outer_next = m.opposite(inner_prev);
            match id {
                1 => {
                    // prev is new, next is old
                    let boundary_prev = m.prev(inner_next);
                    s.next_cache.push((boundary_prev, outer_next));
                    m.set_vertex_halfedge(vh, outer_next);
                }
                2 => {
                    // next is new, prev is old
                    let boundary_next = m.next(inner_prev);
                    s.next_cache.push((outer_prev, boundary_next));
                    m.set_vertex_halfedge(vh, boundary_next);
                }
                _ => {
                    // both are new
                    match m.vertex_halfedge(vh) {
                        None => {
                            m.set_vertex_halfedge(vh, outer_next);
                            s.next_cache.push((outer_prev, outer_next));
                        }
                        Some(boundary_next) => {
                            let boundary_prev = m.prev(boundary_next);
                            s.next_cache.push((boundary_prev, outer_next));
                            s.next_cache.push((outer_prev, boundary_next));
                        }
                    }
                }
            }
            s.next_cache.push((inner_prev, inner_next));
        } else {
            s.needs_adjust[ii] = m.vertex_halfedge(vh) == Some(inner_next);
        }
        m.set_face(inner_prev, f);
    }
    for &(a, b) in &s.next_cache {
        m.set_next(a, b);
    }
    for (&v, &adjust) in vs.iter().zip(&s.needs_adjust) {
        if adjust {
            m.adjust_outgoing_halfedge(v);
        }
    }
    m.face_added(f);
    Ok(f)
}

impl Connectivity for Mesh {
    type V = VertexId;
    type H = HalfedgeId;
    type F = FaceId;
    #[inline]
    fn vertex_halfedge(&self, v: VertexId) -> Option<HalfedgeId> {
        Mesh::vertex_halfedge(self, v)
    }
    #[inline]
    fn set_vertex_halfedge(&mut self, v: VertexId, h: HalfedgeId) {
        Mesh::set_vertex_halfedge(self, v, Some(h));
    }
    #[inline]
    fn to_vertex(&self, h: HalfedgeId) -> VertexId {
        Mesh::to_vertex(self, h)
    }
    #[inline]
    fn next(&self, h: HalfedgeId) -> HalfedgeId {
        Mesh::next(self, h)
    }
    #[inline]
    fn prev(&self, h: HalfedgeId) -> HalfedgeId {
        Mesh::prev(self, h)
    }
    #[inline]
    fn opposite(&self, h: HalfedgeId) -> HalfedgeId {
        Mesh::opposite(self, h)
    }
    #[inline]
    fn is_boundary_halfedge(&self, h: HalfedgeId) -> bool {
        Mesh::is_boundary_halfedge(self, h)
    }
    #[inline]
    fn set_next(&mut self, h: HalfedgeId, n: HalfedgeId) {
        Mesh::set_next(self, h, n);
    }
    #[inline]
    fn set_face(&mut self, h: HalfedgeId, f: FaceId) {
        Mesh::set_face(self, h, Some(f));
    }
    #[inline]
    fn new_edge(&mut self, a: VertexId, b: VertexId) -> HalfedgeId {
        Mesh::new_edge(self, a, b)
    }
    #[inline]
    fn new_face(&mut self, h: HalfedgeId) -> FaceId {
        Mesh::new_face(self, h)
    }
    fn adjust_outgoing_halfedge(&mut self, v: VertexId) {
        Mesh::adjust_outgoing_halfedge(self, v);
    }
}
