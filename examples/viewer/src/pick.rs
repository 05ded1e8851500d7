//! Picking by ray casting: the library's bounding volume hierarchy
//! ([`halfedge::bvh`]), which the viewer keeps current for the document's mesh
//! ([`Bvh::update`] refits after a move and rebuilds after a topology change). A picked
//! vertex is the corner of the hit triangle nearest to the hit point.

pub use halfedge::bvh::{ray_triangle, Bvh, Hit};
