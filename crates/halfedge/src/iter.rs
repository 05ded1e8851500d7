//! Element iterators (skipping removed elements) and circulators.
//!
//! Circulators around a vertex turn **counter-clockwise** (seen from outside, with
//! faces oriented counter-clockwise) and start at [`Mesh::vertex_halfedge`], which is the
//! boundary halfedge for a boundary vertex: so on the boundary the first outgoing
//! halfedge has no face and the faces follow in counter-clockwise order. Face
//! circulators start at [`Mesh::face_halfedge`] and follow `next`.

use crate::handle::{FaceId, HalfedgeId, VertexId};
use crate::handle::{Slots, NONE};
use crate::mesh::HalfedgeRec;
use crate::mesh::Mesh;

/// # Iterating over elements
impl Mesh {
    /// Live vertices, in slot order (file order for a mesh read from a file).
    #[inline]
    pub fn vertices(&self) -> impl Iterator<Item = VertexId> + Clone + '_ {
        let slots = &self.vertex_slots_;
        slots.live_indices().map(move |i| slots.key(i))
    }
    /// Live halfedges, in slot order.
    #[inline]
    pub fn halfedges(&self) -> impl Iterator<Item = HalfedgeId> + Clone + '_ {
        let slots = &self.halfedge_slots_;
        slots.live_indices().map(move |i| slots.key(i))
    }
    /// One halfedge per live edge (the one created first, `a → b` for an edge first
    /// seen as `a → b`).
    #[inline]
    pub fn edges(&self) -> impl Iterator<Item = HalfedgeId> + Clone + '_ {
        let slots = &self.halfedge_slots_;
        slots.live_even_indices().map(move |i| slots.key(i))
    }
    /// Live faces, in slot order (file order for a mesh read from a file).
    #[inline]
    pub fn faces(&self) -> impl Iterator<Item = FaceId> + Clone + '_ {
        let slots = &self.face_slots_;
        slots.live_indices().map(move |i| slots.key(i))
    }
}

/// A walk over halfedge records from `current` back to `start`: around a vertex
/// (`AROUND_VERTEX`, counter-clockwise: `opposite(prev(h))`) or around a face (`next`).
/// Yields each halfedge's slot with its record.
///
/// The walk ends when it comes back to `stop`, which is `NONE` until the first step and
/// `start` after it: so the next halfedge depends on the record alone (no select on the
/// chain of loads, whose latency bounds a walk), and an isolated vertex (`start ==
/// NONE`) ends at once. `NONE` is beyond every halfedge array, so the slice's own bounds
/// check is the only one.
#[derive(Clone, Debug)]
struct Walk<'a, const AROUND_VERTEX: bool> {
    he: &'a [HalfedgeRec],
    start: u32,
    current: u32,
    stop: u32,
}

impl<'a, const AROUND_VERTEX: bool> Walk<'a, AROUND_VERTEX> {
    #[inline]
    fn new(he: &'a [HalfedgeRec], start: u32) -> Self {
        Self {
            he,
            start,
            current: start,
            stop: NONE,
        }
    }
    #[inline(always)]
    fn step(r: &HalfedgeRec) -> u32 {
        if AROUND_VERTEX {
            r.prev ^ 1
        } else {
            r.next
        }
    }
}

impl<'a, const AROUND_VERTEX: bool> Iterator for Walk<'a, AROUND_VERTEX> {
    type Item = (u32, &'a HalfedgeRec);
    #[inline]
    fn next(&mut self) -> Option<Self::Item> {
        let h = self.current;
        if h == self.stop {
            return None;
        }
        let r = self.he.get(h as usize)?;
        self.stop = self.start;
        self.current = Self::step(r);
        Some((h, r))
    }
    #[inline]
    fn fold<B, F: FnMut(B, Self::Item) -> B>(self, init: B, mut f: F) -> B {
        let mut acc = init;
        let mut h = self.current;
        if h == self.stop {
            return acc;
        }
        while let Some(r) = self.he.get(h as usize) {
            acc = f(acc, (h, r));
            h = Self::step(r);
            if h == self.start {
                break;
            }
        }
        acc
    }
}

/// The walk around the vertex whose outgoing halfedge is `start` (`NONE`: isolated), for
/// crate code that works on slot indices.
#[inline]
pub(crate) fn vertex_walk(
    he: &[HalfedgeRec],
    start: u32,
) -> impl Iterator<Item = (u32, &HalfedgeRec)> + Clone {
    Walk::<true>::new(he, start)
}

/// Outgoing halfedges of a vertex, counter-clockwise (see the module docs).
#[derive(Clone, Debug)]
pub struct OutgoingHalfedges<'a> {
    walk: Walk<'a, true>,
    slots: &'a Slots,
}

impl Iterator for OutgoingHalfedges<'_> {
    type Item = HalfedgeId;
    #[inline]
    fn next(&mut self) -> Option<HalfedgeId> {
        self.walk.next().map(|(h, _)| self.slots.key(h))
    }
    #[inline]
    fn fold<B, F: FnMut(B, HalfedgeId) -> B>(self, init: B, mut f: F) -> B {
        let slots = self.slots;
        self.walk.fold(init, |acc, (h, _)| f(acc, slots.key(h)))
    }
}

