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
    /// A per-vertex array (a selection mask, sub-mesh labels, or the vertex slots a
    /// sub-mesh, smoother or snapshot was built for) whose length is not the mesh's
    /// [`vertex_slots`](halfedge::Mesh::vertex_slots): the data belongs to another mesh.
    #[error("per-vertex array has {found} entries, the mesh has {expected} vertex slots")]
    VertexArrayLength {
        /// The mesh's vertex slot count.
        expected: usize,
        /// The array's length.
        found: usize,
    },
    /// A sub-mesh (or vertex selection) without any live vertex.
    #[error("the sub-mesh has no vertex")]
    EmptySubMesh,
    /// The sub-mesh covers whole connected components: no inside vertex has an outside
    /// neighbour, so there is no frontier to fit a plane to or to count levels from.
    #[error("the sub-mesh has no frontier (it covers whole connected components)")]
    NoFrontier,
    /// No plane can be fitted to the frontier: fewer than three frontier vertices, or all
    /// of them (nearly) on a line.
    #[error("cannot fit a plane to the sub-mesh frontier ({vertices} frontier vertices, nearly collinear or too few)")]
    DegenerateFrontier {
        /// Number of frontier vertices.
        vertices: usize,
    },
    /// A direction (axis, normal) of zero length or with non-finite components.
    #[error("direction {name} is zero or not finite: {value}")]
    DegenerateDirection {
        /// Which direction.
        name: &'static str,
        /// The value given.
        value: halfedge::DVec3,
    },
    /// The vertex normal at a picked vertex is zero (isolated vertex or degenerate faces).
    #[error("vertex {0} has no normal (isolated or degenerate faces)")]
    NoVertexNormal(VertexId),
    /// A global taper whose linear factor profile reaches zero or below on the object.
    #[error("taper factor {factor} at axial coordinate {at} is not positive")]
    NonPositiveTaper {
        /// The factor reached.
        factor: f64,
        /// Where along the axis.
        at: f64,
    },
    /// A B-spline surface that cannot be built as asked.
    #[error("invalid B-spline surface: {0}")]
    InvalidSurface(String),
    /// An FFD attachment used with a mesh of another size than the one it was attached to.
    #[error("FFD attached to a mesh with {expected} vertex slots, used with one of {found}")]
    AttachmentMismatch {
        /// Vertex slots at attach time.
        expected: usize,
        /// Vertex slots now.
        found: usize,
    },
    /// No selected vertex could be attached to the shape surface: all project outside it.
    #[error("no vertex projects onto the shape surface")]
    NothingAttached,
}

/// Shorthand for results of the editing methods.
pub type Result<T, E = EditError> = std::result::Result<T, E>;
