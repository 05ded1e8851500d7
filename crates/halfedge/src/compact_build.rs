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
//! The other half of the cost is the first touch of the mesh's memory (page faults:
//! about 400 MB for 1.6 M faces). For large inputs a second thread creates the mesh's
//! vertices and placeholder halfedges and faces while the first one runs the add-face
//! algorithm, following the counts it publishes ([`Progress`]); the first thread then
//! fills in the links. On nefertiti subdivided twice (1.6 M faces) this makes building
//! about a third faster than on the [`Mesh`] alone.

use glam::DVec3;

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use crate::add_face::Connectivity;
use crate::Mesh;

/// "No element" in the compact arrays.
const NONE: u32 = u32::MAX;

#[derive(Clone, Copy)]
struct CompactHalfedge {
    to: u32,
    next: u32,
    prev: u32,
    face: u32,
}

/// How far the add-face algorithm has got: the numbers of halfedges and faces created so
/// far (published every [`Progress::EVERY`] faces) and whether it has finished.
#[derive(Default)]
pub(crate) struct Progress {
    halfedges: AtomicUsize,
    faces: AtomicUsize,
    done: AtomicBool,
}

impl Progress {
    /// Faces between two publications (rarely, so that the two threads do not fight over
    /// the cache line).
    const EVERY: usize = 1024;

    fn publish(&self, halfedges: usize, faces: usize) {
        self.halfedges.store(halfedges, Ordering::Release);
        self.faces.store(faces, Ordering::Release);
    }

    /// A guard that marks the work done when dropped (also when unwinding), so that
    /// [`create_elements`] never waits for ever.
    pub(crate) fn stop_on_drop(&self) -> impl Drop + '_ {
        struct Stop<'a>(&'a Progress);
        impl Drop for Stop<'_> {
            fn drop(&mut self) {
                self.0.done.store(true, Ordering::Release);
            }
        }
        Stop(self)
    }

    /// Publishes the final counts.
    pub(crate) fn finish(&self, compact: &Compact<'_>) {
        self.publish(compact.halfedges.len(), compact.face_halfedge.len());
        self.done.store(true, Ordering::Release);
    }
}

/// Creates the input vertices of `mesh` and then, following `progress`, as many
/// placeholder halfedges (in pairs) and faces as the add-face algorithm has created, until
/// it has finished. [`Compact::fill`] sets their contents afterwards.
pub(crate) fn create_elements(mesh: &mut Mesh, positions: &[DVec3], progress: &Progress) {
    for &p in positions {
        mesh.add_vertex(p);
    }
    let v = mesh.vertex_keys[0];
    loop {
        let done = progress.done.load(Ordering::Acquire);
        let halfedges = progress.halfedges.load(Ordering::Acquire);
        let faces = progress.faces.load(Ordering::Acquire);
        let idle = mesh.halfedge_keys.len() == halfedges && mesh.face_keys.len() == faces;
        while mesh.halfedge_keys.len() < halfedges {
            mesh.new_edge(v, v);
        }
        while mesh.face_keys.len() < faces {
            let h = mesh.halfedge_keys[0];
            mesh.new_face(h);
        }
        if done {
            return;
        }
        if idle {
            std::thread::yield_now();
        }
    }
}

/// Connectivity in plain `u32` arrays; the opposite of halfedge `h` is `h ^ 1`.
pub(crate) struct Compact<'p> {
    progress: Option<&'p Progress>,
    /// Outgoing halfedge per vertex (`NONE` for an isolated vertex).
    vertex_halfedge: Vec<u32>,
    /// For vertices added as copies: the vertex they copy (by input index); vertex
    /// `n_input + k` is `copies[k]`.
    copies: Vec<u32>,
    n_input: usize,
    halfedges: Vec<CompactHalfedge>,
    face_halfedge: Vec<u32>,
}

impl<'p> Compact<'p> {
    /// Largest number of halfedges the `u32` handles can address.
    pub(crate) const MAX_HALFEDGES: usize = (u32::MAX - 1) as usize;

    /// Room for `n_vertices` input vertices and `n_faces` triangles.
    /// Counts are published to `progress`, when given.
    pub(crate) fn new(n_vertices: usize, n_faces: usize, progress: Option<&'p Progress>) -> Self {
        Self {
            progress,
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

    /// Fills `mesh` with this connectivity. The mesh holds the input vertices and
    /// placeholder halfedges and faces, as many as here, made by [`create_elements`] on a
    /// fresh mesh (so element `i` here is in slot `i` there).
    pub(crate) fn fill(self, mesh: &mut Mesh, positions: &[DVec3]) {
        debug_assert_eq!(mesh.vertex_keys.len(), positions.len());
        debug_assert_eq!(mesh.halfedge_keys.len(), self.halfedges.len());
        debug_assert_eq!(mesh.face_keys.len(), self.face_halfedge.len());
        for &c in &self.copies {
            mesh.add_vertex(positions[c as usize]);
        }
        let (vertices, halfedges, faces) =
            (&mesh.vertex_keys, &mesh.halfedge_keys, &mesh.face_keys);
        for (c, &h) in self.halfedges.iter().zip(halfedges) {
            let slot = &mut mesh.halfedges[h];
            slot.to = vertices[c.to as usize];
            slot.next = halfedges[c.next as usize];
            slot.prev = halfedges[c.prev as usize];
            slot.face = (c.face != NONE).then(|| faces[c.face as usize]);
        }
        for (&h, &f) in self.face_halfedge.iter().zip(faces) {
            mesh.faces[f].halfedge = halfedges[h as usize];
        }
        for (&h, &v) in self.vertex_halfedge.iter().zip(vertices) {
            if h != NONE {
                mesh.vertices[v].halfedge = Some(halfedges[h as usize]);
            }
        }
    }
}

impl Connectivity for Compact<'_> {
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
        let n = self.face_halfedge.len();
        if n % Progress::EVERY == 0 {
            if let Some(progress) = self.progress {
                progress.publish(self.halfedges.len(), n);
            }
        }
        (n - 1) as u32
    }
}
