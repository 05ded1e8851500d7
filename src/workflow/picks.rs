//! Vertex choices of the workflow and the examples: where to put an edit on a mesh nobody
//! looked at first.

use glam::DVec3;
use halfedge::{Mesh, VertexId};

/// Where to drag a Lee editing area, in the order to try them, each with words saying
/// which it is: the largest component's vertices furthest along +z (the front), +x, −x,
/// +y, −y, −z; then [`farthest_candidate`] (on an open mesh the extreme vertices are
/// often on the boundary, where no disk-shaped area fits).
pub fn drag_candidates(mesh: &Mesh) -> Vec<(VertexId, String)> {
    let largest = mesh.select_largest_component();
    [
        (DVec3::Z, "+z"),
        (DVec3::X, "+x"),
        (DVec3::NEG_X, "-x"),
        (DVec3::Y, "+y"),
        (DVec3::NEG_Y, "-y"),
        (DVec3::NEG_Z, "-z"),
    ]
    .into_iter()
    .filter_map(|(d, name)| {
        let v = largest.extreme_vertex(mesh, d).ok()??;
        Some((v, format!("the vertex furthest along {name}")))
    })
    .collect()
}

/// The last place to try after [`drag_candidates`]: the vertex farthest from the
/// boundary (none on a closed mesh). Apart, because it needs the edge-path distances of
/// the whole mesh, which the first candidates usually spare.
pub fn farthest_candidate(mesh: &Mesh) -> Option<(VertexId, String)> {
    let v = mesh.farthest_from_boundary().ok()??;
    Some((v, "the vertex farthest from the boundary".to_string()))
}
