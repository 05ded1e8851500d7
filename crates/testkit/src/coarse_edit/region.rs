//! The region rule (see the example's module docs): the component, the tip and the
//! vertices around it by edge-path distance; and the mask helpers the edits share.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use glam::DVec3;
use halfedge::{Mesh, VertexId};

use super::Failure;

/// The region rule's result at the edited level.
pub(super) struct Region {
    /// The tip's vertex index.
    pub(super) tip: usize,
    /// How many rings from the mesh boundary the rule asked the tip to be.
    pub(super) tip_depth: u32,
    /// Vertex indices of the tip's component by increasing edge-path distance from the
    /// tip (ties by index), with the distances.
    pub(super) order: Vec<(u32, f64)>,
}

impl Region {
    /// The first `fraction` of the component (at least `min`, at most all but one
    /// vertex) as a mask over vertex slots, and the distance of its farthest vertex.
    pub(super) fn ball(
        &self,
        slots: usize,
        fraction: f64,
        min: usize,
    ) -> Result<(Vec<bool>, f64), Failure> {
        let n = self.order.len();
        let count = ((fraction * n as f64).round() as usize)
            .max(min)
            .min(n.saturating_sub(1));
        if count < min {
            return Err(Failure::new(
                format!(
                    "the tip's component has only {n} vertices at this level: too few for a region of {min}"
                ),
                "pass a finer --level, or a --seed-vertex on a larger component",
            ));
        }
        let mut mask = vec![false; slots];
        for &(i, _) in &self.order[..count] {
            mask[i as usize] = true;
        }
        Ok((mask, self.order[count - 1].1))
    }
}

/// Ring distance of every vertex slot from the mesh boundary (`u32::MAX` on closed
/// components and for removed slots).
pub(super) fn boundary_depth(mesh: &Mesh) -> Vec<u32> {
    let mut depth = vec![u32::MAX; mesh.vertex_slots()];
    let mut queue = std::collections::VecDeque::new();
    for v in mesh.vertices() {
        if mesh.is_boundary_vertex(v) && !mesh.is_isolated(v) {
            depth[mesh.vertex_index(v)] = 0;
            queue.push_back(v);
        }
    }
    while let Some(v) = queue.pop_front() {
        let next = depth[mesh.vertex_index(v)] + 1;
        for w in mesh.adjacent_vertices(v) {
            let d = &mut depth[mesh.vertex_index(w)];
            if *d == u32::MAX {
                *d = next;
                queue.push_back(w);
            }
        }
    }
    depth
}

/// How many rings from the mesh boundary a tip should be, at most (see the docs).
pub(super) const TIP_DEPTH: u32 = 3;

/// Why a twist or taper refuses a region (see the docs; the rule then tries a tip on
/// the boundary).
pub(super) const FLAT_REGION: &str = "the region is flat: it does not reach beyond its frontier along the axis towards its tip nor along its frontier's normal, so a twist or taper along it moves nothing";

