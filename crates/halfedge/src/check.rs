//! Validation of every connectivity invariant ([`Mesh::check`]).

use crate::error::{Error, Invariant, Result};

use crate::mesh::Mesh;

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
    /// Tests call it after every mutation. Linear time, on all cores (a mesh that breaks
    /// an invariant is walked again in order, to name the first broken one).
    pub fn check(&self) -> Result<()> {
        // On all cores first; only a mesh that breaks an invariant is walked again in
        // order, to name the first broken one.
        if self.invariants_hold() {
            return Ok(());
        }
        self.check_invariants().map_err(Error::from)
    }

    /// True when every invariant of [`check_invariants`](Self::check_invariants) holds,
    /// tested on all cores. Instead of counting each vertex's outgoing halfedges, the walks
    /// around the vertices must add up to the live halfedges: a walk only sees halfedges
    /// leaving its vertex, so the walks are disjoint, and they cover every halfedge exactly
    /// when each vertex's walk sees all of its own.
    fn invariants_hold(&self) -> bool {
        use rayon::prelude::*;
        const NONE: u32 = crate::handle::NONE;
        let (vs, hs, fs) = (
            &self.vertex_slots_,
            &self.halfedge_slots_,
            &self.face_slots_,
        );
        if (vs.live_count(), hs.live_count(), fs.live_count())
            != (self.n_vertices, self.n_halfedges, self.n_faces)
        {
            return false;
        }
        let he = &self.he[..];
        let halfedges = (0..he.len())
            .into_par_iter()
            .with_min_len(1 << 14)
            .all(|i| {
                if !hs.is_live_index(i) {
                    return true;
                }
                let s = he[i];
                let (next, prev) = (s.next as usize, s.prev as usize);
                hs.is_live_index(next)
                    && hs.is_live_index(prev)
                    && vs.is_live_index(s.to as usize)
                    && hs.is_live_index(i ^ 1)
                    && he[next].prev as usize == i
                    && he[prev].next as usize == i
                    && (s.face == NONE || fs.is_live_index(s.face as usize))
                    && he[next].face == s.face
                    && he[i ^ 1].to != s.to
            });
        // The halfedges' links are live from here on.
        let faces = halfedges
            && (0..self.face_conn.len())
                .into_par_iter()
                .with_min_len(1 << 14)
                .all(|i| {
                    if !fs.is_live_index(i) {
                        return true;
                    }
                    let h0 = self.face_conn[i];
                    if !hs.is_live_index(h0 as usize) || he[h0 as usize].face != i as u32 {
                        return false;
                    }
                    let h1 = he[h0 as usize].next;
                    let h2 = he[h1 as usize].next;
                    h1 != h0 && h2 != h0 && he[h2 as usize].next == h0
                });
        let limit = self.n_halfedges;
        faces
            && (0..self.vertex_conn.len())
                .into_par_iter()
                .with_min_len(1 << 12)
                .map(|i| -> Option<usize> {
                    let h = self.vertex_conn[i];
                    if !vs.is_live_index(i) || h == NONE {
                        return Some(0);
                    }
                    let v = i as u32;
                    if !hs.is_live_index(h as usize) || he[(h ^ 1) as usize].to != v {
                        return None;
                    }
                    let (mut count, mut boundary, mut g) = (0usize, 0usize, h);
                    loop {
                        if he[(g ^ 1) as usize].to != v || count > limit {
                            return None;
                        }
                        count += 1;
                        boundary += usize::from(he[g as usize].face == NONE);
                        // `ccw_rotated`: the opposite of the previous halfedge.
                        g = he[g as usize].prev ^ 1;
                        if g == h {
                            break;
                        }
                    }
                    (boundary != 1 || he[h as usize].face == NONE).then_some(count)
                })
                .try_reduce(|| 0, |a, b| Some(a + b))
                == Some(self.n_halfedges)
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
            // The opposite's own links are tested when the loop reaches it; its vertex is
            // needed now.
            if !vs.is_live_index(from as usize) {
                return Err(Invariant::DeadLink(self.hh((i ^ 1) as u32)));
            }
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
    use crate::error::Invariant;
    use crate::generators;
    use crate::mesh::Mesh;

    fn broken(f: impl FnOnce(&mut Mesh)) -> Invariant {
        let mut mesh = generators::icosphere(1);
        mesh.check().unwrap();
        f(&mut mesh);
        match mesh.check() {
            Err(crate::error::Error::Invariant(i)) => i,
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

    /// Test meshes: closed, open, a bow-tie (two grids sharing a corner), tombstones of
    /// collapses and isolated vertices.
    fn valid_meshes() -> Vec<Mesh> {
        // A bow-tie and an isolated vertex.
        let (mut positions, triangles) = generators::bow_tie(3).to_arrays();
        positions.push([9.0; 3]);
        let (bow_tie, _) = Mesh::from_arrays(&positions, &triangles).unwrap();
        let mut collapsed = generators::grid(8, 6, 1.0, 1.0);
        for k in [3, 30, 61] {
            let h = collapsed
                .halfedges()
                .filter(|&h| collapsed.is_collapse_ok(h).is_ok())
                .nth(k)
                .unwrap();
            collapsed.collapse(h).unwrap();
        }
        vec![
            generators::icosphere(2),
            generators::grid(6, 4, 1.0, 1.0),
            bow_tie,
            collapsed,
        ]
    }

    /// The parallel test agrees with the walk in order on valid meshes and on every
    /// single-field corruption of their halfedges, faces and vertices that a small
    /// generator of indices reaches: it accepts exactly the meshes the walk accepts (and
    /// the walk names what is broken).
    #[test]
    fn the_parallel_test_accepts_exactly_what_the_walk_in_order_accepts() {
        /// xorshift64: deterministic indices.
        struct Indices(u64);
        impl Indices {
            fn below(&mut self, n: usize) -> usize {
                self.0 ^= self.0 << 13;
                self.0 ^= self.0 >> 7;
                self.0 ^= self.0 << 17;
                (self.0 % n as u64) as usize
            }
            /// A value that is sometimes a neighbour's, sometimes anything in range,
            /// sometimes out of range or NONE.
            fn value(&mut self, len: usize, old: u32) -> u32 {
                match self.below(4) {
                    0 => old ^ 1,
                    1 => (old as usize + 1 + self.below(3)).min(len + 2) as u32,
                    2 => crate::handle::NONE,
                    _ => self.below(len) as u32,
                }
            }
        }
        let mut rng = Indices(0x9e37_79b9_7f4a_7c15);
        let (mut broken, mut total) = (0, 0);
        for mesh in valid_meshes() {
            assert!(mesh.check_invariants().is_ok());
            assert!(mesh.invariants_hold());
            for trial in 0..600 {
                let mut m = mesh.clone();
                let (nh, nv, nf) = (m.he.len(), m.vertex_conn.len(), m.face_conn.len());
                // One field of one element, and the length of what it indexes.
                let (field, len) = match trial % 6 {
                    0 => (&mut m.he[rng.below(nh)].next, nh),
                    1 => (&mut m.he[rng.below(nh)].prev, nh),
                    2 => (&mut m.he[rng.below(nh)].to, nv),
                    3 => (&mut m.he[rng.below(nh)].face, nf),
                    4 => (&mut m.vertex_conn[rng.below(nv)], nh),
                    _ => (&mut m.face_conn[rng.below(nf)], nh),
                };
                *field = rng.value(len, *field);
                let walk = m.check_invariants();
                assert_eq!(m.invariants_hold(), walk.is_ok(), "trial {trial}: {walk:?}");
                broken += usize::from(walk.is_err());
                total += 1;
            }
        }
        // Most corruptions break something; some (a tombstone's fields, a link set to
        // what it was) do not.
        assert!(broken > total / 2 && broken < total, "{broken} of {total}");
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
            Err(crate::error::Error::Invariant(Invariant::BoundaryHalfedge(
                _
            )))
        ));
    }
}
