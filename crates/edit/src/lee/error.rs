//! What can go wrong in Lee 1999 area editing (the family's one error type).
//!
//! This module imports nothing of the crate: every other module of the family stands above
//! it.

use glam::{DVec2, DVec3};
use halfedge::{FaceId, VertexId};

/// Everything that can go wrong in Lee 1999 area editing (*Interactive multiresolution
/// editing of arbitrary meshes*): the editing area, its harmonic embedding, the local
/// frames, the multilevel B-spline fit and the session. Kernel errors lift in (a kernel
/// refusal of stale data becomes [`LeeError::Stale`]).
#[derive(Debug, thiserror::Error)]
pub enum LeeError {
    /// An error of the half-edge kernel (for example
    /// [`halfedge::Error::InvalidHandle`] for a vertex or face that is not live).
    #[error(transparent)]
    Mesh(halfedge::Error),
    /// Something derived from a mesh (an editing area, a session) met another mesh, or
    /// its mesh at another hierarchy level or after a change of connectivity: the one
    /// staleness error (see [`halfedge::Binding`]).
    #[error(transparent)]
    Stale(#[from] halfedge::Stale),
    /// A parameter outside its documented range, or NaN.
    #[error("invalid parameter {name}: {reason}")]
    InvalidParameter {
        /// The parameter.
        name: &'static str,
        /// What is wrong with it.
        reason: String,
    },
    /// An edit would move a vertex to a position that is not finite: the displacements
    /// are too large for the coordinates, or a position the edit reads is already NaN or
    /// infinite. Nothing was changed.
    #[error(
        "overflow: {what} would move vertex v{vertex} to {position} (the parameters are too \
         large for the coordinates, or the vertex or a neighbour already had a non-finite \
         position)"
    )]
    Overflow {
        /// The edit ("the drag").
        what: &'static str,
        /// The vertex's [`Mesh::vertex_index`](halfedge::Mesh::vertex_index).
        vertex: usize,
        /// The position it would get.
        position: DVec3,
    },
    /// A multilevel B-spline fit reaches values that do not fit in f64 (Lee, Wolberg &
    /// Shin 1997: the data values are too large or too far apart).
    #[error(
        "overflow: the fit reaches {value}: the values are too large (or too far apart) for f64"
    )]
    FitOverflow {
        /// A non-finite value of the fitted function.
        value: DVec3,
    },
    /// The sparse linear solve of the harmonic embedding failed (Lee 1999, §4).
    #[error("linear solve failed: {failure}")]
    Solver {
        /// What failed.
        failure: SolveFailure,
    },
    /// The editing area has no face (Lee 1999, §3.2).
    #[error("the editing area is empty: it has no face")]
    AreaEmpty,
    /// The editing area contains an edge of the mesh boundary: it must lie inside the
    /// surface so that its own boundary is a closed loop of mesh edges (Lee 1999, §3.2).
    #[error("the editing area touches the mesh boundary at vertex {vertex}")]
    AreaTouchesMeshBoundary {
        /// A vertex of a mesh-boundary edge inside the area.
        vertex: VertexId,
    },
    /// The editing area is not a topological disk (Lee 1999, §3.2): a disk has one
    /// boundary loop, one component and Euler characteristic 1. Several loops mean holes
    /// (an annulus), a lower Euler characteristic means a handle.
    #[error(
        "the editing area is not a topological disk: {boundary_loops} boundary loop(s), \
         {components} component(s), Euler characteristic {euler} (a disk has 1, 1 and 1)"
    )]
    AreaNotDisk {
        /// Number of boundary loops of the area.
        boundary_loops: usize,
        /// Number of edge-connected components of its faces.
        components: usize,
        /// V − E + F of the area.
        euler: i64,
    },
    /// The area's boundary passes twice through one vertex (two parts of the area meet
    /// only at that vertex), so the area is not a disk.
    #[error("the editing area's boundary passes more than once through vertex {vertex}")]
    AreaPinched {
        /// The vertex where the area pinches.
        vertex: VertexId,
    },
    /// The loop through the picked vertices does not cut the mesh in two (for example a
    /// loop around a handle): there is no inside to fill.
    #[error("the loop through the picked vertices does not separate the mesh into two sides")]
    LoopDoesNotSeparate,
    /// The seed naming the side of the area lies on the boundary loop itself.
    #[error("seed vertex {0} lies on the boundary loop; pick a vertex inside the area")]
    SeedOnLoop(VertexId),
    /// The seed naming the side of the area is on neither side of the loop (another
    /// component of the mesh).
    #[error("the seed is on neither side of the boundary loop")]
    SeedNotBesideLoop,
    /// A face added to grow the area shares no edge with it.
    #[error("face {face} shares no edge with the editing area")]
    FaceNotAdjacent {
        /// The face.
        face: FaceId,
    },
    /// A vertex given as a rectangle corner is not on the area's boundary loop.
    #[error("corner vertex {vertex} is not on the editing area's boundary")]
    CornerNotOnBoundary {
        /// The vertex.
        vertex: VertexId,
    },
    /// The four corner vertices are not distinct.
    #[error("corner vertex {vertex} is given twice; the four corners must be distinct")]
    RepeatedCorner {
        /// The repeated vertex.
        vertex: VertexId,
    },
    /// An editing operation was asked for without an editing primitive, or with an empty
    /// one (Lee 1999, §3.3).
    #[error("the editing primitive is empty")]
    EmptyPrimitive,
    /// A vertex of the editing primitive is not in the editing area.
    #[error("primitive vertex {vertex} is not in the editing area")]
    PrimitiveOutsideArea {
        /// The vertex.
        vertex: VertexId,
    },
    /// A vertex of the editing primitive is on the area's boundary, which stays fixed for
    /// every scale (Lee 1999, §5.3).
    #[error("primitive vertex {vertex} is on the editing area's boundary, which never moves")]
    PrimitiveOnAreaBoundary {
        /// The vertex.
        vertex: VertexId,
    },
    /// A vertex moved one by one is not in the current editing primitive.
    #[error("vertex {vertex} is not in the editing primitive")]
    NotInPrimitive {
        /// The vertex.
        vertex: VertexId,
    },
    /// A drag displacement is NaN or infinite.
    #[error("the displacement {displacement} is not finite")]
    NonFiniteDisplacement {
        /// The displacement given.
        displacement: DVec3,
    },
    /// A target position of a primitive vertex is NaN or infinite.
    #[error("the target {target} of vertex {vertex} is not finite")]
    NonFiniteTarget {
        /// The vertex.
        vertex: VertexId,
        /// The target given.
        target: DVec3,
    },
    /// Positions given per local vertex of an editing area (to compute local frames) are
    /// not one per vertex of the area.
    #[error("{found} positions for an editing area of {expected} vertices")]
    AreaPositionCount {
        /// The area's number of vertices.
        expected: usize,
        /// The number of positions given.
        found: usize,
    },
    /// Multilevel B-spline input: the numbers of points and values differ.
    #[error("MBA input has {points} points but {values} values")]
    MbaLengthMismatch {
        /// Number of points.
        points: usize,
        /// Number of values.
        values: usize,
    },
    /// Multilevel B-spline input: a point or value is NaN or infinite.
    #[error("MBA data point {index} has a non-finite coordinate or value")]
    MbaNonFiniteData {
        /// Index of the data point.
        index: usize,
    },
    /// Multilevel B-spline input: a point lies outside the rectangle of the lattices.
    #[error("MBA data point {index} at {point} lies outside the domain {min}..{max}")]
    MbaPointOutsideDomain {
        /// Index of the data point.
        index: usize,
        /// The point.
        point: DVec2,
        /// Lower corner of the domain.
        min: DVec2,
        /// Upper corner of the domain.
        max: DVec2,
    },
}

