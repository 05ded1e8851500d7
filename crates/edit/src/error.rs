//! The error of any editing method: the three family errors gathered, for programs that
//! handle any of them (the command line, the Python package, the viewer).
//!
//! Error types stand below everything else of the crate: this module imports only the
//! three family errors, which import nothing of the crate.

use crate::bendels_klein::error::BendelsKleinError;
use crate::deform::error::DeformError;
use crate::lee::error::LeeError;

/// An error of any editing method: a family's error (Lee 1999, *Interactive
/// multiresolution editing of arbitrary meshes*; Bendels & Klein 2003, *Image and
/// 3D-object editing with precisely specified editing regions*; the deformers of
/// *Interactive editing of multiresolution meshes*, Barr 1984, Taubin 1995 and Feng, Ma &
/// Peng 1996), or an error of the modules shared by the families
/// ([`HierarchyMarks`](crate::HierarchyMarks), [`Snapshot`](crate::Snapshot)), which are
/// kernel errors.
///
/// Every family error converts into it (`?` works); the payloads are boxed so that a
/// `Result<_, edit::Error>` stays two words wide (a family error is 120 bytes, most of it
/// the kernel's [`halfedge::Stale`]).
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Lee 1999 area editing ([`crate::lee`]).
    #[error(transparent)]
    Lee(Box<LeeError>),
    /// Bendels & Klein, on meshes, polylines and pictures ([`crate::bendels_klein`]).
    #[error(transparent)]
    BendelsKlein(Box<BendelsKleinError>),
    /// Sub-mesh edits and deformers ([`crate::deform`]).
    #[error(transparent)]
    Deform(Box<DeformError>),
    /// An error of the half-edge kernel met by a shared module (a hierarchy refusing a
    /// mark).
    #[error(transparent)]
    Mesh(Box<halfedge::Error>),
    /// Something derived from a mesh met another mesh, or its mesh in another state (see
    /// [`halfedge::Binding`]), found by a shared module; every family's `Stale` variant is
    /// this error too ([`Error::as_stale`] finds either).
    #[error(transparent)]
    Stale(Box<halfedge::Stale>),
}

impl From<LeeError> for Error {
    fn from(error: LeeError) -> Self {
        Self::Lee(Box::new(error))
    }
}

impl From<BendelsKleinError> for Error {
    fn from(error: BendelsKleinError) -> Self {
        Self::BendelsKlein(Box::new(error))
    }
}

impl From<DeformError> for Error {
    fn from(error: DeformError) -> Self {
        Self::Deform(Box::new(error))
    }
}

impl From<halfedge::Stale> for Error {
    fn from(stale: halfedge::Stale) -> Self {
        Self::Stale(Box::new(stale))
    }
}

impl From<halfedge::Error> for Error {
    /// Lifts a kernel error; a kernel refusal of stale data becomes [`Error::Stale`].
    fn from(error: halfedge::Error) -> Self {
        match error {
            halfedge::Error::Stale(stale) => stale.into(),
            error => Self::Mesh(Box::new(error)),
        }
    }
}

impl Error {
    /// The staleness error, whichever family (or shared module) found it: `Some` for every
    /// `Stale` variant.
    #[must_use]
    pub fn as_stale(&self) -> Option<&halfedge::Stale> {
        match self {
            Self::Stale(s) => Some(s),
            Self::Lee(e) => match e.as_ref() {
                LeeError::Stale(s) => Some(s),
                _ => None,
            },
            Self::BendelsKlein(e) => match e.as_ref() {
                BendelsKleinError::Stale(s) => Some(s),
                _ => None,
            },
            Self::Deform(e) => match e.as_ref() {
                DeformError::Stale(s) => Some(s),
                _ => None,
            },
            Self::Mesh(_) => None,
        }
    }
}

/// Shorthand for results of the editing methods, by default with [`Error`]: the three
/// families of this crate (Lee 1999, Bendels & Klein 2003, the deformers).
pub type Result<T, E = Error> = std::result::Result<T, E>;
