//! Compact connectivity arrays that [`Mesh::from_polygons`] builds on, and the filling
//! of the [`Mesh`] from them.
//!
//! Why: building is bound by memory. The add-face algorithm walks around vertices
//! (`next(opposite(h))`) and reads halfedges all over the mesh; on the `slotmap` storage
//! of [`Mesh`] every such read loads a 56-byte slot and checks its version, while here a
//! halfedge is 16 bytes (four per cache line, opposite halfedges side by side, as in
//! OpenMesh). The same [add-face algorithm](crate::add_face) runs on these arrays, so the
//! resulting connectivity is exactly what adding the faces one by one to the [`Mesh`]
//! gives: halfedge `i` here becomes the `i`-th halfedge created there, face `f` the
//! `f`-th face, and every link, face and vertex halfedge is copied over.
//!
//! The other half of the cost is writing the mesh's memory for the first time (page
//! faults: about 400 MB for 1.6 M faces). For large inputs a second thread does that
//! while the first runs the add-face algorithm: the first sends it [`Batch`]es of what
//! it has created, and the halfedges whose links have become final — a halfedge never
//! changes once its face has been added, since later faces only re-link boundary
//! halfedges — so that most slots are written once, with their final contents, by the
//! second thread. After both have finished, the first writes what is left: the
//! boundary halfedges and the vertices' halfedges.

use std::sync::mpsc::{Receiver, SyncSender};

use glam::DVec3;

use crate::add_face::Connectivity;
use crate::Mesh;

/// "No element" in the compact arrays.
const NONE: u32 = u32::MAX;

/// A halfedge in the compact arrays.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CompactHalfedge {
    to: u32,
    next: u32,
    prev: u32,
    face: u32,
}

/// What the add-face thread sends the element thread: the elements created since the
/// last batch, and halfedges whose contents are final.
#[derive(Default)]
pub(crate) struct Batch {
    /// Halfedges created so far, in all.
    halfedges: usize,
    /// Vertices added as copies since the last batch: the input vertex each one copies.
    copies: Vec<u32>,
    /// Faces created since the last batch: the halfedge of each.
    faces: Vec<u32>,
    /// Halfedges whose contents are final, with their index.
    finals: Vec<(u32, CompactHalfedge)>,
}

impl Batch {
    /// Faces per batch: enough to keep the channel quiet, few enough that the second
    /// thread writes the final contents while the placeholders are still in cache.
    const FACES: usize = 1024;
}

/// Connectivity in plain `u32` arrays; the opposite of halfedge `h` is `h ^ 1`.
pub(crate) struct Compact {
    /// Outgoing halfedge per vertex (`NONE` for an isolated vertex).
    vertex_halfedge: Vec<u32>,
    /// For vertices added as copies: the input vertex they copy; vertex `n_input + k` is
    /// `copies[k]`.
    copies: Vec<u32>,
    n_input: usize,
    halfedges: Vec<CompactHalfedge>,
    face_halfedge: Vec<u32>,
    /// Where batches go when a second thread fills the mesh, and the batch being made.
    sink: Option<(SyncSender<Batch>, Batch)>,
}

impl Compact {
    /// Largest number of halfedges the `u32` handles can address.
    pub(crate) const MAX_HALFEDGES: usize = (u32::MAX - 1) as usize;