impl From<halfedge::Error> for LeeError {
    /// Lifts a kernel error; a kernel refusal of stale data becomes [`LeeError::Stale`],
    /// so that staleness has one variant whoever found it.
    fn from(error: halfedge::Error) -> Self {
        match error {
            halfedge::Error::Stale(stale) => Self::Stale(stale),
            error => Self::Mesh(error),
        }
    }
}

/// How the sparse solve of the harmonic embedding failed ([`LeeError::Solver`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SolveFailure {
    /// The sparse LU factorisation found no pivot at this step: the system is singular.
    NoPivot {
        /// The elimination step.
        step: usize,
    },
    /// The sparse LU factorisation could not allocate or index its storage.
    Resources,
    /// The solution at this interior vertex (local index) is not finite: the system is
    /// singular.
    NonFinite {
        /// The interior vertex's local index.
        vertex: usize,
    },
}

impl std::fmt::Display for SolveFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::NoPivot { step } => write!(
                f,
                "the sparse LU of the embedding found no pivot at step {step} (singular system)"
            ),
            Self::Resources => write!(
                f,
                "the sparse LU of the embedding could not allocate or index its storage"
            ),
            Self::NonFinite { vertex } => write!(
                f,
                "the embedding of interior vertex {vertex} is not finite (singular system)"
            ),
        }
    }
}

/// Results of this family's functions.
pub(crate) type Result<T, E = LeeError> = std::result::Result<T, E>;
