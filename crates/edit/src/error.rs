//! The error of any editing method: the three family errors gathered, for programs that
//! handle any of them (the command line, the Python package, the viewer).
//!
//! Error types stand below everything else of the crate: this module imports only the
//! three family errors, which import nothing of the crate.

use crate::bendels_klein::error::BendelsKleinError;
use crate::deform::error::DeformError;
use crate::lee::error::LeeError;

/// An error of any editing method: a family's error, or an error of the modules shared by
/// the families ([`HierarchyMarks`](crate::HierarchyMarks),
/// [`Snapshot`](crate::Snapshot)), which are kernel errors.
///
/// Paper: Lee 1999, *Interactive multiresolution editing of arbitrary meshes*; Bendels &
/// Klein 2003, *Image and 3D-object editing with precisely specified editing regions*;
/// *Interactive editing of multiresolution meshes*, Barr 1984, Taubin 1995, Feng, Ma & Peng
/// 1996, *A new free-form deformation through the control of parametric surfaces*.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Lee 1999 area editing ([`crate::lee`]).
    #[error(transparent)]
    Lee(#[from] LeeError),
    /// Bendels & Klein, on meshes, polylines and pictures ([`crate::bendels_klein`]).
    #[error(transparent)]
    BendelsKlein(#[from] BendelsKleinError),
    /// Sub-mesh edits and deformers ([`crate::deform`]).
    #[error(transparent)]
    Deform(#[from] DeformError),
    /// An error of the half-edge kernel met by a shared module (a hierarchy refusing a
    /// mark).
    #[error(transparent)]
    Mesh(halfedge::Error),
    /// Something derived from a mesh met another mesh, or its mesh in another state (see
    /// [`halfedge::Binding`]); every family's `Stale` variant is this error too.
    #[error(transparent)]
    Stale(#[from] halfedge::Stale),
}

impl From<halfedge::Error> for Error {
    /// Lifts a kernel error; a kernel refusal of stale data becomes [`Error::Stale`].
    fn from(error: halfedge::Error) -> Self {
        match error {
            halfedge::Error::Stale(stale) => Self::Stale(stale),
            error => Self::Mesh(error),
        }
    }
}

impl Error {
    /// The staleness error, whichever family (or shared module) found it: `Some` for every
    /// `Stale` variant.
    #[must_use]
    pub fn as_stale(&self) -> Option<&halfedge::Stale> {
        match self {
            Self::Stale(s)
            | Self::Lee(LeeError::Stale(s))
            | Self::BendelsKlein(BendelsKleinError::Stale(s))
            | Self::Deform(DeformError::Stale(s)) => Some(s),
            _ => None,
        }
    }
}

/// Shorthand for results of the editing methods, by default with [`Error`].
///
/// Paper: the three families of this crate (Lee 1999, Bendels & Klein 2003, the deformers).
pub type Result<T, E = Error> = std::result::Result<T, E>;
