//! Validation of every connectivity invariant ([`Mesh::check`]).

use crate::{Error, Invariant, Mesh, Result};

/// # Validation
impl Mesh {
    /// Verifies every connectivity invariant of a manifold triangle mesh and returns the
    /// first broken one, naming the elements involved:
    ///
    /// - halfedges: `opposite` is an involution without fixed points, `prev(next(h)) == h`,
    ///   no link to a removed element, no loop edge, `face(next(h)) == face(h)`;
    /// - faces: triangles whose halfedge points back to them;
    /// - vertices: the vertex halfedge starts at the vertex and is a boundary halfedge when
    ///   the vertex is on the boundary; circulating around the vertex returns to the start
    ///   and sees every halfedge leaving it. A vertex may join several fans through its
    ///   boundary gaps (a "bow-tie", which OpenMesh's add-face accepts too; see
    ///   [`Mesh::is_manifold_vertex`]);
    /// - the live-element counts agree with the elements.
    ///
    /// Tests call it after every mutation. Linear time.
    pub fn check(&self) -> Result<()> {
        self.check_invariants().map_err(Error::from)
    }

    fn check_invariants(&self) -> std::result::Result<(), Invariant> {
        let live_v = self.vertices.values().filter(|s| !s.deleted).count();
        let live_h = self.halfedges.values().filter(|s| !s.deleted).count();
        let live_f = self.faces.values().filter(|s| !s.deleted).count();
        if (live_v, live_h, live_f) != (self.n_vertices, self.n_halfedges, self.n_faces) {
            return Err(Invariant::Counts(format!(
                "stored V/H/F {}/{}/{}, live {live_v}/{live_h}/{live_f}",
                self.n_vertices, self.n_halfedges, self.n_faces
            )));
        }
        let mut outgoing = vec![0usize; self.vertex_slots()];
        for h in self.halfedges() {
            let s = &self.halfedges[h];
            if !self.is_valid_halfedge(s.next)
                || !self.is_valid_halfedge(s.prev)
                || !self.is_valid_vertex(s.to)
            {
                return Err(Invariant::DeadLink(h));
            }
            if !self.is_valid_halfedge(s.opposite)
                || s.opposite == h
                || self.opposite(s.opposite) != h
            {
                return Err(Invariant::Opposite(h));
            }
            if self.prev(s.next) != h || self.next(s.prev) != h {
                return Err(Invariant::NextPrev(h));
            }
            if let Some(f) = s.face {
                if !self.is_valid_face(f) {
                    return Err(Invariant::DeadLink(h));
                }
            }
            if self.face(s.next) != s.face {
                return Err(Invariant::FaceLoop(h));
            }
            let from = self.from_vertex(h);
            if from == s.to {
                return Err(Invariant::SelfLoop(h));
            }
            outgoing[self.vertex_index(from)] += 1;
        }
        for f in self.faces() {
            let h = self.faces[f].halfedge;
            if !self.is_valid_halfedge(h) || self.face(h) != Some(f) {
                return Err(Invariant::FaceHalfedge(f));
            }
            let len = self.face_halfedges(f).take(4).count();
            if len != 3 {
                return Err(Invariant::NotTriangle { face: f, len });
            }
        }
        for v in self.vertices() {
            let expected = outgoing[self.vertex_index(v)];
            let Some(h) = self.vertex_halfedge(v) else {
                if expected != 0 {
                    return Err(Invariant::Isolated(v));
                }
                continue;
            };
            if !self.is_valid_halfedge(h) || self.from_vertex(h) != v {
                return Err(Invariant::VertexHalfedge(v));
            }
            let mut count = 0;
            let mut boundary = 0;
            let mut g = h;
            loop {
                if self.from_vertex(g) != v || count > expected {
                    return Err(Invariant::Fan(v));
                }
                count += 1;
                boundary += usize::from(self.is_boundary_halfedge(g));
                g = self.ccw_rotated(g);
                if g == h {
                    break;
                }
            }
            if count != expected {
                return Err(Invariant::Fan(v));
            }
            if boundary == 1 && !self.is_boundary_halfedge(h) {
                return Err(Invariant::BoundaryHalfedge(v));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::{generators, Invariant, Mesh};

    fn broken(f: impl FnOnce(&mut Mesh)) -> Invariant {
        let mut mesh = generators::icosphere(1);
        mesh.check().unwrap();
        f(&mut mesh);
        match mesh.check() {
            Err(crate::Error::Invariant(i)) => i,
            other => panic!("expected a broken invariant, got {other:?}"),
        }
    }

    #[test]
    fn names_the_broken_invariant() {
        let i = broken(|m| {
            let h = m.halfedges().next().unwrap();
            let n = m.next(h);
            let nn = m.next(n);
            m.halfedges[h].next = nn;
        });
        assert!(matches!(i, Invariant::NextPrev(_)), "{i}");

        let i = broken(|m| {
            let h = m.halfedges().next().unwrap();
            let o = m.opposite(h);
            let other = m.halfedges().find(|&g| g != h && g != o).unwrap();
            m.halfedges[h].opposite = other;
        });
        assert!(matches!(i, Invariant::Opposite(_)), "{i}");

        let i = broken(|m| {
            let f = m.faces().next().unwrap();
            let g = m.faces().nth(5).unwrap();
            let hg = m.face_halfedge(g);
            m.faces[f].halfedge = hg;
        });
        assert!(matches!(i, Invariant::FaceHalfedge(_)), "{i}");

        let i = broken(|m| {
            let v = m.vertices().next().unwrap();
            let h = m.halfedges().find(|&h| m.from_vertex(h) != v).unwrap();
            m.vertices[v].halfedge = Some(h);
        });
        assert!(matches!(i, Invariant::VertexHalfedge(_)), "{i}");

        let i = broken(|m| {
            m.n_faces += 1;
        });
        assert!(matches!(i, Invariant::Counts(_)), "{i}");

        let i = broken(|m| {
            let h = m.halfedges().next().unwrap();
            let f = m.face(h);
            let g = m.faces().find(|&g| Some(g) != f).unwrap();
            m.halfedges[h].face = Some(g);
        });
        assert!(
            matches!(i, Invariant::FaceLoop(_) | Invariant::FaceHalfedge(_)),
            "{i}"
        );

        let i = broken(|m| {
            let v = m.vertices().next().unwrap();
            m.vertices[v].halfedge = None;
        });
        assert!(matches!(i, Invariant::Isolated(_)), "{i}");
    }

    #[test]
    fn boundary_vertex_must_point_at_boundary_halfedge() {
        let mut mesh = generators::grid(3, 3, 1.0, 1.0);
        mesh.check().unwrap();
        let v = mesh.vertices().next().unwrap();
        let interior = mesh
            .outgoing_halfedges(v)
            .find(|&h| !mesh.is_boundary_halfedge(h))
            .unwrap();
        mesh.vertices[v].halfedge = Some(interior);
        assert!(matches!(
            mesh.check(),
            Err(crate::Error::Invariant(Invariant::BoundaryHalfedge(_)))
        ));
    }
}
