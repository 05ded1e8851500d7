//! What can go wrong in a Bendels & Klein edit, on a mesh, a polyline or a picture (the
//! family's one error type), and the small enums it names.
//!
//! This module imports nothing of the crate: every other module of the family stands above
//! it.

use std::path::PathBuf;

use glam::DVec3;
use halfedge::VertexId;

/// Everything that can go wrong in a Bendels & Klein edit (*Image and 3D-object editing
/// with precisely specified editing regions*): its regions, distance fields, shape
/// function and affine blend `exp(α log A)` (Alexa 2002), on meshes, polylines and
/// pictures. Kernel errors lift in (a kernel refusal of stale data becomes
/// [`BendelsKleinError::Stale`]).
#[derive(Debug, thiserror::Error)]
pub enum BendelsKleinError {
    /// An error of the half-edge kernel (for example
    /// [`halfedge::Error::InvalidHandle`] for a vertex that is not live).
    #[error(transparent)]
    Mesh(halfedge::Error),
    /// Something derived from a mesh or a polyline (regions, a session, a distance
    /// solver) met another one, or its own at another hierarchy level or after a change
    /// of connectivity: the one staleness error (see [`halfedge::Binding`]).
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
    /// The blend would move a vertex, point or grid vertex to a position that is not
    /// finite (a translation of 1e308). Nothing was changed.
    #[error(
        "overflow: {what} would move {site} to {position} (the transform is too large for \
         the coordinates, or the position was already not finite)"
    )]
    Overflow {
        /// The edit ("the blended transform").
        what: &'static str,
        /// What would move.
        site: Site,
        /// Where it would go (a 2-D point in the plane `z = 0`).
        position: DVec3,
    },
    /// `α ⊙ A` or `log A` does not fit in f64 (Alexa 2002).
    #[error("overflow: {0}")]
    TransformOverflow(TransformOverflow),
    /// The handle, the fixed or the deformable region of an edit has no vertex, point
    /// or pixel (or a border has no edge).
    #[error("the {0} region is empty")]
    EmptyRegion(RegionKind),
    /// A vertex, point or pixel is in both the handle and the fixed region.
    #[error("{site} is in both the handle and the fixed region")]
    Overlap {
        /// Where.
        site: Site,
    },
    /// The handle touches the fixed area: a mesh vertex in both (then `handle` and
    /// `fixed` are the same vertex), or neighbours, one in each (Bendels & Klein, Sec. 2,
    /// footnote 1: the handle must lie in the complement of the fixed area, with room for
    /// the deformable region between them).
    #[error("the handle touches the fixed area: handle {handle} and fixed {fixed}")]
    HandleTouchesFixed {
        /// The handle vertex, point or pixel.
        handle: Site,
        /// The fixed one.
        fixed: Site,
    },
    /// A border given as halfedges is not a closed loop.
    #[error("the {region} border does not close: {reason}")]
    BorderNotClosed {
        /// Whose border.
        region: RegionKind,
        /// Where it breaks.
        reason: String,
    },
    /// A closed border loop does not split the mesh into two sides (e.g. it winds around
    /// a handle of a torus), or the two loops do not enclose a common area.
    #[error("the {region} border does not separate the mesh: {reason}")]
    BorderDoesNotSeparate {
        /// Whose border.
        region: RegionKind,
        /// What was found.
        reason: String,
    },
    /// The handle or the fixed area has no deformable neighbour, so it bounds nothing.
    #[error(
        "invalid regions: the {region} area has no deformable neighbour, so it bounds nothing"
    )]
    NoDeformableNeighbour {
        /// Which area.
        region: RegionKind,
    },
    /// A role per point of a polyline, but not as many roles as points.
    #[error("{roles} roles for a polyline of {points} points")]
    RoleCount {
        /// Roles given.
        roles: usize,
        /// Points of the polyline.
        points: usize,
    },
    /// The handle transform has no real matrix logarithm, so `α ⊙ A` is undefined
    /// (Alexa 2002, Sec. 3).
    #[error("the transform has no real logarithm: {0}")]
    NoRealLogarithm(NoLogReason),
    /// A 4×4 matrix that should be affine has a bottom row other than (0, 0, 0, 1).
    #[error("the matrix is not affine: bottom row {0:?}, expected [0, 0, 0, 1]")]
    NotAffine([f64; 4]),
    /// A matrix entry is NaN or infinite.
    #[error("the matrix has a non-finite entry")]
    NonFiniteMatrix,
    /// A control point of a shape curve (Bendels & Klein, Sec. 5) is malformed.
    #[error("invalid shape curve: control point {index} ({}, {}) {problem}", point.0, point.1)]
    InvalidShapeCurve {
        /// The interior control point's index.
        index: usize,
        /// The point given.
        point: (f64, f64),
        /// What is wrong with it.
        problem: ControlPointProblem,
    },
    /// A monotone shape curve was asked for through control points that decrease.
    #[error("the shape curve's control points decrease between x = {x0} and x = {x1}, but a monotone curve was asked for")]
    ShapeNotMonotone {
        /// Start of the decreasing interval.
        x0: f64,
        /// End of the decreasing interval.
        x1: f64,
    },
    /// A refinement inside a hierarchy (Sec. 6) was asked for while the hierarchy is
    /// between two levels.
    #[error("the hierarchy is between two levels")]
    BetweenLevels,
    /// A polyline without any point.
    #[error("the polyline has no point")]
    EmptyPolyline,
    /// A closed polygon (a polyline, or a region of a picture) of fewer than 3 points.
    #[error("a closed polygon needs at least 3 points, got {points}")]
    TooFewPoints {
        /// Points given.
        points: usize,
    },
    /// A point of a polyline or polygon (or a picked position) is NaN or infinite.
    #[error("point {index} is not finite")]
    NonFinitePoint {
        /// Its index (for a pick: the position of the pick in its list).
        index: usize,
    },
    /// A span of a polyline names a point the polyline does not have.
    #[error("{region} span {first}..={last} is out of range: the polyline has {len} points")]
    OutOfRange {
        /// Whose span.
        region: RegionKind,
        /// First index of the span.
        first: usize,
        /// Last index of the span.
        last: usize,
        /// Number of points.
        len: usize,
    },
    /// A span runs backwards (`first > last`) on an open polyline, where it cannot wrap
    /// around.
    #[error("{region} span {first}..={last} runs backwards, but the polyline is open")]
    SpanWrapsOpen {
        /// Whose span.
        region: RegionKind,
        /// First index of the span.
        first: usize,
        /// Last index of the span.
        last: usize,
    },
    /// A picture narrower or lower than 2 pixels: it carries no grid cell.
    #[error("the image is {width}×{height}: at least 2×2 pixels are needed")]
    TooSmall {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
    /// A picture of more than [`MAX_PIXELS`] pixels.
    #[error("an image of {width}×{height} pixels × {channels} channels is too large (at most {MAX_PIXELS} pixels)")]
    TooLarge {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
        /// Channels.
        channels: u8,
    },
    /// A channel count other than 1 (grey), 2 (grey + alpha), 3 (RGB) or 4 (RGBA).
    #[error("{0} channels: 1 (grey), 2 (grey + alpha), 3 (RGB) or 4 (RGBA) expected")]
    Channels(u8),
    /// Pixel data of the wrong length.
    #[error("the pixel data has {got} bytes, {expected} expected")]
    DataLength {
        /// Bytes given.
        got: usize,
        /// Width × height × channels.
        expected: usize,
    },
    /// A mask of another size than the picture (or than another mask).
    #[error("a mask of {got:?} pixels for an image of {expected:?}")]
    MaskSize {
        /// The mask's (width, height).
        got: (u32, u32),
        /// The picture's (width, height).
        expected: (u32, u32),
    },
    /// A grid step of 0.
    #[error("the grid step must be at least 1 pixel")]
    GridStep,
    /// An output raster of another size or channel count than the session's picture.
    #[error("the output is {got:?} (width, height, channels), the session's image {expected:?}")]
    OutputMismatch {
        /// The output's (width, height, channels).
        got: (u32, u32, u8),
        /// The picture's.
        expected: (u32, u32, u8),
    },
    /// Reading or writing a PNG failed.
    #[error("{path}: {source}")]
    Png {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        source: image::ImageError,
    },
}

