//! The vertex regions the editing tests pick on Spot, the bunny and their stand-ins
//! ([`crate::stand_in`]).

use glam::DVec3;
use halfedge::{Mesh, VertexId};

/// The snout tip: the vertex with the largest z (Spot and the creature look along +z;
/// on Spot it is vertex 1855).
pub fn nose(mesh: &Mesh) -> VertexId {
    mesh.extreme_vertex(DVec3::Z).unwrap().unwrap()
}

/// Vertex `i` of the file.
///
/// # Panics
/// When there is no live vertex `i`.
pub fn vertex(mesh: &Mesh, i: usize) -> VertexId {
    mesh.vertex_at(i).unwrap()
}

/// The connected component (through vertices with `mask` set) containing slot `seed`, as
/// a mask.
pub fn component(mesh: &Mesh, mask: &[bool], seed: usize) -> Vec<bool> {
    let mut out = vec![false; mesh.vertex_slots()];
    let mut stack = vec![mesh.vertex_at(seed).unwrap()];
    out[seed] = true;
    while let Some(v) = stack.pop() {
        for w in mesh.adjacent_vertices(v) {
            let j = mesh.vertex_index(w);
            if mask[j] && !out[j] {
                out[j] = true;
                stack.push(w);
            }
        }
    }
    out
}

/// Slot of the vertex with the largest `key`, among vertices with faces.
pub fn argmax(mesh: &Mesh, key: impl Fn(DVec3) -> f64) -> usize {
    mesh.vertices()
        .filter(|&v| !mesh.is_isolated(v))
        .map(|v| mesh.vertex_index(v))
        .max_by(|&a, &b| key(mesh.positions()[a]).total_cmp(&key(mesh.positions()[b])))
        .unwrap()
}

/// The bunny's ear (as the paper's Fig. 5 sub-mesh): the vertices above the cutting plane
/// `y = 0.16` connected to the highest vertex (the ear tip).
pub fn bunny_ear(mesh: &Mesh) -> Vec<bool> {
    let above: Vec<bool> = mesh.positions().iter().map(|p| p.y > 0.16).collect();
    component(mesh, &above, argmax(mesh, |p| p.y))
}

/// The bunny's head: the vertices with `x < −0.04` and `y > 0.09` connected to the
/// highest of them.
pub fn bunny_head(mesh: &Mesh) -> Vec<bool> {
    let region: Vec<bool> = mesh
        .positions()
        .iter()
        .map(|p| p.x < -0.04 && p.y > 0.09)
        .collect();
    let seed = argmax(mesh, |p| {
        if p.x < -0.04 && p.y > 0.09 {
            p.y
        } else {
            f64::NEG_INFINITY
        }
    });
    component(mesh, &region, seed)
}
