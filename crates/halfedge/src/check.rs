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
        let live_v = self.vertex_slots_.live_count();
        let live_h = self.halfedge_slots_.live_count();
        let live_f = self.face_slots_.live_count();
        if (live_v, live_h, live_f) != (self.n_vertices, self.n_halfedges, self.n_faces) {
            return Err(Invariant::Counts(format!(
                "stored V/H/F {}/{}/{}, live {live_v}/{live_h}/{live_f}",
                self.n_vertices, self.n_halfedges, self.n_faces
            )));
        }
        let (vs, hs, fs) = (
            &self.vertex_slots_,
            &self.halfedge_slots_,
            &self.face_slots_,
        );
        let mut outgoing = vec![0usize; self.vertex_slots()];
        for h in self.halfedges() {
            let i = Self::ix(h) as usize;
            let s = self.he[i];
            if !hs.is_live_index(s.next as usize)
                || !hs.is_live_index(s.prev as usize)
                || !vs.is_live_index(s.to as usize)
            {
                return Err(Invariant::DeadLink(h));
            }
            if !hs.is_live_index(i ^ 1) {
                return Err(Invariant::Opposite(h));
            }
            if self.he[s.next as usize].prev as usize != i
                || self.he[s.prev as usize].next as usize != i
            {
                return Err(Invariant::NextPrev(h));
            }
            if s.face != crate::handle::NONE && !fs.is_live_index(s.face as usize) {
                return Err(Invariant::DeadLink(h));
            }
            if self.he[s.next as usize].face != s.face {
                return Err(Invariant::FaceLoop(h));
            }
            let from = self.he[i ^ 1].to;
            if from == s.to {
                return Err(Invariant::SelfLoop(h));
            }
            outgoing[from as usize] += 1;
        }
        for f in self.faces() {
            let h = self.face_conn[Self::ix(f) as usize];
            if !hs.is_live_index(h as usize) || self.he[h as usize].face != Self::ix(f) {
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
            m.rec_mut(h).next = Mesh::ix(nn);
        });
        assert!(matches!(i, Invariant::NextPrev(_)), "{i}");

        let i = broken(|m| {
            let h = m.halfedges().next().unwrap();
            let o = m.opposite(h);
            // Opposites are neighbouring slots: remove one half of the edge.
            m.halfedge_slots_.bury(Mesh::ix(o) as usize);
            m.n_halfedges -= 1;
        });
        assert!(matches!(i, Invariant::Opposite(_)), "{i}");

        let i = broken(|m| {
            let f = m.faces().next().unwrap();
            let g = m.faces().nth(5).unwrap();
            let hg = m.face_halfedge(g);
            m.face_conn[Mesh::ix(f) as usize] = Mesh::ix(hg);
        });
        assert!(matches!(i, Invariant::FaceHalfedge(_)), "{i}");

        let i = broken(|m| {
            let v = m.vertices().next().unwrap();
            let h = m.halfedges().find(|&h| m.from_vertex(h) != v).unwrap();
            m.vertex_conn[Mesh::ix(v) as usize] = Mesh::ix(h);
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
            m.rec_mut(h).face = Mesh::ix(g);
        });
        assert!(
            matches!(i, Invariant::FaceLoop(_) | Invariant::FaceHalfedge(_)),
            "{i}"
        );

        let i = broken(|m| {
            let v = m.vertices().next().unwrap();
            m.vertex_conn[Mesh::ix(v) as usize] = crate::handle::NONE;
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
        mesh.vertex_conn[Mesh::ix(v) as usize] = Mesh::ix(interior);
        assert!(matches!(
            mesh.check(),
            Err(crate::Error::Invariant(Invariant::BoundaryHalfedge(_)))
        ));
    }
}