/// The largest picture, in pixels (`width × height`), that rasters, masks and image
/// sessions accept: 2²⁶, e.g. 8192 × 8192 (an RGBA raster of 256 MiB). Larger sizes are
/// refused with [`BendelsKleinError::TooLarge`] before anything is allocated.
pub const MAX_PIXELS: usize = 1 << 26;

impl From<halfedge::Error> for BendelsKleinError {
    /// Lifts a kernel error; a kernel refusal of stale data becomes
    /// [`BendelsKleinError::Stale`], so that staleness has one variant whoever found it.
    fn from(error: halfedge::Error) -> Self {
        match error {
            halfedge::Error::Stale(stale) => Self::Stale(stale),
            error => Self::Mesh(error),
        }
    }
}

/// Which region of a Bendels & Klein edit (Sec. 2), in errors and reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RegionKind {
    /// The handle.
    Handle,
    /// The fixed area.
    Fixed,
    /// The deformable area.
    Deformable,
}

impl std::fmt::Display for RegionKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Handle => "handle",
            Self::Fixed => "fixed",
            Self::Deformable => "deformable",
        })
    }
}

/// Where an error of a Bendels & Klein edit happened: a vertex of a mesh, a point of a
/// polyline, a pixel or a vertex of a picture's grid mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Site {
    /// A mesh vertex.
    Vertex(VertexId),
    /// A point of a polyline, by index.
    Point(usize),
    /// A pixel (column, row).
    Pixel {
        /// Column.
        x: u32,
        /// Row.
        y: u32,
    },
    /// A vertex of a picture's grid mesh, by row-major index.
    GridVertex(usize),
}