/// Halfedges of a face, following `next`.
#[derive(Clone, Debug)]
pub struct FaceHalfedges<'a> {
    walk: Walk<'a, false>,
    slots: &'a Slots,
}

impl Iterator for FaceHalfedges<'_> {
    type Item = HalfedgeId;
    #[inline]
    fn next(&mut self) -> Option<HalfedgeId> {
        self.walk.next().map(|(h, _)| self.slots.key(h))
    }
    #[inline]
    fn fold<B, F: FnMut(B, HalfedgeId) -> B>(self, init: B, mut f: F) -> B {
        let slots = self.slots;
        self.walk.fold(init, |acc, (h, _)| f(acc, slots.key(h)))
    }
}

/// # Circulators
impl Mesh {
    #[inline(always)]
    fn vertex_walk(&self, v: VertexId) -> Walk<'_, true> {
        self.check_vertex(v);
        Walk::new(&self.he, self.vertex_conn[crate::handle::slot(v)])
    }
    #[inline(always)]
    fn face_walk(&self, f: FaceId) -> Walk<'_, false> {
        self.check_face(f);
        Walk::new(&self.he, self.face_conn[crate::handle::slot(f)])
    }
    /// Outgoing halfedges of `v`, counter-clockwise from [`vertex_halfedge`](Self::vertex_halfedge).
    #[inline]
    pub fn outgoing_halfedges(&self, v: VertexId) -> OutgoingHalfedges<'_> {
        OutgoingHalfedges {
            walk: self.vertex_walk(v),
            slots: &self.halfedge_slots_,
        }
    }
    /// Incoming halfedges of `v` (the opposites of the outgoing ones, same order).
    #[inline]
    pub fn incoming_halfedges(&self, v: VertexId) -> impl Iterator<Item = HalfedgeId> + Clone + '_ {
        let slots = &self.halfedge_slots_;
        self.vertex_walk(v).map(move |(h, _)| slots.key(h ^ 1))
    }
    /// The one-ring neighbours of `v`, counter-clockwise.
    #[inline]
    pub fn adjacent_vertices(&self, v: VertexId) -> impl Iterator<Item = VertexId> + Clone + '_ {
        let slots = &self.vertex_slots_;
        self.vertex_walk(v).map(move |(_, r)| slots.key(r.to))
    }
    /// The faces around `v`, counter-clockwise (boundary gaps skipped).
    #[inline]
    pub fn adjacent_faces(&self, v: VertexId) -> impl Iterator<Item = FaceId> + Clone + '_ {
        let slots = &self.face_slots_;
        self.vertex_walk(v)
            .filter(|(_, r)| r.face != NONE)
            .map(move |(_, r)| slots.key(r.face))
    }
    /// The halfedges of `f`, starting at [`face_halfedge`](Self::face_halfedge).
    #[inline]
    pub fn face_halfedges(&self, f: FaceId) -> FaceHalfedges<'_> {
        FaceHalfedges {
            walk: self.face_walk(f),
            slots: &self.halfedge_slots_,
        }
    }
    /// The vertices of `f`, counter-clockwise, starting at `to_vertex(face_halfedge(f))`.
    #[inline]
    pub fn face_vertices(&self, f: FaceId) -> impl Iterator<Item = VertexId> + Clone + '_ {
        let slots = &self.vertex_slots_;
        self.face_walk(f).map(move |(_, r)| slots.key(r.to))
    }
    /// The faces sharing an edge with `f` (boundary edges skipped).
    #[inline]
    pub fn face_neighbors(&self, f: FaceId) -> impl Iterator<Item = FaceId> + Clone + '_ {
        let (he, slots) = (&self.he[..], &self.face_slots_);
        self.face_walk(f)
            .filter_map(move |(h, _)| he.get((h ^ 1) as usize))
            .filter(|r| r.face != NONE)
            .map(move |r| slots.key(r.face))
    }
}

#[cfg(test)]
mod tests {
    use crate::generators;
    use crate::handle::HalfedgeId;
    use crate::mesh::Mesh;

    /// Items of an iterator by `next`, by `fold`, and by one `next` then `fold`.
    fn three_ways<T: PartialEq + std::fmt::Debug>(it: impl Iterator<Item = T> + Clone) -> Vec<T> {
        let mut by_next = Vec::new();
        // A `for` loop calls `next`.
        for x in it.clone() {
            by_next.push(x);
        }
        let by_fold = it.clone().fold(Vec::new(), |mut v, x| {
            v.push(x);
            v
        });
        let mut it3 = it;
        let mut mixed: Vec<T> = it3.next().into_iter().collect();
        mixed = it3.fold(mixed, |mut v, x| {
            v.push(x);
            v
        });
        assert_eq!(by_next, by_fold);
        assert_eq!(by_next, mixed);
        by_next
    }

