//! Building a mesh from indexed polygons, with OpenMesh's importer policy so that the
//! topology matches OpenMesh's on every file.
//!
//! - Faces are added in input order by the classic add-face algorithm (OpenMesh
//!   `PolyConnectivity::add_face`, pmp `SurfaceMesh::add_face`), which refuses a
//!   *complex vertex* (a face vertex not on the boundary), a *complex edge* (a face edge
//!   whose halfedge already has a face) and a failed patch re-linking.
//! - A polygon is fan-triangulated from its first vertex and its triangles added in order
//!   (OpenMesh `TriConnectivity::add_face`).
//! - A face with fewer than three vertices or a repeated vertex index is dropped.
//! - When a face cannot be added (for a polygon: when its last fan triangle fails), it is
//!   added again on fresh copies of its vertices (same positions); the copies are counted.
//! - Out-of-range indices, non-finite coordinates and empty input are errors, checked
//!   before anything is built. Unreferenced vertices stay as isolated vertices, and vertex
//!   `i` of the input is the vertex with [`Mesh::vertex_index`] `i`.

use glam::DVec3;

use crate::{Error, FaceId, HalfedgeId, Mesh, Result, VertexId};

/// What [`Mesh::from_polygons`] had to do to turn the input into a manifold triangle mesh.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BuildReport {
    /// Input polygons.
    pub input_faces: usize,
    /// Vertices added as copies for faces that would have made an edge or a vertex
    /// non-manifold (OpenMesh's importer does the same).
    pub duplicated_vertices: usize,
    /// Faces added on duplicated vertices.
    pub duplicated_faces: usize,
    /// Input faces dropped: fewer than three vertices or a repeated vertex index.
    pub dropped_faces: usize,
    /// Fan triangles of polygons that could not be added although the polygon's last
    /// triangle could, so the polygon was not re-added on copies (OpenMesh loses them
    /// silently; we count them).
    pub dropped_triangles: usize,
    /// Vertices no face refers to (kept as isolated vertices).
    pub unreferenced_vertices: usize,
}

/// Why the add-face algorithm refused a face.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AddFaceError {
    /// A vertex of the face is already surrounded by faces.
    ComplexVertex(VertexId),
    /// An edge of the face already has a face on this side.
    ComplexEdge(VertexId, VertexId),
    /// The fans around a vertex could not be re-linked to make room for the face.
    PatchRelinkingFailed(VertexId),
}

impl std::fmt::Display for AddFaceError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::ComplexVertex(v) => write!(f, "complex vertex {v}"),
            Self::ComplexEdge(a, b) => write!(f, "complex edge {a}-{b}"),
            Self::PatchRelinkingFailed(v) => write!(f, "patch re-linking failed at {v}"),
        }
    }
}
impl std::error::Error for AddFaceError {}

/// Scratch space of the add-face algorithm, reused between faces.
#[derive(Default)]
struct AddFaceScratch {
    halfedges: Vec<Option<HalfedgeId>>,
    is_new: Vec<bool>,
    needs_adjust: Vec<bool>,
    next_cache: Vec<(HalfedgeId, HalfedgeId)>,
    hs: Vec<HalfedgeId>,
    vertex_halfedges: Vec<Option<HalfedgeId>>,
    is_boundary: Vec<bool>,
}

