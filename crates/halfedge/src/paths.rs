//! Shortest edge paths, closed edge loops through picked vertices, and splitting the
//! faces of a mesh along a loop: the building blocks of sub-mesh frontiers (Kobbelt-style
//! sub-meshes), Lee's editing-area boundary and Bendels & Klein's region borders.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::error::{Error, Result};

use crate::handle::{HalfedgeId, VertexId};

use crate::mesh::Mesh;

#[derive(PartialEq)]
struct Entry(f64, VertexId);
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0)
    }
}

/// # Paths and loops
impl Mesh {
    /// The shortest path of edges from `from` to `to` (edge-length Dijkstra), as the
    /// halfedges walked in order. Empty when `from == to`; `None` when `to` cannot be
    /// reached. Halfedges in `forbidden` (by [`halfedge_index`](Self::halfedge_index),
    /// either direction) are not used.
    pub fn shortest_edge_path(
        &self,
        from: VertexId,
        to: VertexId,
        forbidden: Option<&[bool]>,
    ) -> Option<Vec<HalfedgeId>> {
        let mut dist = vec![f64::INFINITY; self.vertex_slots()];
        let mut via: Vec<Option<HalfedgeId>> = vec![None; self.vertex_slots()];
        let mut heap = BinaryHeap::new();
        dist[self.vertex_index(from)] = 0.0;
        heap.push(Entry(0.0, from));
        while let Some(Entry(d, v)) = heap.pop() {
            if v == to {
                break;
            }
            if d > dist[self.vertex_index(v)] {
                continue;
            }
            for h in self.outgoing_halfedges(v) {
                if forbidden.is_some_and(|f| f[self.halfedge_index(h)]) {
                    continue;
                }
                let w = self.to_vertex(h);
                let nd = d + self.edge_length(h);
                let wi = self.vertex_index(w);
                if nd < dist[wi] {
                    dist[wi] = nd;
                    via[wi] = Some(h);
                    heap.push(Entry(nd, w));
                }
            }
        }
        if !dist[self.vertex_index(to)].is_finite() {
            return None;
        }
        let mut path = Vec::new();
        let mut v = to;
        while v != from {
            let h = via[self.vertex_index(v)]?;
            path.push(h);
            v = self.from_vertex(h);
        }
        path.reverse();
        Some(path)
    }

    /// A closed loop of edges through the picked vertices in order: consecutive picks
    /// (and the last with the first) are joined by shortest edge paths. Edges already used
    /// by earlier segments are avoided, so the loop does not run back over itself.
    /// Returns the halfedges of the loop in walking order.
    pub fn closed_loop_through(&self, picks: &[VertexId]) -> Result<Vec<HalfedgeId>> {
        if picks.len() < 2 {
            return Err(Error::InvalidFrontier(format!(
                "a closed loop needs at least 2 picked vertices, got {}",
                picks.len()
            )));
        }
        for &v in picks {
            self.ensure_vertex(v)?;
        }
        let mut used = vec![false; self.halfedge_slots()];
        let mut loop_halfedges = Vec::new();
        for i in 0..picks.len() {
            let (a, b) = (picks[i], picks[(i + 1) % picks.len()]);
            let segment = self.shortest_edge_path(a, b, Some(&used)).ok_or_else(|| {
                Error::InvalidFrontier(format!(
                    "no edge path from {a} to {b} that avoids the loop so far"
                ))
            })?;
            for &h in &segment {
                used[self.halfedge_index(h)] = true;
                used[self.halfedge_index(self.opposite(h))] = true;
            }
            loop_halfedges.extend(segment);
        }
        if loop_halfedges.len() < 3 {
            return Err(Error::InvalidFrontier(
                "the loop has fewer than 3 edges".into(),
            ));
        }
        Ok(loop_halfedges)
    }

    /// Splits the faces along a set of cut edges: faces on the two sides of an edge that
    /// is not cut are in one region. Returns a region id per face slot (`u32::MAX` for
    /// removed slots) and the number of regions, numbered in the order of each region's
    /// first face. `cut` lists halfedges (either direction).
    ///
    /// One pass over the edges in slot order joins faces in a union–find forest (path
    /// halving, the smaller root kept), a second pass over the faces numbers the roots:
    /// both walk the mesh's arrays in order, where a flood fill jumps about them.
    pub fn face_regions(&self, cut: &[HalfedgeId]) -> (Vec<u32>, u32) {
        let mut is_cut = vec![false; self.halfedge_slots()];
        for &h in cut {
            is_cut[self.halfedge_index(h)] = true;
            is_cut[self.halfedge_index(self.opposite(h))] = true;
        }
        let n_faces = self.face_slots();
        let mut parent: Vec<u32> = (0..n_faces as u32).collect();
        let find = |parent: &mut [u32], mut x: u32| -> u32 {
            while parent[x as usize] != x {
                let up = parent[parent[x as usize] as usize];
                parent[x as usize] = up;
                x = up;
            }
            x
        };
        for i in (0..self.halfedge_slots()).step_by(2) {
            let Some(h) = self.halfedge_at(i) else {
                continue;
            };
            if is_cut[i] {
                continue;
            }
            let (Some(f), Some(g)) = (self.face(h), self.face(self.opposite(h))) else {
                continue;
            };
            let a = find(&mut parent, self.face_index(f) as u32);
            let b = find(&mut parent, self.face_index(g) as u32);
            if a != b {
                parent[a.max(b) as usize] = a.min(b);
            }
        }
        let mut region = vec![u32::MAX; n_faces];
        let mut count = 0u32;
        for i in 0..n_faces {
            if self.face_at(i).is_none() {
                continue;
            }
            let root = find(&mut parent, i as u32) as usize;
            // A root is the smallest face slot of its region: numbered before its faces.
            if region[root] == u32::MAX {
                region[root] = count;
                count += 1;
            }
            region[i] = region[root];
        }
        (region, count)
    }
}
