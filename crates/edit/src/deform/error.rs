//! What can go wrong in a sub-mesh edit or a deformer (the family's one error type), and
//! the small enum it names.
//!
//! This module imports nothing of the crate: every other module of the family stands above
//! it.

use glam::DVec3;
use halfedge::VertexId;

/// Everything that can go wrong in the deformers: sub-mesh edits with propagation levels
/// (*Interactive editing of multiresolution meshes*), Barr's taper, twist and bend, Taubin
/// smoothing, and Feng, Ma & Peng's shape/height-surface FFD. Kernel errors lift in (a
/// kernel refusal of stale data becomes [`DeformError::Stale`]).
#[derive(Debug, thiserror::Error)]
pub enum DeformError {
    /// An error of the half-edge kernel (for example
    /// [`halfedge::Error::InvalidHandle`] for a vertex that is not live).
    #[error(transparent)]
    Mesh(halfedge::Error),
    /// Something derived from a mesh (a vertex mask, a sub-mesh, a smoother, a snapshot,
    /// an FFD attachment) met another mesh, or its mesh at another hierarchy level or
    /// after a change of connectivity: the one staleness error (see
    /// [`halfedge::Binding`]).
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
    /// A deformation would move a vertex to a position that is not finite: the parameters
    /// are too large for the mesh's coordinates, or a position the edit reads is already
    /// NaN or infinite. Nothing was changed.
    #[error(
        "overflow: {what} would move vertex v{vertex} to {position} (the parameters are too \
         large for the coordinates, or the vertex or a neighbour already had a non-finite \
         position)"
    )]
    Overflow {
        /// The edit ("the deformation", "the sub-mesh edit", "Taubin smoothing").
        what: &'static str,
        /// The vertex's [`Mesh::vertex_index`](halfedge::Mesh::vertex_index).
        vertex: usize,
        /// The position it would get.
        position: DVec3,
    },
    /// An FFD operation would move a control point of its surfaces to a position that is
    /// not finite. Nothing was changed.
    #[error("overflow: {what} would move a control point to {position}")]
    ControlPointOverflow {
        /// The operation ("the translation", "the bend").
        what: &'static str,
        /// The position it would get.
        position: DVec3,
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
        value: DVec3,
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
    /// A B-spline surface of an FFD (Feng, Ma & Peng §2) that cannot be built or used as
    /// asked.
    #[error("invalid {surface} surface: {problem}")]
    InvalidSurface {
        /// Which surface: "shape", "height", or "B-spline" for one not yet in an FFD.
        surface: &'static str,
        /// What is wrong with it.
        problem: SurfaceProblem,
    },
    /// No selected vertex could be attached to the shape surface: all project outside it.
    #[error("no vertex projects onto the shape surface")]
    NothingAttached,
}

impl From<halfedge::Error> for DeformError {
    /// Lifts a kernel error; a kernel refusal of stale data becomes
    /// [`DeformError::Stale`], so that staleness has one variant whoever found it.
    fn from(error: halfedge::Error) -> Self {
        match error {
            halfedge::Error::Stale(stale) => Self::Stale(stale),
            error => Self::Mesh(error),
        }
    }
}

/// What is wrong with a B-spline surface ([`DeformError::InvalidSurface`]); directions are
/// `'u'` and `'v'`, grid sizes and degrees `[u, v]`.
///
/// Paper: Feng, Ma & Peng 1996, *A new free-form deformation through the control of
/// parametric surfaces*, §2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SurfaceProblem {
    /// A degree outside `1 ..= max`.
    Degree {
        /// The direction.
        direction: char,
        /// The degree given.
        degree: usize,
        /// The largest degree.
        max: usize,
    },
    /// No more control points than the degree in a direction.
    TooFewControlPoints {
        /// The direction.
        direction: char,
        /// Control points in that direction.
        count: usize,
        /// The degree in that direction.
        degree: usize,
    },
    /// More control points than the limit.
    TooManyControlPoints {
        /// The grid.
        count: [usize; 2],
        /// The limit.
        max: usize,
    },
    /// More polynomial coefficients in power form than the limit.
    TooManyCoefficients {
        /// The grid.
        count: [usize; 2],
        /// The degrees.
        degree: [usize; 2],
        /// The limit.
        max: usize,
    },
    /// A number of control points other than the grid's.
    ControlPointCount {
        /// Control points given.
        given: usize,
        /// The grid.
        count: [usize; 2],
    },
    /// A planar surface needs at least 2 × 2 control points.
    GridTooSmall {
        /// The grid.
        count: [usize; 2],
    },
    /// A control point that is NaN or infinite.
    NonFiniteControlPoint {
        /// Its grid position `(i, j)`.
        index: [usize; 2],
        /// Its value.
        point: DVec3,
    },
}

impl std::fmt::Display for SurfaceProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Self::Degree {
                direction,
                degree,
                max,
            } => write!(
                f,
                "degree {degree} in direction {direction} (needs 1..={max})"
            ),
            Self::TooFewControlPoints {
                direction,
                count,
                degree,
            } => write!(
                f,
                "{count} control points in direction {direction} for degree {degree} (needs \
                 more than the degree)"
            ),
            Self::TooManyControlPoints { count, max } => write!(
                f,
                "a {}×{} control grid has more than {max} control points",
                count[0], count[1]
            ),
            Self::TooManyCoefficients { count, degree, max } => write!(
                f,
                "a {}×{} control grid of degrees {}×{} has more than {max} polynomial \
                 coefficients",
                count[0], count[1], degree[0], degree[1]
            ),
            Self::ControlPointCount { given, count } => write!(
                f,
                "{given} control points given for a {}×{} grid",
                count[0], count[1]
            ),
            Self::GridTooSmall { count } => {
                write!(f, "a {}×{} control grid is too small", count[0], count[1])
            }
            Self::NonFiniteControlPoint { index, point } => write!(
                f,
                "control point ({}, {}) is {point}, not finite",
                index[0], index[1]
            ),
        }
    }
}

/// Results of this family's functions.
pub(crate) type Result<T, E = DeformError> = std::result::Result<T, E>;
