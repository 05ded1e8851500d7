//! Snapshots and comparisons of meshes: bit-for-bit positions and connectivity, the Euler
//! characteristic, enclosed volume, label crossings.

use glam::DVec3;
use halfedge::{FaceId, HalfedgeId, Mesh, VertexId};

/// Everything about a mesh's elements, handle for handle: the counts, every vertex's
/// outgoing halfedge and position (bit for bit), every halfedge's target, next, previous,
/// opposite and face, every face's halfedge. Two equal snapshots are the same mesh down to
/// the handles.
#[derive(Debug, PartialEq, Clone)]
pub struct Snapshot {
    counts: (usize, usize, usize),
    vertices: Vec<(VertexId, Option<HalfedgeId>, [u64; 3])>,
    halfedges: Vec<(
        HalfedgeId,
        VertexId,
        HalfedgeId,
        HalfedgeId,
        HalfedgeId,
        Option<FaceId>,
    )>,
    faces: Vec<(FaceId, HalfedgeId)>,
}

/// The [`Snapshot`] of `mesh` (everything `collapse` / `vertex_split` touch).
pub fn snapshot(mesh: &Mesh) -> Snapshot {
    Snapshot {
        counts: (mesh.n_vertices(), mesh.n_halfedges(), mesh.n_faces()),
        vertices: mesh
            .vertices()
            .map(|v| {
                (
                    v,
                    mesh.vertex_halfedge(v),
                    mesh.position(v).to_array().map(f64::to_bits),
                )
            })
            .collect(),
        halfedges: mesh
            .halfedges()
            .map(|h| {
                (
                    h,
                    mesh.to_vertex(h),
                    mesh.next(h),
                    mesh.prev(h),
                    mesh.opposite(h),
                    mesh.face(h),
                )
            })
            .collect(),
        faces: mesh.faces().map(|f| (f, mesh.face_halfedge(f))).collect(),
    }
}

/// `V − E + F`.
pub fn euler(mesh: &Mesh) -> i64 {
    mesh.n_vertices() as i64 - mesh.n_edges() as i64 + mesh.n_faces() as i64
}

/// Signed volume enclosed by a closed mesh.
pub fn volume(mesh: &Mesh) -> f64 {
    mesh.faces()
        .map(|f| {
            let [a, b, c] = mesh.triangle_positions(f);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

/// Largest distance between corresponding positions.
pub fn max_distance(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f64::max)
}

/// Bit-for-bit equality of position arrays.
pub fn bit_identical(a: &[DVec3], b: &[DVec3]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(p, q)| p.to_array().map(f64::to_bits) == q.to_array().map(f64::to_bits))
}

/// Edges joining two vertices of different sub-meshes (neither on the frontier), counted
/// once per halfedge, by the vertex labels of `halfedge::labels`.
///
/// # Panics
/// When the mesh has no label attribute.
pub fn crossing_edges(mesh: &Mesh) -> usize {
    let a = mesh
        .find_attribute::<VertexId, u32>(halfedge::labels::LABEL_ATTRIBUTE)
        .unwrap();
    let labels = mesh.attribute_values(a).unwrap();
    mesh.halfedges()
        .filter(|&e| {
            let l = |v| labels[mesh.vertex_index(v)];
            let (x, y) = (l(mesh.from_vertex(e)), l(mesh.to_vertex(e)));
            x != y && x != halfedge::labels::FRONTIER && y != halfedge::labels::FRONTIER
        })
        .count()
}

/// The bits of the positions of the live vertices, in [`Mesh::vertices`] order: equal
/// for two meshes whose vertices sit at the same places bit for bit.
pub fn position_bits(mesh: &Mesh) -> Vec<[u64; 3]> {
    mesh.vertices()
        .map(|v| mesh.position(v).to_array().map(f64::to_bits))
        .collect()
}

/// The bits of every position slot (removed vertices' slots too), in slot order: equal
/// for two meshes whose position arrays are the same bit for bit.
pub fn slot_position_bits(mesh: &Mesh) -> Vec<[u64; 3]> {
    mesh.positions()
        .iter()
        .map(|p| p.to_array().map(f64::to_bits))
        .collect()
}

/// Every face as the slot indices of its three vertices, in [`Mesh::faces`] order: with
/// [`position_bits`], what a file reader or writer must keep.
pub fn triangles(mesh: &Mesh) -> Vec<[usize; 3]> {
    mesh.faces()
        .map(|f| mesh.triangle(f).map(|v| mesh.vertex_index(v)))
        .collect()
}
