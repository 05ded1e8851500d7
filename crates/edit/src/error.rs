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
    /// A region of a Bendels & Klein edit has no vertex (or a border has no edge).
    #[error("the {0} region is empty")]
    EmptyRegion(crate::regions::RegionKind),
    /// The handle touches the fixed area: a vertex in both, or an edge joining them
    /// (Bendels & Klein, Sec. 2: the handle must lie in the complement of the fixed area).
    #[error("the handle touches the fixed area: handle vertex {handle} and fixed vertex {fixed}")]
    HandleTouchesFixed {
        /// The handle vertex.
        handle: VertexId,
        /// The fixed vertex (equal to `handle` when one vertex was put in both sets).
        fixed: VertexId,
    },
    /// A border given as halfedges is not a closed loop.
    #[error("the {region} border does not close: {reason}")]
    BorderNotClosed {
        /// Whose border.
        region: crate::regions::RegionKind,
        /// Where it breaks.
        reason: String,
    },
    /// A closed border loop does not split the mesh into two sides (e.g. it winds around
    /// a handle of a torus), or the two loops do not enclose a common area.
    #[error("the {region} border does not separate the mesh: {reason}")]
    BorderDoesNotSeparate {
        /// Whose border.
        region: crate::regions::RegionKind,
        /// What was found.
        reason: String,
    },
    /// A vertex set names a vertex twice in conflicting roles, or a role array has the
    /// wrong length.
    #[error("invalid region specification: {0}")]
    InvalidRegions(String),
    /// The handle transform has no real matrix logarithm, so `α ⊙ A` is undefined
    /// (Alexa 2002, Sec. 3).
    #[error("the transform has no real logarithm: {0}")]
    NoRealLogarithm(crate::matrix::NoLogReason),
    /// A 4×4 matrix that should be affine has a bottom row other than (0, 0, 0, 1).
    #[error("the matrix is not affine: bottom row {0:?}, expected [0, 0, 0, 1]")]
    NotAffine([f64; 4]),
    /// A matrix entry is NaN or infinite.
    #[error("the matrix has a non-finite entry")]
    NonFiniteMatrix,
    /// Control points of a shape curve are malformed (outside the unit square, not
    /// strictly increasing in x, not finite).
    #[error("invalid shape curve: {0}")]
    InvalidShapeCurve(String),
    /// A monotone shape curve was asked for through control points that decrease.
    #[error("the shape curve's control points decrease between x = {x0} and x = {x1}, but a monotone curve was asked for")]
    ShapeNotMonotone {
        /// Start of the decreasing interval.
        x0: f64,
        /// End of the decreasing interval.
        x1: f64,
    },
    /// The mesh handed to an editing session is not the one it was set up on (or was
    /// changed behind its back).
    #[error("the mesh does not match the editing session: {0}")]
    SessionMismatch(String),
    // ---- sub-mesh edits, Barr deformers, smoothing, FFD: modules `submesh`, `barr`, `smoothing`, `ffd` ----
}

/// Shorthand for results of the editing methods.
pub type Result<T, E = EditError> = std::result::Result<T, E>;
