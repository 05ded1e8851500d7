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
    /// A result would not be finite: the parameters are too large for the mesh's
    /// coordinates (an overflow), or a position the edit reads is already NaN or
    /// infinite. Nothing was changed.
    #[error("overflow: {0}")]
    Overflow(String),
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
    /// Something derived from a mesh (an editing area, a session, a sub-mesh, an FFD
    /// attachment) met another mesh, or its mesh at another hierarchy level or after a
    /// change of connectivity: the one staleness error (see [`halfedge::Binding`]).
    #[error(transparent)]
    Stale(#[from] halfedge::Stale),
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
    /// A region of a Bendels & Klein edit has no vertex (or a border has no edge).
    #[error("the {0} region is empty")]
    EmptyRegion(crate::bendels_klein::RegionKind),
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
        region: crate::bendels_klein::RegionKind,
        /// Where it breaks.
        reason: String,
    },
    /// A closed border loop does not split the mesh into two sides (e.g. it winds around
    /// a handle of a torus), or the two loops do not enclose a common area.
    #[error("the {region} border does not separate the mesh: {reason}")]
    BorderDoesNotSeparate {
        /// Whose border.
        region: crate::bendels_klein::RegionKind,
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
    NoRealLogarithm(crate::bendels_klein::affine_power::NoLogReason),
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
    /// No selected vertex could be attached to the shape surface: all project outside it.
    #[error("no vertex projects onto the shape surface")]
    NothingAttached,
}

/// Shorthand for results of the editing methods.
pub type Result<T, E = EditError> = std::result::Result<T, E>;
