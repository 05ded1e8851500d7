//! The connectivity arrays that [`Mesh::from_polygons`] builds on, moved into the
//! [`Mesh`] when done.
//!
//! The mesh's own storage is flat `u32` arrays (see [`Mesh`]); building works on the
//! same layout without the per-slot generations and attribute columns, then hands the
//! arrays over whole, so every element is written once. The same
//! [add-face algorithm](crate::add_face) runs on the mesh itself (for
//! [`Mesh::add_triangle`]), so the result is exactly what adding the faces one by one
//! to a [`Mesh`] gives: halfedge `i` here is the `i`-th halfedge created there, face `f`
//! the `f`-th face.

use glam::DVec3;

use crate::add_face::Connectivity;
use crate::handle::{Slots, NONE};
use crate::mesh::HalfedgeRec;
use crate::mesh::Mesh;

/// Connectivity in plain `u32` arrays; the opposite of halfedge `h` is `h ^ 1`.
pub(crate) struct Compact {
    /// Outgoing halfedge per vertex (`NONE` for an isolated vertex).
    vertex_halfedge: Vec<u32>,
    /// For vertices added as copies: the input vertex they copy; vertex `n_input + k` is
    /// `copies[k]`.
    copies: Vec<u32>,
    n_input: usize,
    halfedges: Vec<HalfedgeRec>,
    face_halfedge: Vec<u32>,
}

impl Compact {
    /// Largest number of halfedges the `u32` slot indices can address.
    pub(crate) const MAX_HALFEDGES: usize = (u32::MAX - 1) as usize;

    /// Room for `n_vertices` input vertices and `n_faces` triangles.
    pub(crate) fn new(n_vertices: usize, n_faces: usize) -> Self {
        Self {
            vertex_halfedge: vec![NONE; n_vertices],
            copies: Vec::new(),
            n_input: n_vertices,
            // A closed triangle mesh has 3F halfedges; open ones a few more.
            halfedges: Vec::with_capacity(3 * n_faces + 6),
            face_halfedge: Vec::with_capacity(n_faces),
        }
    }

    /// Adds a copy of vertex `v` (same position), returning it.
    pub(crate) fn copy_vertex(&mut self, v: u32) -> u32 {
        let original = if (v as usize) < self.n_input {
            v
        } else {
            self.copies[v as usize - self.n_input]
        };
        self.copies.push(original);
        self.vertex_halfedge.push(NONE);
        (self.vertex_halfedge.len() - 1) as u32
    }

    /// The mesh with this connectivity: `positions` for the input vertices (they become
    /// the mesh's, not copied), copies at the positions of what they copy.
    pub(crate) fn into_mesh(self, positions: Vec<DVec3>) -> Mesh {
        let mut all = positions;
        all.reserve_exact(self.copies.len());
        for &c in &self.copies {
            all.push(all[c as usize]);
        }
        let (nv, nh, nf) = (all.len(), self.halfedges.len(), self.face_halfedge.len());
        let mut mesh = Mesh {
            vertex_conn: self.vertex_halfedge,
            vertex_slots_: Slots::live(nv),
            he: self.halfedges,
            halfedge_slots_: Slots::live(nh),
            face_conn: self.face_halfedge,
            face_slots_: Slots::live(nf),
            positions: all,
            n_vertices: nv,
            n_halfedges: nh,
            n_faces: nf,
            ..Mesh::default()
        };
        mesh.vertex_attributes.ensure_len(nv);
        mesh.halfedge_attributes.ensure_len(nh);
        mesh.face_attributes.ensure_len(nf);
        mesh
    }
}

impl Connectivity for Compact {
    type V = u32;
    type H = u32;
    type F = u32;
    #[inline]
    fn vertex_halfedge(&self, v: u32) -> Option<u32> {
        let h = self.vertex_halfedge[v as usize];
        (h != NONE).then_some(h)
    }
    #[inline]
    fn set_vertex_halfedge(&mut self, v: u32, h: u32) {
        self.vertex_halfedge[v as usize] = h;
    }
    #[inline]
    fn to_vertex(&self, h: u32) -> u32 {
        self.halfedges[h as usize].to
    }
    #[inline]
    fn next(&self, h: u32) -> u32 {
        self.halfedges[h as usize].next
    }
    #[inline]
    fn prev(&self, h: u32) -> u32 {
        self.halfedges[h as usize].prev
    }
    #[inline]
    fn opposite(&self, h: u32) -> u32 {
        h ^ 1
    }
    #[inline]
    fn is_boundary_halfedge(&self, h: u32) -> bool {
        self.halfedges[h as usize].face == NONE
    }
    #[inline]
    fn set_next(&mut self, h: u32, n: u32) {
        self.halfedges[h as usize].next = n;
        self.halfedges[n as usize].prev = h;
    }
    #[inline]
    fn set_face(&mut self, h: u32, f: u32) {
        self.halfedges[h as usize].face = f;
    }
    #[inline]
    fn new_edge(&mut self, a: u32, b: u32) -> u32 {
        let h0 = self.halfedges.len() as u32;
        let h1 = h0 + 1;
        self.halfedges.push(HalfedgeRec {
            to: b,
            next: h0,
            prev: h0,
            face: NONE,
        });
        self.halfedges.push(HalfedgeRec {
            to: a,
            next: h1,
            prev: h1,
            face: NONE,
        });
        h0
    }
    #[inline]
    fn new_face(&mut self, h: u32) -> u32 {
        self.face_halfedge.push(h);
        (self.face_halfedge.len() - 1) as u32
    }
}