    /// Room for `n_vertices` input vertices and `n_faces` triangles; batches go to
    /// `sink`, when given.
    pub(crate) fn new(n_vertices: usize, n_faces: usize, sink: Option<SyncSender<Batch>>) -> Self {
        Self {
            vertex_halfedge: vec![NONE; n_vertices],
            copies: Vec::new(),
            n_input: n_vertices,
            // A closed triangle mesh has 3F halfedges; open ones a few more.
            halfedges: Vec::with_capacity(3 * n_faces + 6),
            face_halfedge: Vec::with_capacity(n_faces),
            sink: sink.map(|s| (s, Batch::default())),
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
        if let Some((_, batch)) = &mut self.sink {
            batch.copies.push(original);
        }
        self.vertex_halfedge.push(NONE);
        (self.vertex_halfedge.len() - 1) as u32
    }

    /// Sends the batch being made (if any) and starts a new one.
    fn send(&mut self) {
        if let Some((sender, batch)) = &mut self.sink {
            batch.halfedges = self.halfedges.len();
            let full = std::mem::take(batch);
            // If the element thread is gone it has panicked; joining it reports that.
            let _ = sender.send(full);
        }
    }

    /// Sends what is left and closes the channel, so that the element thread finishes.
    pub(crate) fn finish_sending(&mut self) {
        self.send();
        self.sink = None;
    }

    /// Creates the mesh's elements and writes every halfedge and face, without a second
    /// thread: the same steps as [`create_elements`] and [`apply`] on one batch holding
    /// everything.
    pub(crate) fn create_all(&self, mesh: &mut Mesh, positions: &[DVec3]) {
        create_vertices(mesh, positions);
        apply(
            mesh,
            positions,
            &self.copies,
            self.halfedges.len(),
            &self.face_halfedge,
            self.halfedges
                .iter()
                .enumerate()
                .map(|(i, &c)| (i as u32, c)),
        );
    }

    /// Writes what the element thread has not: halfedges without face (their links were
    /// final only at the end) and every vertex's halfedge. Afterwards `mesh` has exactly
    /// this connectivity.
    pub(crate) fn finish(self, mesh: &mut Mesh) {
        debug_assert_eq!(mesh.halfedge_keys.len(), self.halfedges.len());
        debug_assert_eq!(mesh.face_keys.len(), self.face_halfedge.len());
        debug_assert_eq!(mesh.vertex_keys.len(), self.vertex_halfedge.len());
        write_finals(
            mesh,
            self.halfedges
                .iter()
                .enumerate()
                .filter(|(_, c)| c.face == NONE)
                .map(|(i, &c)| (i as u32, c)),
        );
        for (&h, &v) in self.vertex_halfedge.iter().zip(&mesh.vertex_keys) {
            if h != NONE {
                mesh.vertices[v].halfedge = Some(mesh.halfedge_keys[h as usize]);
            }
        }
    }
}

/// Creates the input vertices in a fresh mesh.
fn create_vertices(mesh: &mut Mesh, positions: &[DVec3]) {
    for &p in positions {
        mesh.add_vertex(p);
    }
}

/// The element thread: creates the input vertices, then applies batches until the
/// add-face thread closes the channel.
pub(crate) fn create_elements(mesh: &mut Mesh, positions: &[DVec3], batches: Receiver<Batch>) {
    create_vertices(mesh, positions);
    for batch in batches {
        apply(
            mesh,
            positions,
            &batch.copies,
            batch.halfedges,
            &batch.faces,
            batch.finals.into_iter(),
        );
    }
}

/// Adds the copied vertices, placeholder halfedges up to `halfedges` in all, and the
/// faces, then writes the final halfedges. Elements are created in the compact order,
/// so element `i` there is in slot `i` of the (fresh) mesh.
fn apply(
    mesh: &mut Mesh,
    positions: &[DVec3],
    copies: &[u32],
    halfedges: usize,
    faces: &[u32],
    finals: impl Iterator<Item = (u32, CompactHalfedge)>,
) {
    for &c in copies {
        mesh.add_vertex(positions[c as usize]);
    }
    let v = mesh.vertex_keys[0];
    while mesh.halfedge_keys.len() < halfedges {
        mesh.new_edge(v, v);
    }
    for &h in faces {
        let h = mesh.halfedge_keys[h as usize];
        mesh.new_face(h);
    }
    write_finals(mesh, finals);
}

/// Writes the contents of halfedges into their (existing) slots.
fn write_finals(mesh: &mut Mesh, finals: impl Iterator<Item = (u32, CompactHalfedge)>) {
    let (vertices, halfedges, faces) = (&mesh.vertex_keys, &mesh.halfedge_keys, &mesh.face_keys);
    for (i, c) in finals {
        let slot = &mut mesh.halfedges[halfedges[i as usize]];
        slot.to = vertices[c.to as usize];
        slot.next = halfedges[c.next as usize];
        slot.prev = halfedges[c.prev as usize];
        slot.face = (c.face != NONE).then(|| faces[c.face as usize]);
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
        self.halfedges.push(CompactHalfedge {
            to: b,
            next: h0,
            prev: h0,
            face: NONE,
        });
        self.halfedges.push(CompactHalfedge {
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
        if let Some((_, batch)) = &mut self.sink {
            batch.faces.push(h);
        }
        (self.face_halfedge.len() - 1) as u32
    }
    /// The halfedges of a face just added are final (see the [module docs](self)): they
    /// go into the batch, which is sent every [`Batch::FACES`] faces.
    #[inline]
    fn face_added(&mut self, f: u32) {
        let Some((_, batch)) = &mut self.sink else {
            return;
        };
        let start = self.face_halfedge[f as usize];
        let mut h = start;
        loop {
            let c = self.halfedges[h as usize];
            batch.finals.push((h, c));
            h = c.next;
            if h == start {
                break;
            }
        }
        if batch.faces.len() >= Batch::FACES {
            self.send();
        }
    }
}