/// The region rule (see the example's module docs), with tips at least `tip_depth`
/// rings from the mesh boundary where there are such vertices.
pub(super) fn choose_region(
    mesh: &Mesh,
    ancestors: &[u32],
    seed: Option<usize>,
    tip_depth: u32,
) -> Result<Region, Failure> {
    let (component, _) = mesh.connected_components();
    let tip = match seed {
        Some(s) => {
            let a = *ancestors.get(s).ok_or_else(|| {
                Failure::new(
                    format!(
                        "--seed-vertex {s} is not a vertex of the mesh ({} vertex slots)",
                        ancestors.len()
                    ),
                    "pass a vertex index below the mesh's vertex count",
                )
            })? as usize;
            match mesh.vertex_at(a) {
                Some(v) if !mesh.is_isolated(v) => a,
                _ => {
                    return Err(Failure::new(
                        format!("--seed-vertex {s} is not a vertex of any face"),
                        "pass the index of a vertex on the surface",
                    ))
                }
            }
        }
        None => {
            // the largest component (ties: the first found)
            let mut size = std::collections::HashMap::<usize, usize>::new();
            let mut first = Vec::new();
            for v in mesh.vertices().filter(|&v| !mesh.is_isolated(v)) {
                let c = component[mesh.vertex_index(v)];
                let s = size.entry(c).or_insert(0);
                if *s == 0 {
                    first.push(c);
                }
                *s += 1;
            }
            let largest = first
                .iter()
                .copied()
                .max_by(|a, b| size[a].cmp(&size[b]).then(b.cmp(a)))
                .ok_or_else(|| Failure::new("the mesh has no faces", "pass a mesh with faces"))?;
            let members: Vec<VertexId> = mesh
                .vertices()
                .filter(|&v| component[mesh.vertex_index(v)] == largest)
                .collect();
            let centroid =
                members.iter().map(|&v| mesh.position(v)).sum::<DVec3>() / members.len() as f64;
            let depth = boundary_depth(mesh);
            let mut best: Option<(u32, f64, usize)> = None;
            for &v in &members {
                let i = mesh.vertex_index(v);
                let key = (depth[i].min(tip_depth), mesh.position(v).distance(centroid));
                if best.is_none_or(|(d, r, _)| key.0 > d || (key.0 == d && key.1 > r)) {
                    best = Some((key.0, key.1, i));
                }
            }
            best.map(|b| b.2)
                .ok_or_else(|| Failure::new("the mesh has no faces", "pass a mesh with faces"))?
        }
    };
    // Dijkstra over edge lengths from the tip, ties by index
    let positions = mesh.positions();
    let mut distance = vec![f64::INFINITY; mesh.vertex_slots()];
    let mut done = vec![false; mesh.vertex_slots()];
    let mut heap = BinaryHeap::new();
    distance[tip] = 0.0;
    heap.push(Reverse((Ordered(0.0), tip as u32)));
    let mut order = Vec::new();
    while let Some(Reverse((Ordered(d), i))) = heap.pop() {
        if std::mem::replace(&mut done[i as usize], true) {
            continue;
        }
        order.push((i, d));
        let Some(v) = mesh.vertex_at(i as usize) else {
            continue;
        };
        for w in mesh.adjacent_vertices(v) {
            let j = mesh.vertex_index(w);
            let e = d + positions[i as usize].distance(positions[j]);
            if !done[j] && e < distance[j] {
                distance[j] = e;
                heap.push(Reverse((Ordered(e), j as u32)));
            }
        }
    }
    Ok(Region {
        tip,
        tip_depth,
        order,
    })
}

/// A totally ordered `f64` for the Dijkstra heap.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Ordered(f64);
impl Eq for Ordered {}
impl PartialOrd for Ordered {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Ordered {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

/// The fine mask of a coarse mask: the live input vertices whose ancestor is in it.
pub(super) fn fine_mask(input: &Mesh, ancestors: &[u32], coarse: &[bool]) -> Vec<bool> {
    let mut mask = vec![false; input.vertex_slots()];
    for v in input.vertices() {
        let i = input.vertex_index(v);
        mask[i] = coarse[ancestors[i] as usize];
    }
    mask
}

/// The live vertices of a mask.
pub(super) fn listed(mesh: &Mesh, mask: &[bool]) -> Vec<VertexId> {
    mesh.vertices()
        .filter(|&v| mask[mesh.vertex_index(v)])
        .collect()
}

/// A unit vector perpendicular to `d`, towards `w` where `w` is well away from `d`.
pub(super) fn perpendicular(d: DVec3, w: DVec3) -> DVec3 {
    let p = w - w.dot(d) * d;
    if p.length() > 0.3 * w.length() {
        p.normalize()
    } else {
        d.any_orthonormal_vector()
    }
}

/// The normalised sum of the vertex normals of the masked vertices (zero if they cancel).
pub(super) fn mean_normal(mesh: &Mesh, mask: &[bool]) -> DVec3 {
    mesh.vertices()
        .filter(|&v| mask[mesh.vertex_index(v)])
        .map(|v| mesh.vertex_normal(v))
        .sum::<DVec3>()
        .normalize_or_zero()
}