/// # Building
impl Mesh {
    /// Builds a mesh from positions and indexed polygons (0-based indices), with the
    /// policy of the [module docs](crate::build). Returns the mesh and a report of what was
    /// duplicated and dropped.
    ///
    /// ```
    /// use glam::DVec3;
    /// let p = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE];
    /// let (mesh, report) = halfedge::Mesh::from_polygons(&p, [[0u32, 1, 3, 2]]).unwrap();
    /// assert_eq!((mesh.n_faces(), report.dropped_faces), (2, 0));
    /// ```
    pub fn from_polygons<I, F>(positions: &[DVec3], polygons: I) -> Result<(Mesh, BuildReport)>
    where
        I: IntoIterator<Item = F>,
        I::IntoIter: Clone,
        F: AsRef<[u32]>,
    {
        if positions.is_empty() {
            return Err(Error::EmptyInput);
        }
        for (i, p) in positions.iter().enumerate() {
            if let Some(&value) = p.to_array().iter().find(|c| !c.is_finite()) {
                return Err(Error::NonFiniteCoordinate { vertex: i, value });
            }
        }
        let polygons = polygons.into_iter();
        let n = positions.len();
        let mut n_faces = 0;
        let mut referenced = vec![false; n];
        for (face, poly) in polygons.clone().enumerate() {
            n_faces += poly.as_ref().len().saturating_sub(2);
            for &i in poly.as_ref() {
                if i as usize >= n {
                    return Err(Error::IndexOutOfRange {
                        face,
                        index: u64::from(i),
                        vertex_count: n,
                    });
                }
                referenced[i as usize] = true;
            }
        }

        let mut mesh = Mesh::with_capacity(n, n_faces);
        let mut vertices: Vec<VertexId> = positions.iter().map(|&p| mesh.add_vertex(p)).collect();
        let mut report = BuildReport {
            unreferenced_vertices: referenced.iter().filter(|&&r| !r).count(),
            ..BuildReport::default()
        };
        let mut scratch = AddFaceScratch::default();
        let mut face_vertices: Vec<VertexId> = Vec::new();
        for poly in polygons {
            let poly = poly.as_ref();
            report.input_faces += 1;
            if poly.len() < 3 || has_repeated_index(poly) {
                report.dropped_faces += 1;
                continue;
            }
            face_vertices.clear();
            face_vertices.extend(poly.iter().map(|&i| vertices[i as usize]));
            let (last_ok, failed) = mesh.add_polygon(&face_vertices, &mut scratch);
            if last_ok {
                report.dropped_triangles += failed;
                continue;
            }
            // The face would make the mesh non-manifold: add it (all its fan triangles)
            // again on fresh vertices, as OpenMesh's importer does.
            for v in face_vertices.iter_mut() {
                let p = mesh.position(*v);
                *v = mesh.add_vertex(p);
            }
            report.duplicated_vertices += face_vertices.len();
            report.duplicated_faces += 1;
            let (ok, _) = mesh.add_polygon(&face_vertices, &mut scratch);
            debug_assert!(ok, "a face on fresh vertices always fits");
        }
        vertices.clear();
        Ok((mesh, report))
    }

    /// Builds a mesh from triangles; see [`from_polygons`](Self::from_polygons).
    pub fn from_triangles(
        positions: &[DVec3],
        triangles: &[[u32; 3]],
    ) -> Result<(Mesh, BuildReport)> {
        Self::from_polygons(positions, triangles.iter())
    }

    /// Adds a triangle on existing vertices by the add-face algorithm; on error nothing
    /// is changed.
    pub fn add_triangle(
        &mut self,
        a: VertexId,
        b: VertexId,
        c: VertexId,
    ) -> Result<FaceId, AddFaceError> {
        for v in [a, b, c] {
            assert!(self.is_valid_vertex(v), "stale vertex handle {v}");
        }
        self.add_face(&[a, b, c], &mut AddFaceScratch::default())
    }

    /// Fan-triangulates a polygon and adds its triangles; returns whether the last one
    /// was added and how many failed.
    fn add_polygon(&mut self, vs: &[VertexId], scratch: &mut AddFaceScratch) -> (bool, usize) {
        let mut failed = 0;
        let mut last_ok = false;
        for i in 1..vs.len() - 1 {
            last_ok = self.add_face(&[vs[0], vs[i], vs[i + 1]], scratch).is_ok();
            if !last_ok {
                failed += 1;
            }
        }
        (last_ok, failed)
    }

