//! Global topology: boundary loops, connected components, valence histogram, and the
//! [`TopologyReport`] the `topology` example prints.

use std::collections::BTreeMap;

use crate::{BuildReport, HalfedgeId, Mesh, VertexId};

/// Counts that describe a mesh's topology, comparable with OpenMesh's.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TopologyReport {
    /// Live vertices, isolated ones included.
    pub vertices: usize,
    /// Live edges.
    pub edges: usize,
    /// Live faces.
    pub faces: usize,
    /// Live halfedges.
    pub halfedges: usize,
    /// Vertices on the boundary, isolated vertices included (as OpenMesh and pmp count them).
    pub boundary_vertices: usize,
    /// Closed loops of boundary halfedges.
    pub boundary_loops: usize,
    /// Connected components of the vertex-edge graph; an isolated vertex is a component.
    pub components: usize,
    /// `V − E + F`.
    pub euler: i64,
    /// Number of vertices of each valence (isolated vertices have valence 0).
    pub valence_histogram: BTreeMap<usize, usize>,
    /// Vertices where several fans meet (more than one boundary gap).
    pub non_manifold_vertices: usize,
}

/// # Topology
impl Mesh {
    /// True when at most one boundary gap meets at `v` (a single fan, closed or open).
    pub fn is_manifold_vertex(&self, v: VertexId) -> bool {
        self.outgoing_halfedges(v)
            .filter(|&h| self.is_boundary_halfedge(h))
            .count()
            <= 1
    }

    /// One boundary halfedge per boundary loop (loops of halfedges without face).
    pub fn boundary_loops(&self) -> Vec<Vec<HalfedgeId>> {
        let mut seen = vec![false; self.halfedge_slots()];
        let mut loops = Vec::new();
        for h in self.halfedges() {
            if !self.is_boundary_halfedge(h) || seen[self.halfedge_index(h)] {
                continue;
            }
            let mut boundary = Vec::new();
            let mut g = h;
            loop {
                seen[self.halfedge_index(g)] = true;
                boundary.push(g);
                g = self.next(g);
                if g == h {
                    break;
                }
            }
            loops.push(boundary);
        }
        loops
    }

    /// Connected components: a component id per vertex slot (`usize::MAX` for removed
    /// slots) and the number of components. Isolated vertices are components of their own.
    pub fn connected_components(&self) -> (Vec<usize>, usize) {
        let mut component = vec![usize::MAX; self.vertex_slots()];
        let mut count = 0;
        let mut stack = Vec::new();
        for v in self.vertices() {
            if component[self.vertex_index(v)] != usize::MAX {
                continue;
            }
            component[self.vertex_index(v)] = count;
            stack.push(v);
            while let Some(u) = stack.pop() {
                for w in self.adjacent_vertices(u) {
                    let c = &mut component[self.vertex_index(w)];
                    if *c == usize::MAX {
                        *c = count;
                        stack.push(w);
                    }
                }
            }
            count += 1;
        }
        (component, count)
    }

    /// Number of vertices of each valence.
    pub fn valence_histogram(&self) -> BTreeMap<usize, usize> {
        let mut histogram = BTreeMap::new();
        for v in self.vertices() {
            *histogram.entry(self.valence(v)).or_insert(0) += 1;
        }
        histogram
    }

    /// The topology report of this mesh.
    pub fn topology_report(&self) -> TopologyReport {
        TopologyReport {
            vertices: self.n_vertices(),
            edges: self.n_edges(),
            faces: self.n_faces(),
            halfedges: self.n_halfedges(),
            boundary_vertices: self
                .vertices()
                .filter(|&v| self.is_boundary_vertex(v))
                .count(),
            boundary_loops: self.boundary_loops().len(),
            components: self.connected_components().1,
            euler: self.n_vertices() as i64 - self.n_edges() as i64 + self.n_faces() as i64,
            valence_histogram: self.valence_histogram(),
            non_manifold_vertices: self
                .vertices()
                .filter(|&v| !self.is_manifold_vertex(v))
                .count(),
        }
    }
}

impl TopologyReport {
    /// The report as one JSON object (keys in the documented order; `duplicated_vertices`
    /// and `dropped_faces` come from the build report when there is one).
    pub fn to_json(&self, build: Option<&BuildReport>) -> String {
        let histogram: Vec<String> = self
            .valence_histogram
            .iter()
            .map(|(k, v)| format!("\"{k}\": {v}"))
            .collect();
        let build = build.copied().unwrap_or_default();
        format!(
            "{{\"vertices\": {}, \"edges\": {}, \"faces\": {}, \"halfedges\": {}, \"boundary_vertices\": {}, \
             \"boundary_loops\": {}, \"components\": {}, \"euler\": {}, \"valence_histogram\": {{{}}}, \
             \"duplicated_vertices\": {}, \"dropped_faces\": {}, \"non_manifold_vertices\": {}}}",
            self.vertices,
            self.edges,
            self.faces,
            self.halfedges,
            self.boundary_vertices,
            self.boundary_loops,
            self.components,
            self.euler,
            histogram.join(", "),
            build.duplicated_vertices,
            build.dropped_faces,
            self.non_manifold_vertices,
        )
    }
}
