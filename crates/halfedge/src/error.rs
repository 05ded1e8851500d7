//! The kernel's error type.

use std::path::PathBuf;

use crate::handle::{FaceId, HalfedgeId, VertexId};

/// Everything that can go wrong in the kernel. Variants carry the offending handles,
/// indices or file so that the message says what is wrong and where.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The input has no vertices at all (in-memory input such as
    /// [`Mesh::from_polygons`](crate::Mesh::from_polygons); the file readers report an
    /// empty file or one without vertices as [`Error::Format`], naming the file).
    #[error("empty input: no vertices")]
    EmptyInput,
    /// A face refers to a vertex index that does not exist.
    #[error(
        "face {face} refers to vertex index {index}, but there are only {vertex_count} vertices"
    )]
    IndexOutOfRange {
        /// Index of the face in the input (file order).
        face: usize,
        /// The offending vertex index (0-based).
        index: u64,
        /// Number of vertices in the input.
        vertex_count: usize,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate ({value})")]
    NonFiniteCoordinate {
        /// Index of the vertex in the input.
        vertex: usize,
        /// The offending value.
        value: f64,
    },
    /// A handle does not name a live element of this mesh.
    #[error("stale or foreign handle: {0}")]
    InvalidHandle(String),
    /// A connectivity invariant is broken (returned by [`Mesh::check`](crate::Mesh::check)).
    #[error("invariant broken: {0}")]
    Invariant(#[from] Invariant),
    /// An edge collapse was refused; nothing was changed.
    #[error("collapse of {halfedge} refused: {reason}")]
    CollapseRefused {
        /// The halfedge whose collapse was asked for.
        halfedge: HalfedgeId,
        /// Why it was refused.
        reason: crate::collapse::CollapseVeto,
    },
    /// A vertex split was refused because the mesh around the record has changed.
    #[error("vertex split refused: {0}")]
    SplitRefused(String),
    /// An attribute with this name already exists.
    #[error("an attribute named {0:?} already exists")]
    DuplicateAttribute(String),
    /// A mesh file could not be opened, read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A mesh file is malformed or truncated.
    #[error("{path}: {message}")]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong, and where in the file.
        message: String,
    },
    /// A file extension the IO layer does not know.
    #[error(
        "{0}: unknown mesh format (expected .obj, .ply, .off or .stl, or one of them \
         gzip-compressed: .obj.gz, .ply.gz, .off.gz, .stl.gz)"
    )]
    UnknownFormat(PathBuf),
    /// A value derived from a mesh (per-vertex data, a selection) met a mesh it was not
    /// made for.
    #[error(transparent)]
    Stale(#[from] crate::binding::Stale),
    /// An argument is outside its documented range.
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
    /// A long operation was stopped by its caller (a progress callback returned
    /// [`ControlFlow::Break`](std::ops::ControlFlow::Break)); nothing the caller owns was
    /// changed.
    #[error("cancelled: {0}")]
    Cancelled(String),
    /// A computed position would not be finite: the coordinates (or an edit's
    /// translations) are too large for the operation, or a position is already NaN or
    /// infinite. Nothing was changed.
    #[error("overflow: {0}")]
    Overflow(String),
    /// A sub-mesh frontier does not separate the mesh or is not a closed loop.
    #[error("invalid frontier: {0}")]
    InvalidFrontier(String),
}

/// A broken connectivity invariant, naming the elements involved.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum Invariant {
    /// `opposite(opposite(h)) != h`, or `opposite(h) == h`, or the opposite is dead.
    #[error("{0}: opposite is not an involution")]
    Opposite(HalfedgeId),
    /// `prev(next(h)) != h`.
    #[error("{0}: prev(next(h)) != h")]
    NextPrev(HalfedgeId),
    /// A link points to a dead element.
    #[error("{0}: links to a removed element")]
    DeadLink(HalfedgeId),
    /// `face(next(h)) != face(h)`.
    #[error("{0}: face(next(h)) differs from face(h)")]
    FaceLoop(HalfedgeId),
    /// `to_vertex(h) == from_vertex(h)`.
    #[error("{0}: is a loop (from == to)")]
    SelfLoop(HalfedgeId),
    /// A face is not a triangle.
    #[error("{face}: has {len} sides, expected 3")]
    NotTriangle {
        /// The face.
        face: FaceId,
        /// Its number of halfedges.
        len: usize,
    },
    /// `face(halfedge(f)) != f`.
    #[error("{0}: its halfedge belongs to another face")]
    FaceHalfedge(FaceId),
    /// `from_vertex(halfedge(v)) != v` or the halfedge is dead.
    #[error("{0}: its halfedge does not start at it")]
    VertexHalfedge(VertexId),
    /// A boundary vertex whose halfedge is not a boundary halfedge.
    #[error("{0}: boundary vertex whose outgoing halfedge is not on the boundary")]
    BoundaryHalfedge(VertexId),
    /// Circulating around a vertex does not return, or misses outgoing halfedges.
    #[error("{0}: the one-ring circulation is broken or the vertex is non-manifold")]
    Fan(VertexId),
    /// A live halfedge starts at a vertex whose halfedge is unset (isolated).
    #[error("{0}: isolated vertex with incident halfedges")]
    Isolated(VertexId),
    /// Counts kept by the mesh disagree with its elements.
    #[error("element counts are out of step: {0}")]
    Counts(String),
}

/// Shorthand for results of the kernel.
pub type Result<T, E = Error> = std::result::Result<T, E>;