    /// A grid (boundary, corners of valence 2 and 3) with collapsed edges (tombstones)
    /// and an isolated vertex.
    fn mesh_with_holes() -> Mesh {
        let mut mesh = generators::grid(9, 7, 1.0, 1.0);
        for _ in 0..6 {
            let h = mesh
                .halfedges()
                .filter(|&h| mesh.is_collapse_ok(h).is_ok())
                .nth(17)
                .unwrap();
            mesh.collapse(h).unwrap();
        }
        mesh.add_vertex(glam::DVec3::ZERO);
        mesh.check().unwrap();
        mesh
    }

    /// Every circulator gives, by `next` and by `fold` alike, what the navigation
    /// primitives give step by step (`ccw_rotated` around a vertex, `next` around a face).
    #[test]
    fn circulators_match_the_primitives() {
        let mesh = mesh_with_holes();
        let mut isolated = 0;
        for v in mesh.vertices() {
            let mut ring: Vec<HalfedgeId> = Vec::new();
            if let Some(start) = mesh.vertex_halfedge(v) {
                let mut h = start;
                loop {
                    ring.push(h);
                    h = mesh.ccw_rotated(h);
                    if h == start {
                        break;
                    }
                }
            } else {
                isolated += 1;
            }
            assert_eq!(three_ways(mesh.outgoing_halfedges(v)), ring);
            let incoming: Vec<_> = ring.iter().map(|&h| mesh.opposite(h)).collect();
            assert_eq!(three_ways(mesh.incoming_halfedges(v)), incoming);
            let ring_vertices: Vec<_> = ring.iter().map(|&h| mesh.to_vertex(h)).collect();
            assert_eq!(three_ways(mesh.adjacent_vertices(v)), ring_vertices);
            let faces: Vec<_> = ring.iter().filter_map(|&h| mesh.face(h)).collect();
            assert_eq!(three_ways(mesh.adjacent_faces(v)), faces);
            assert_eq!(mesh.valence(v), ring.len());
        }
        assert_eq!(isolated, 1);
        for f in mesh.faces() {
            let h0 = mesh.face_halfedge(f);
            let (h1, h2) = (mesh.next(h0), mesh.next(mesh.next(h0)));
            assert_eq!(three_ways(mesh.face_halfedges(f)), [h0, h1, h2]);
            let vs = [h0, h1, h2].map(|h| mesh.to_vertex(h));
            assert_eq!(three_ways(mesh.face_vertices(f)), vs);
            assert_eq!(vs, mesh.triangle(f));
            let neighbours: Vec<_> = [h0, h1, h2]
                .iter()
                .filter_map(|&h| mesh.face(mesh.opposite(h)))
                .collect();
            assert_eq!(three_ways(mesh.face_neighbors(f)), neighbours);
        }
    }

    /// Element iterators give the live elements in slot order, by `next` and `fold`.
    #[test]
    fn element_iterators_skip_removed_elements() {
        let mesh = mesh_with_holes();
        let vertices: Vec<_> = (0..mesh.vertex_slots())
            .filter_map(|i| mesh.vertex_at(i))
            .collect();
        assert_eq!(vertices.len(), mesh.n_vertices());
        assert_eq!(three_ways(mesh.vertices()), vertices);
        let halfedges: Vec<_> = (0..mesh.halfedge_slots())
            .filter_map(|i| mesh.halfedge_at(i))
            .collect();
        assert_eq!(three_ways(mesh.halfedges()), halfedges);
        let edges: Vec<_> = halfedges
            .iter()
            .copied()
            .filter(|&h| mesh.halfedge_index(h) % 2 == 0)
            .collect();
        assert_eq!(edges.len(), mesh.n_edges());
        assert_eq!(three_ways(mesh.edges()), edges);
        let faces: Vec<_> = (0..mesh.face_slots())
            .filter_map(|i| mesh.face_at(i))
            .collect();
        assert_eq!(faces.len(), mesh.n_faces());
        assert_eq!(three_ways(mesh.faces()), faces);
    }

    /// The parallel normals are the per-element ones at live slots and zero elsewhere.
    #[test]
    fn normals_of_a_mesh_with_holes() {
        let mut mesh = mesh_with_holes();
        for (i, p) in mesh.positions_mut().iter_mut().enumerate() {
            p.z = (i as f64 * 0.37).sin();
        }
        let face_normals = mesh.face_normals();
        for (i, n) in face_normals.iter().enumerate() {
            let expected = mesh
                .face_at(i)
                .map_or(glam::DVec3::ZERO, |f| mesh.face_normal(f));
            assert_eq!(*n, expected);
        }
        let normals = mesh.vertex_normals();
        for (i, n) in normals.iter().enumerate() {
            let expected = mesh.vertex_at(i).map_or(glam::DVec3::ZERO, |v| {
                mesh.adjacent_faces(v)
                    .map(|f| face_normals[mesh.face_index(f)])
                    .sum::<glam::DVec3>()
                    .normalize_or_zero()
            });
            assert_eq!(*n, expected);
            if mesh.vertex_at(i).is_some_and(|v| !mesh.is_isolated(v)) {
                assert!((n.length() - 1.0).abs() < 1e-12);
            }
        }
    }
}
