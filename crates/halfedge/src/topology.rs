//! Global topology: boundary loops, connected components, valence histogram, and the
//! [`TopologyReport`] the `topology` example prints.

use std::collections::BTreeMap;

use crate::handle::NONE;
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

    /// `boundary_loops().len()`, with a bit per halfedge slot instead of the loops.
    fn count_boundary_loops(&self) -> usize {
        let mut seen = BitSet::new(self.halfedge_slots());
        let mut loops = 0;
        for start in self.halfedge_slots_.live_indices() {
            if self.he[start as usize].face != NONE || seen.contains(start) {
                continue;
            }
            let mut h = start;
            loop {
                seen.insert(h);
                h = self.he[h as usize].next;
                if h == start {
                    break;
                }
            }
            loops += 1;
        }
        loops
    }

    /// `connected_components().1`, with a bit per vertex slot instead of the labels and
    /// a breadth-first queue (a front, not a whole component).
    fn count_components(&self) -> usize {
        let mut seen = BitSet::new(self.vertex_slots());
        let mut queue = std::collections::VecDeque::new();
        let mut count = 0;
        for v in self.vertex_slots_.live_indices() {
            if seen.contains(v) {
                continue;
            }
            seen.insert(v);
            queue.push_back(v);
            while let Some(u) = queue.pop_front() {
                for (_, r) in crate::iter::vertex_walk(&self.he, self.vertex_conn[u as usize]) {
                    if !seen.contains(r.to) {
                        seen.insert(r.to);
                        queue.push_back(r.to);
                    }
                }
            }
            count += 1;
        }
        count
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
            boundary_loops: self.count_boundary_loops(),
            components: self.count_components(),
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

/// A set of slot indices below a bound, a bit each.
struct BitSet(Vec<u64>);

impl BitSet {
    fn new(n: usize) -> Self {
        Self(vec![0; n.div_ceil(64)])
    }
    fn contains(&self, i: u32) -> bool {
        self.0[i as usize / 64] >> (i % 64) & 1 != 0
    }
    fn insert(&mut self, i: u32) {
        self.0[i as usize / 64] |= 1 << (i % 64);
    }
}

#[cfg(test)]
mod tests {
    use crate::{generators, DVec3, Mesh};

    /// The report's counts (bit sets, breadth-first) are those of `boundary_loops` and
    /// `connected_components`, on meshes with several loops and components, tombstones
    /// and isolated vertices.
    #[test]
    fn report_counts_match_the_full_queries() {
        let grid = generators::grid(6, 5, 1.0, 1.0);
        let mut holes = generators::grid(12, 9, 1.0, 1.0);
        // Collapses leave tombstones among the slots.
        for k in [5, 40, 77] {
            let h = holes
                .halfedges()
                .filter(|&h| holes.is_collapse_ok(h).is_ok())
                .nth(k)
                .unwrap();
            holes.collapse(h).unwrap();
        }
        // Two grids side by side (two boundary loops, two components) and two isolated vertices.
        let (a, b) = (
            generators::grid(3, 3, 1.0, 1.0),
            generators::grid(4, 2, 1.0, 1.0),
        );
        let mut positions: Vec<DVec3> = a.positions().to_vec();
        positions.extend(b.positions().iter().map(|p| *p + DVec3::X * 10.0));
        positions.extend([DVec3::Z, DVec3::ONE]);
        let offset = a.vertex_slots() as u32;
        let mut triangles: Vec<[u32; 3]> = a
            .faces()
            .map(|f| a.triangle(f).map(|v| a.vertex_index(v) as u32))
            .collect();
        triangles.extend(
            b.faces()
                .map(|f| b.triangle(f).map(|v| b.vertex_index(v) as u32 + offset)),
        );
        let (two, _) = Mesh::from_triangles(&positions, &triangles).unwrap();
        for (mesh, loops, components) in [
            (grid, 1, 1),
            (generators::icosphere(2), 0, 1),
            (holes, 1, 1),
            (two, 2, 4),
        ] {
            let report = mesh.topology_report();
            assert_eq!(report.boundary_loops, mesh.boundary_loops().len());
            assert_eq!(report.components, mesh.connected_components().1);
            assert_eq!(
                (report.boundary_loops, report.components),
                (loops, components)
            );
        }
    }
}
