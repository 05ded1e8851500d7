//! Vertex choices shared by the examples (included with `#[path]`): where to put an edit
//! on a mesh nobody looked at first.

use glam::DVec3;
use halfedge::{Mesh, VertexId};

/// Where to drag a Lee editing area, in the order to try them, each with words saying
/// which it is: the largest component's vertices furthest along +z (the front), +x, −x,
/// +y, −y, −z, then the vertex farthest from the boundary (on an open mesh the extreme
/// vertices are often on the boundary, where no disk-shaped area fits).
pub fn drag_candidates(mesh: &Mesh) -> Vec<(VertexId, String)> {
    let largest = mesh.select_largest_component();
    let mut centres: Vec<(VertexId, String)> = Vec::new();
    for (d, name) in [
        (DVec3::Z, "+z"),
        (DVec3::X, "+x"),
        (DVec3::NEG_X, "-x"),
        (DVec3::Y, "+y"),
        (DVec3::NEG_Y, "-y"),
        (DVec3::NEG_Z, "-z"),
    ] {
        if let Ok(Some(v)) = largest.extreme_vertex(mesh, d) {
            centres.push((v, format!("the vertex furthest along {name}")));
        }
    }
    if let Ok(Some(v)) = mesh.farthest_from_boundary() {
        centres.push((v, "the vertex farthest from the boundary".into()));
    }
    centres
}
