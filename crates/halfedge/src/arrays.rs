//! Plain arrays in and out: positions as `[f64; 3]` and triangles as `[u32; 3]`, the
//! shapes other libraries and file formats exchange (numpy arrays, GPU buffers, glTF).
//!
//! The numbering is the one the file writers use ([`crate::io`]): vertex `k` of the
//! arrays is the `k`-th live vertex in [`Mesh::vertices`] order
//! ([`io::file_vertex_indices`](crate::io::file_vertex_indices) gives the map), so for a
//! mesh without removed vertices (one just built or read) it is
//! [`Mesh::vertex_index`], and `from_arrays(to_arrays())` gives back the same mesh.
//!
//! ```
//! use halfedge::{generators, Mesh};
//! let mesh = generators::icosphere(2);
//! let (positions, triangles) = mesh.to_arrays();
//! assert_eq!((positions.len(), triangles.len()), (162, 320));
//! let (back, report) = Mesh::from_arrays(&positions, &triangles).unwrap();
//! assert_eq!(back.to_arrays(), (positions, triangles));
//! assert_eq!(report.duplicated_vertices, 0);
//! // A triangle naming a vertex that does not exist is a typed error.
//! assert!(matches!(
//!     Mesh::from_arrays(&[[0.0; 3]; 3], &[[0, 1, 3]]),
//!     Err(halfedge::Error::IndexOutOfRange { face: 0, index: 3, vertex_count: 3 })
//! ));
//! ```

use glam::DVec3;

use crate::build::BuildReport;

use crate::error::Result;

use crate::mesh::Mesh;

/// # Plain arrays
impl Mesh {
    /// The live vertices' positions and the faces as triangles of indices into them
    /// (numbered as the file writers number: vertex `k` is the `k`-th live vertex in [`Mesh::vertices`] order). Faces come in
    /// [`faces`](Self::faces) order, each from its [`triangle`](Self::triangle) corner;
    /// isolated vertices are kept. Indices fit `u32` because vertex slots are 32-bit.
    pub fn to_arrays(&self) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let index = crate::io::file_vertex_indices(self);
        let positions = self
            .vertices()
            .map(|v| self.position(v).to_array())
            .collect();
        let triangles = self
            .faces()
            .map(|f| self.triangle(f).map(|v| index[self.vertex_index(v)]))
            .collect();
        (positions, triangles)
    }

    /// Builds a mesh from plain arrays, with the policy of [`Mesh::from_triangles`]
    /// (faces that would make the mesh non-manifold go onto copies of their vertices,
    /// faces with a repeated index are dropped; the report counts both).
    ///
    /// # Errors
    /// [`Error::EmptyInput`](crate::Error::EmptyInput) without positions;
    /// [`Error::NonFiniteCoordinate`](crate::Error::NonFiniteCoordinate) naming the
    /// first vertex with a NaN or infinite coordinate;
    /// [`Error::IndexOutOfRange`](crate::Error::IndexOutOfRange) naming the first
    /// triangle with an index past the positions;
    /// [`Error::InvalidArgument`](crate::Error::InvalidArgument) for more elements than
    /// 32-bit slots address.
    pub fn from_arrays(
        positions: &[[f64; 3]],
        triangles: &[[u32; 3]],
    ) -> Result<(Mesh, BuildReport)> {
        let points: Vec<DVec3> = positions.iter().map(|&p| DVec3::from_array(p)).collect();
        Mesh::from_triangles(&points, triangles)
    }
}
