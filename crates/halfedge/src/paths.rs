//! Shortest edge paths, closed edge loops through picked vertices, and splitting the
//! faces of a mesh along a loop: the building blocks of sub-mesh frontiers (Kobbelt-style
//! sub-meshes), Lee's editing-area boundary and Bendels & Klein's region borders.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::error::{Error, Result};

use crate::handle::{HalfedgeId, VertexId};
use crate::vertex_data::VertexData;

use crate::mesh::Mesh;

/// A heap entry: a vertex slot at a tentative distance, ordered nearest first and, at the
/// same distance, lowest slot first, so that the walk settles vertices in one order
/// whatever the heap does with ties.
#[derive(PartialEq)]
struct Entry(f64, u32);
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

/// What [`Mesh::walk_edges`] gives back: the distance of every vertex slot (`∞` where
/// not reached), and where asked for, the halfedge each vertex was reached by and the
/// order the vertices were settled in.
struct EdgeWalk {
    distance: Vec<f64>,
    via: Option<Vec<Option<HalfedgeId>>>,
    order: Option<Vec<(VertexId, f64)>>,
}

/// The one edge-length Dijkstra of the kernel (shortest paths, distance fields, balls):
/// where it stops and what it records.
#[derive(Clone, Copy, Default)]
struct WalkOptions<'a> {
    /// Vertices beyond this distance are not reached (`∞`: no bound).
    max_distance: f64,
    /// Stop once this vertex is settled.
    target: Option<VertexId>,
    /// Halfedges not to walk along, by halfedge index (either direction must be given).
    forbidden: Option<&'a [bool]>,
    /// Record the halfedge each vertex was reached by.
    via: bool,
    /// Record the order the vertices are settled in.
    order: bool,
}

impl Mesh {
    /// Edge-length Dijkstra from `seeds` (see [`WalkOptions`]); the seeds are live vertices.
    fn walk_edges(&self, seeds: &[VertexId], options: WalkOptions<'_>) -> EdgeWalk {
        let n = self.vertex_slots();
        let mut distance = vec![f64::INFINITY; n];
        let mut settled = vec![false; n];
        let mut via = options.via.then(|| vec![None; n]);
        let mut order = options.order.then(Vec::new);
        let mut heap = BinaryHeap::new();
        for &v in seeds {
            let i = self.vertex_index(v);
            distance[i] = 0.0;
            heap.push(Entry(0.0, i as u32));
        }
        while let Some(Entry(d, i)) = heap.pop() {
            let i = i as usize;
            if d > distance[i] || std::mem::replace(&mut settled[i], true) {
                continue;
            }
            let v = self.vh(i as u32);
            if let Some(order) = &mut order {
                order.push((v, d));
            }
            if options.target == Some(v) {
                break;
            }
            for h in self.outgoing_halfedges(v) {
                if options.forbidden.is_some_and(|f| f[self.halfedge_index(h)]) {
                    continue;
                }
                let wi = self.vertex_index(self.to_vertex(h));
                let nd = d + self.edge_length(h);
                if nd <= options.max_distance && nd < distance[wi] {
                    distance[wi] = nd;
                    if let Some(via) = &mut via {
                        via[wi] = Some(h);
                    }
                    heap.push(Entry(nd, wi as u32));
                }
            }
        }
        EdgeWalk {
            distance,
            via,
            order,
        }
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
        let walk = self.walk_edges(
            &[from],
            WalkOptions {
                max_distance: f64::INFINITY,
                target: Some(to),
                forbidden,
                via: true,
                order: false,
            },
        );
        if !walk.distance[self.vertex_index(to)].is_finite() {
            return None;
        }
        let via = walk.via?;
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

    /// Edge-path distances from `seeds` (edge-length Dijkstra), by
    /// [`vertex_index`](Self::vertex_index): `∞` for vertices farther than
    /// `max_distance` or not reachable. The walk stops at `max_distance`, so a small
    /// radius costs little on a large mesh. An edge path is never shorter than the
    /// surface distance; on a regular triangulation it is up to about 15 % longer (the
    /// fast-marching distance of the `edit` crate's geodesic ball is the surface
    /// distance).
    ///
    /// # Errors
    /// [`Error::InvalidHandle`] for a seed that is not a live vertex;
    /// [`Error::InvalidArgument`] for a negative or NaN `max_distance`.
    pub fn edge_distances(&self, seeds: &[VertexId], max_distance: f64) -> Result<VertexData<f64>> {
        self.check_walk(seeds, max_distance, "edge_distances")?;
        let walk = self.walk_edges(
            seeds,
            WalkOptions {
                max_distance,
                ..WalkOptions::default()
            },
        );
        Ok(VertexData::with_binding(walk.distance, self.binding()))
    }

    /// The vertices within edge-path distance `max_distance` of `seeds`, in the order of
    /// their distance (ties by [`vertex_index`](Self::vertex_index)), each with its
    /// distance: the nearest `k` vertices of a seed are the first `k`.
    ///
    /// # Errors
    /// As [`edge_distances`](Self::edge_distances).
    pub fn edge_distance_order(
        &self,
        seeds: &[VertexId],
        max_distance: f64,
    ) -> Result<Vec<(VertexId, f64)>> {
        self.check_walk(seeds, max_distance, "edge_distance_order")?;
        let walk = self.walk_edges(
            seeds,
            WalkOptions {
                max_distance,
                order: true,
                ..WalkOptions::default()
            },
        );
        Ok(walk.order.unwrap_or_default())
    }

    fn check_walk(&self, seeds: &[VertexId], max_distance: f64, what: &str) -> Result<()> {
        if max_distance.is_nan() || max_distance < 0.0 {
            return Err(Error::InvalidArgument(format!(
                "{what} needs a maximum distance ≥ 0, got {max_distance}"
            )));
        }
        for &v in seeds {
            self.ensure_vertex(v)?;
        }
        Ok(())
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
