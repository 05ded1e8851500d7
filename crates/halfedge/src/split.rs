//! Topological edge split on triangle meshes: a new vertex on an edge, each incident
//! triangle cut in two (pmp `split(Edge, Vertex)` + `triangulate`, geometry-central
//! `splitEdgeTriangular`). Used by adaptive refinement (Bendels & Klein, Sec. 6:
//! Rivara longest-edge bisection), and by anything that needs conforming local
//! refinement: every split keeps the mesh conforming, so any sequence of splits
//! passes [`Mesh::check`].

use glam::DVec3;

use crate::error::{Error, Result};

use crate::handle::{HalfedgeId, VertexId};

use crate::mesh::Mesh;

/// # Edge split
impl Mesh {
    /// Splits the edge of `h = (a → b)` at a new vertex `m` placed at `p`, and cuts each
    /// triangle on either side into two by an edge from `m` to the opposite corner.
    /// Boundary edges are split too (one triangle cut). Returns `m`.
    ///
    /// ```text
    ///            c                          c
    ///           / \                        /|\
    ///          /   \                      / | \
    ///         /  f  \                    / f|f'\
    ///        a --h-> b        ==>       a-h>m-t>b
    ///         \  g  /                    \ g|g'/
    ///          \   /                      \ | /
    ///           \ /                        \|/
    ///            d                          d
    /// ```
    ///
    /// After the split `h` runs `a → m` and keeps its face `f`; `opposite(h)` runs
    /// `m → a` and keeps `g`; the new halfedge `m → b` is `find_halfedge(m, b)`. The
    /// faces `f'` and `g'` are new. Positions of old vertices do not change; attributes
    /// of new elements take their defaults (the kernel's creation helpers grow every
    /// attribute column).
    ///
    /// # Errors
    /// Nothing is changed on error: [`Error::InvalidHandle`] if `h` is not a live
    /// halfedge of this mesh, [`Error::InvalidArgument`] for a non-finite `p`, for an edge
    /// without a face or beside a face that is not a triangle, and when the triangles on
    /// both sides have the same third vertex (`c == d`, as on a closed mesh of two
    /// faces): the two new edges would join the same two vertices.
    pub fn split_edge(&mut self, h: HalfedgeId, p: DVec3) -> Result<VertexId> {
        self.ensure_halfedge(h)?;
        if !p.is_finite() {
            return Err(Error::InvalidArgument(format!(
                "split_edge: the new vertex's position {p} is not finite"
            )));
        }
        let o = self.opposite(h);
        let b = self.to_vertex(h);
        let f = self.face(h);
        let g = self.face(o);
        if f.is_none() && g.is_none() {
            return Err(Error::InvalidArgument(format!(
                "split_edge: the edge of {h} has no face"
            )));
        }
        // Remember the links before any change.
        let h_next = self.next(h);
        let h_prev = self.prev(h);
        let o_next = self.next(o);
        let o_prev = self.prev(o);
        for (face, first) in [(f, h), (g, o)] {
            if face.is_some() {
                let n = self.next(first);
                if self.next(self.next(n)) != first {
                    return Err(Error::InvalidArgument(format!(
                        "split_edge needs triangles beside the edge of {first}"
                    )));
                }
            }
        }
        if f.is_some() && g.is_some() && self.to_vertex(h_next) == self.to_vertex(o_next) {
            return Err(Error::InvalidArgument(format!(
                "split_edge: both triangles beside the edge of {h} have the third vertex {}, \
                 the split would join it twice to the new vertex",
                self.to_vertex(h_next)
            )));
        }
        let b_was_on_o = self.vertex_halfedge(b) == Some(o);

        let m = self.add_vertex(p);
        // h: a → m, o: m → a (o keeps `to = a`), new pair t: m → b, t_o: b → m.
        self.set_to_vertex(h, m);
        let t = self.new_edge(m, b);
        let t_o = self.opposite(t);

        // Side of h.
        match f {
            Some(f) => {
                // Triangle (a, b, c): h (a→b), n = h_next (b→c), q = h_prev (c→a).
                let c = self.to_vertex(h_next);
                let x = self.new_edge(m, c); // x: m → c, x_o: c → m
                let x_o = self.opposite(x);
                let f2 = self.new_face(t);
                // (a, m, c) keeps f: h → x → q.
                self.set_next(h, x);
                self.set_next(x, h_prev);
                self.set_next(h_prev, h);
                self.set_face(x, Some(f));
                self.set_face_halfedge(f, h);
                // (m, b, c) is f2: t → n → x_o.
                self.set_next(t, h_next);
                self.set_next(h_next, x_o);
                self.set_next(x_o, t);
                for e in [t, h_next, x_o] {
                    self.set_face(e, Some(f2));
                }
            }
            None => {
                // Boundary: … → h_prev → h → h_next … becomes h → t → h_next.
                self.set_next(h, t);
                self.set_next(t, h_next);
            }
        }

        // Side of o (originally b → a, now m → a).
        match g {
            Some(g) => {
                // Triangle (b, a, d): o (b→a), on = o_next (a→d), op = o_prev (d→b).
                let d = self.to_vertex(o_next);
                let y = self.new_edge(m, d); // y: m → d, y_o: d → m
                let y_o = self.opposite(y);
                let g2 = self.new_face(t_o);
                // (m, a, d) keeps g: o → on → y_o.
                self.set_next(o, o_next);
                self.set_next(o_next, y_o);
                self.set_next(y_o, o);
                self.set_face(y_o, Some(g));
                self.set_face_halfedge(g, o);
                // (b, m, d) is g2: t_o → y → op.
                self.set_next(t_o, y);
                self.set_next(y, o_prev);
                self.set_next(o_prev, t_o);
                for e in [t_o, y, o_prev] {
                    self.set_face(e, Some(g2));
                }
            }
            None => {
                // Boundary: … → o_prev → o → o_next … becomes o_prev → t_o → o.
                self.set_next(o_prev, t_o);
                self.set_next(t_o, o);
            }
        }

        // Vertex halfedges: b may have pointed at o, which now starts at m.
        if b_was_on_o {
            self.set_vertex_halfedge(b, Some(t_o));
        }
        self.set_vertex_halfedge(m, Some(t));
        self.adjust_outgoing_halfedge(m);
        self.adjust_outgoing_halfedge(b);
        Ok(m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generators;

    fn total_area(mesh: &Mesh) -> f64 {
        mesh.surface_area()
    }

    #[test]
    fn split_interior_edge_keeps_a_valid_mesh() {
        let mut mesh = generators::icosphere(1);
        let (v, e, f) = (mesh.n_vertices(), mesh.n_edges(), mesh.n_faces());
        let h = mesh.edges().next().unwrap();
        let (a, b) = (mesh.from_vertex(h), mesh.to_vertex(h));
        let mid = 0.5 * (mesh.position(a) + mesh.position(b));
        let m = mesh.split_edge(h, mid).unwrap();
        mesh.check().unwrap();
        assert_eq!(
            (mesh.n_vertices(), mesh.n_edges(), mesh.n_faces()),
            (v + 1, e + 3, f + 2)
        );
        assert_eq!(mesh.valence(m), 4);
        assert_eq!(mesh.position(m), mid);
        assert_eq!(mesh.to_vertex(h), m);
        assert!(mesh.find_halfedge(a, b).is_none());
        assert!(mesh.find_halfedge(m, b).is_some());
        assert!(mesh.find_halfedge(a, m).is_some());
    }

    #[test]
    fn split_boundary_edge_both_directions() {
        for flip in [false, true] {
            let mut mesh = generators::grid(3, 2, 3.0, 2.0);
            let area = total_area(&mesh);
            let h = mesh
                .halfedges()
                .find(|&h| mesh.is_boundary_halfedge(h))
                .unwrap();
            let h = if flip { mesh.opposite(h) } else { h };
            let (a, b) = (mesh.from_vertex(h), mesh.to_vertex(h));
            let mid = 0.5 * (mesh.position(a) + mesh.position(b));
            let (v, e, f) = (mesh.n_vertices(), mesh.n_edges(), mesh.n_faces());
            let m = mesh.split_edge(h, mid).unwrap();
            mesh.check().unwrap();
            assert_eq!(
                (mesh.n_vertices(), mesh.n_edges(), mesh.n_faces()),
                (v + 1, e + 2, f + 1)
            );
            assert!(mesh.is_boundary_vertex(m));
            assert_eq!(mesh.valence(m), 3);
            assert!((total_area(&mesh) - area).abs() < 1e-12);
            assert_eq!(mesh.boundary_loops().len(), 1);
            assert_eq!(mesh.boundary_loops()[0].len(), 11);
        }
    }

    #[test]
    fn many_random_splits_stay_valid() {
        let mut mesh = generators::grid(4, 4, 1.0, 1.0);
        let area = total_area(&mesh);
        let mut state = 12345u64;
        for _ in 0..300 {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let k = (state >> 33) as usize % mesh.n_halfedges();
            let h = mesh.halfedges().nth(k).unwrap();
            let (a, b) = (mesh.from_vertex(h), mesh.to_vertex(h));
            let mid = 0.5 * (mesh.position(a) + mesh.position(b));
            mesh.split_edge(h, mid).unwrap();
            mesh.check().unwrap();
        }
        assert!((total_area(&mesh) - area).abs() < 1e-12);
        assert_eq!(mesh.boundary_loops().len(), 1);
        let euler = mesh.n_vertices() as i64 - mesh.n_edges() as i64 + mesh.n_faces() as i64;
        assert_eq!(euler, 1);
    }

    #[test]
    fn split_keeps_attributes_in_step() {
        let mut mesh = generators::icosphere(0);
        let label = mesh.add_vertex_attribute("label", 7u32).unwrap();
        let flabel = mesh.add_face_attribute("flabel", 3u8).unwrap();
        let h = mesh.halfedges().next().unwrap();
        let m = mesh.split_edge(h, DVec3::ZERO).unwrap();
        assert_eq!(*mesh.attribute(label, m).unwrap(), 7);
        for f in mesh.faces() {
            assert_eq!(*mesh.attribute(flabel, f).unwrap(), 3);
        }
        mesh.check().unwrap();
    }
}