    /// The add-face algorithm of OpenMesh's `PolyConnectivity::add_face`, step for step
    /// (so that non-manifold input is resolved exactly as OpenMesh resolves it). Next
    /// links are collected first and written at the end, so a refused face changes nothing.
    fn add_face(
        &mut self,
        vs: &[VertexId],
        s: &mut AddFaceScratch,
    ) -> Result<FaceId, AddFaceError> {
        let n = vs.len();
        s.halfedges.clear();
        s.is_new.clear();
        s.needs_adjust.clear();
        s.next_cache.clear();
        // The vertex halfedges are loaded first, all of them, so that their cache misses
        // overlap (building is bound by memory latency); the checks then run in
        // OpenMesh's order and return the same error.
        s.vertex_halfedges.clear();
        s.vertex_halfedges
            .extend(vs.iter().map(|&v| self.vertex_halfedge(v)));
        s.is_boundary.clear();
        s.is_boundary.extend(
            s.vertex_halfedges
                .iter()
                .map(|h| h.is_none_or(|h| self.is_boundary_halfedge(h))),
        );
        for i in 0..n {
            let ii = (i + 1) % n;
            if !s.is_boundary[i] {
                return Err(AddFaceError::ComplexVertex(vs[i]));
            }
            let h = s.vertex_halfedges[i].and_then(|start| self.find_halfedge_from(start, vs[ii]));
            if let Some(h) = h {
                if !self.is_boundary_halfedge(h) {
                    return Err(AddFaceError::ComplexEdge(vs[i], vs[ii]));
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
                if self.next(inner_prev) != inner_next {
                    // Search a free gap between boundary_prev and boundary_next.
                    let outer_prev = self.opposite(inner_next);
                    let mut boundary_prev = outer_prev;
                    loop {
                        boundary_prev = self.opposite(self.next(boundary_prev));
                        if self.is_boundary_halfedge(boundary_prev) {
                            break;
                        }
                    }
                    let boundary_next = self.next(boundary_prev);
                    if boundary_prev == inner_prev {
                        return Err(AddFaceError::PatchRelinkingFailed(vs[ii]));
                    }
                    let patch_start = self.next(inner_prev);
                    let patch_end = self.prev(inner_next);
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
                None => self.new_edge(vs[i], vs[(i + 1) % n]),
            };
            s.hs.push(h);
        }
        let hs = &s.hs;

        let f = self.new_face(hs[n - 1]);
        for i in 0..n {
            let ii = (i + 1) % n;
            let vh = vs[ii];
            let inner_prev = hs[i];
            let inner_next = hs[ii];
            let id = usize::from(s.is_new[i]) | (usize::from(s.is_new[ii]) << 1);
            if id != 0 {
                let outer_prev = self.opposite(inner_next);
                let outer_next = self.opposite(inner_prev);
                match id {
                    1 => {
                        // prev is new, next is old
                        let boundary_prev = self.prev(inner_next);
                        s.next_cache.push((boundary_prev, outer_next));
                        self.set_vertex_halfedge(vh, Some(outer_next));
                    }
                    2 => {
                        // next is new, prev is old
                        let boundary_next = self.next(inner_prev);
                        s.next_cache.push((outer_prev, boundary_next));
                        self.set_vertex_halfedge(vh, Some(boundary_next));
                    }
                    _ => {
                        // both are new
                        match self.vertex_halfedge(vh) {
                            None => {
                                self.set_vertex_halfedge(vh, Some(outer_next));
                                s.next_cache.push((outer_prev, outer_next));
                            }
                            Some(boundary_next) => {
                                let boundary_prev = self.prev(boundary_next);
                                s.next_cache.push((boundary_prev, outer_next));
                                s.next_cache.push((outer_prev, boundary_next));
                            }
                        }
                    }
                }
                s.next_cache.push((inner_prev, inner_next));
            } else {
                s.needs_adjust[ii] = self.vertex_halfedge(vh) == Some(inner_next);
            }
            self.set_face(inner_prev, Some(f));
        }
        for &(a, b) in &s.next_cache {
            self.set_next(a, b);
        }
        for (&v, &adjust) in vs.iter().zip(&s.needs_adjust) {
            if adjust {
                self.adjust_outgoing_halfedge(v);
            }
        }
        Ok(f)
    }

    /// `find_halfedge` circulating clockwise from `start` (an outgoing halfedge of the
    /// vertex) like OpenMesh (the order matters only for speed: there is at most one
    /// halfedge `a → b`).
    #[inline]
    fn find_halfedge_from(&self, start: HalfedgeId, b: VertexId) -> Option<HalfedgeId> {
        let mut h = start;
        loop {
            if self.to_vertex(h) == b {
                return Some(h);
            }
            h = self.cw_rotated(h);
            if h == start {
                return None;
            }
        }
    }
}

fn has_repeated_index(poly: &[u32]) -> bool {
    if poly.len() <= 8 {
        (1..poly.len()).any(|i| poly[..i].contains(&poly[i]))
    } else {
        let mut sorted = poly.to_vec();
        sorted.sort_unstable();
        sorted.windows(2).any(|w| w[0] == w[1])
    }
}
