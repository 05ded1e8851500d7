//! The error type of the editing methods.

use halfedge::{FaceId, VertexId};

/// Everything that can go wrong in an editing method. Kernel errors lift in unchanged.
#[derive(Debug, thiserror::Error)]
pub enum EditError {
    /// An error of the half-edge kernel.
    #[error(transparent)]
    Mesh(#[from] halfedge::Error),
    /// A vertex handle that is not a live vertex of the mesh.
    #[error("vertex {0} is not a live vertex of the mesh")]
    InvalidVertex(VertexId),
    /// A face handle that is not a live face of the mesh.
    #[error("face {0} is not a live face of the mesh")]
    InvalidFace(FaceId),
    /// A parameter outside its documented range, or NaN.
    #[error("invalid parameter {name}: {reason}")]
    InvalidParameter {
        /// The parameter.
        name: &'static str,
        /// What is wrong with it.
        reason: String,
    },
    /// The sparse linear solver failed (the matrix is not positive definite).
    #[error("linear solve failed: {0}")]
    Solver(String),
    // ---- area editing (Lee 1999): module `area`, `mba` ----

    // ---- precise regions (Bendels & Klein): modules `regions`, `distance`, `shape`, `matrix`, `blend` ----

    // ---- sub-mesh edits, Barr deformers, smoothing, FFD: modules `submesh`, `barr`, `smoothing`, `ffd` ----
}

/// Shorthand for results of the editing methods.
pub type Result<T, E = EditError> = std::result::Result<T, E>;
