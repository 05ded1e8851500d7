//! Basic geometric queries: normals, areas, lengths, bounds.

use glam::DVec3;

use crate::handle::{FaceId, HalfedgeId, VertexId};

use crate::mesh::Mesh;

/// # Geometry
impl Mesh {
    /// The three corner positions of a triangle, in [`triangle`](Self::triangle) order.
    #[inline]
    pub fn triangle_positions(&self, f: FaceId) -> [DVec3; 3] {
        // Straight from the records: the corners are live vertices of a live face, so no
        // handle is made for them and none checked.
        self.check_face(f);
        let r0 = &self.he[self.face_conn[crate::handle::slot(f)] as usize];
        let r1 = &self.he[r0.next as usize];
        let r2 = &self.he[r1.next as usize];
        let p = &self.positions;
        [p[r0.to as usize], p[r1.to as usize], p[r2.to as usize]]
    }
    /// Unit normal of a face (zero for a degenerate face).
    #[inline]
    pub fn face_normal(&self, f: FaceId) -> DVec3 {
        let [a, b, c] = self.triangle_positions(f);
        (b - a).cross(c - a).normalize_or_zero()
    }
    /// Area of a face.
    #[inline]
    pub fn face_area(&self, f: FaceId) -> f64 {
        let [a, b, c] = self.triangle_positions(f);
        0.5 * (b - a).cross(c - a).length()
    }
    /// Centroid of a face.
    #[inline]
    pub fn face_centroid(&self, f: FaceId) -> DVec3 {
        let [a, b, c] = self.triangle_positions(f);
        (a + b + c) / 3.0
    }
    /// Length of the edge of `h`.
    #[inline]
    pub fn edge_length(&self, h: HalfedgeId) -> f64 {
        self.position(self.to_vertex(h))
            .distance(self.position(self.from_vertex(h)))
    }
    /// Vector from `from_vertex(h)` to `to_vertex(h)`.
    #[inline]
    pub fn edge_vector(&self, h: HalfedgeId) -> DVec3 {
        self.position(self.to_vertex(h)) - self.position(self.from_vertex(h))
    }
    /// Mean edge length (0 for a mesh without edges).
    pub fn mean_edge_length(&self) -> f64 {
        let n = self.n_edges();
        if n == 0 {
            return 0.0;
        }
        self.edges().map(|h| self.edge_length(h)).sum::<f64>() / n as f64
    }
    /// Unit vertex normal: the normalised sum of the unit normals of the faces around `v`
    /// (OpenMesh's default); zero for an isolated vertex.
    pub fn vertex_normal(&self, v: VertexId) -> DVec3 {
        self.adjacent_faces(v)
            .map(|f| self.face_normal(f))
            .sum::<DVec3>()
            .normalize_or_zero()
    }
    /// Unit normals of all faces, indexed by [`face_index`](Self::face_index), in parallel
    /// (zero for removed faces).
    pub fn face_normals(&self) -> Vec<DVec3> {
        let mut normals = vec![DVec3::ZERO; self.face_slots()];
        let (he, positions) = (&self.he[..], &self.positions[..]);
        self.face_slots_.par_for_each_live(&mut normals, |i, n| {
            let r0 = &he[self.face_conn[i] as usize];
            let r1 = &he[r0.next as usize];
            let r2 = &he[r1.next as usize];
            let [a, b, c] = [r0.to, r1.to, r2.to].map(|v| positions[v as usize]);
            *n = (b - a).cross(c - a).normalize_or_zero();
        });
        normals
    }
    /// Unit normals of all vertices, indexed by [`vertex_index`](Self::vertex_index), in
    /// parallel (face normals computed once; zero for removed and isolated vertices),
    /// bound to this mesh ([`VertexData`](crate::VertexData)).
    pub fn vertex_normals(&self) -> crate::vertex_data::VertexData<DVec3> {
        let face_normals = self.face_normals();
        let mut normals = vec![DVec3::ZERO; self.vertex_slots()];
        self.vertex_slots_.par_for_each_live(&mut normals, |i, n| {
            let walk = crate::iter::vertex_walk(&self.he, self.vertex_conn[i]);
            *n = walk
                .filter(|(_, r)| r.face != crate::handle::NONE)
                .map(|(_, r)| face_normals[r.face as usize])
                .sum::<DVec3>()
                .normalize_or_zero();
        });
        crate::vertex_data::VertexData::with_binding(normals, self.binding())
    }
    /// Axis-aligned bounding box `(min, max)` of the live vertices; `None` when empty.
    pub fn bounding_box(&self) -> Option<(DVec3, DVec3)> {
        let mut it = self.vertices().map(|v| self.position(v));
        let first = it.next()?;
        Some(it.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
    }
    /// Total surface area.
    pub fn surface_area(&self) -> f64 {
        self.faces().map(|f| self.face_area(f)).sum()
    }
}
