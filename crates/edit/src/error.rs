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
    /// An editing operation was asked for without an editing primitive, or with an empty one.
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
        displacement: glam::DVec3,
    },
    /// A target position of a primitive vertex is NaN or infinite.
    #[error("the target {target} of vertex {vertex} is not finite")]
    NonFiniteTarget {
        /// The vertex.
        vertex: VertexId,
        /// The target given.
        target: glam::DVec3,
    },
    /// The mesh no longer matches the editing area (its vertex or face slots changed
    /// since the area was specified), or the session is used with another mesh.
    #[error(
        "the editing area does not match this mesh: it was specified on a mesh with \
         {area_vertex_slots} vertex slots and {area_faces} faces, the mesh has \
         {mesh_vertex_slots} and {mesh_faces}"
    )]
    AreaStale {
        /// Vertex slots of the mesh the area was specified on.
        area_vertex_slots: usize,
        /// Faces of the mesh the area was specified on.
        area_faces: usize,
        /// Vertex slots of the mesh given now.
        mesh_vertex_slots: usize,
        /// Faces of the mesh given now.
        mesh_faces: usize,
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
        point: glam::DVec2,
        /// Lower corner of the domain.
        min: glam::DVec2,
        /// Upper corner of the domain.
        max: glam::DVec2,
    },
    // ---- precise regions (Bendels & Klein): modules `regions`, `distance`, `shape`, `matrix`, `blend` ----

    // ---- sub-mesh edits, Barr deformers, smoothing, FFD: modules `submesh`, `barr`, `smoothing`, `ffd` ----
}

/// Shorthand for results of the editing methods.
pub type Result<T, E = EditError> = std::result::Result<T, E>;