impl std::fmt::Display for Site {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Vertex(v) => write!(f, "vertex {v}"),
            Self::Point(i) => write!(f, "point {i}"),
            Self::Pixel { x, y } => write!(f, "pixel ({x}, {y})"),
            Self::GridVertex(i) => write!(f, "grid vertex {i}"),
        }
    }
}

/// Why a transform has no real logarithm (Alexa 2002, Sec. 3; see
/// `affine_power::log`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NoLogReason {
    /// The linear part has a negative determinant: the transform contains a reflection
    /// (Alexa 2002, Sec. 3: reflections have no real logarithm).
    Reflection {
        /// The determinant of the linear part.
        det: f64,
    },
    /// The linear part is singular (it flattens space).
    Singular,
    /// The linear part has an eigenvalue on (or within rounding of) the negative real
    /// axis, e.g. a rotation by exactly π: no real principal logarithm exists.
    NegativeEigenvalue {
        /// Real part of the eigenvalue.
        re: f64,
        /// Imaginary part of the eigenvalue (zero or rounding-sized).
        im: f64,
    },
    /// The square-root iteration did not converge (a matrix too close to the cases
    /// above).
    NotConverged,
}

impl std::fmt::Display for NoLogReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Reflection { det } => write!(
                f,
                "it contains a reflection (determinant of the linear part is {det})"
            ),
            Self::Singular => write!(f, "its linear part is singular"),
            Self::NegativeEigenvalue { re, im } => write!(
                f,
                "its linear part has the eigenvalue {re}{im:+}i on the negative real axis \
                 (e.g. a rotation by exactly π)"
            ),
            Self::NotConverged => write!(f, "the square-root iteration did not converge"),
        }
    }
}

/// What does not fit in f64 when a transform is blended (Alexa 2002).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TransformOverflow {
    /// `log A` has a non-finite entry (a translation too large).
    Logarithm {
        /// The transform's translation.
        translation: DVec3,
    },
    /// The linear part is too large for the translation to be taken apart.
    LinearPart {
        /// The largest entry of `φ₁(log M)`.
        largest: f64,
    },
    /// `α ⊙ A` has a non-finite entry (a large α of a large transform).
    Power {
        /// The α asked for.
        alpha: f64,
    },
}

impl std::fmt::Display for TransformOverflow {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Logarithm { translation } => write!(
                f,
                "the logarithm of the transform does not fit in f64 (translation {translation})"
            ),
            Self::LinearPart { largest } => write!(
                f,
                "the linear part of the transform is too large for its translation to be \
                 taken apart (φ₁(log M) has an entry of {largest})"
            ),
            Self::Power { alpha } => write!(f, "{alpha} ⊙ A does not fit in f64"),
        }
    }
}

/// What is wrong with a control point of a shape curve
/// ([`BendelsKleinError::InvalidShapeCurve`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ControlPointProblem {
    /// A coordinate is NaN or infinite.
    NotFinite,
    /// The point lies outside (0, 1) × [0, 1].
    OutsideUnitSquare,
    /// Its x does not increase strictly from the previous point.
    NotIncreasing,
}

impl std::fmt::Display for ControlPointProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::NotFinite => "is not finite",
            Self::OutsideUnitSquare => "is outside (0, 1) × [0, 1]",
            Self::NotIncreasing => "does not increase strictly in x",
        })
    }
}

/// Results of this family's functions.
pub(crate) type Result<T, E = BendelsKleinError> = std::result::Result<T, E>;
