//! The library's errors as Python exceptions: every failure of the Rust side becomes a
//! [`MeshError`] (a `ValueError`), an `EditError` or a `RecipeError` (both `MeshError`s),
//! or, for a file that is missing or unreadable, an `OSError` subclass — always with the
//! library's own message.

use pyo3::exceptions::{PyFileNotFoundError, PyOSError, PyValueError};
use pyo3::PyErr;

pyo3::create_exception!(
    multires,
    MeshError,
    PyValueError,
    "A mesh, array, hierarchy or file the library refuses (wrong dtype or shape, NaN, an \
     index out of range, a bad format, a corrupt .mrh, a level that does not exist). A \
     subclass of ValueError; the message is the library's."
);
pyo3::create_exception!(
    multires,
    EditError,
    MeshError,
    "An editing method refused its input (an empty or overlapping region, a non-finite \
     transform, a region that is not a disk...). A subclass of MeshError."
);
pyo3::create_exception!(
    multires,
    RecipeError,
    MeshError,
    "A recipe that cannot be read or applied (names the step and the key). A subclass of \
     MeshError."
);

/// A failure met while the GIL was released, turned into a Python exception afterwards.
#[derive(Debug)]
pub enum Fail {
    /// `MeshError`.
    Mesh(String),
    /// `EditError`.
    Edit(String),
    /// `RecipeError`.
    Recipe(String),
    /// `FileNotFoundError` / `OSError`.
    Io {
        /// The message.
        message: String,
        /// The file is missing.
        not_found: bool,
    },
    /// A Python exception raised by a callback.
    Python(PyErr),
}

/// `Result` with a [`Fail`].
pub type Res<T> = Result<T, Fail>;

impl From<Fail> for PyErr {
    fn from(f: Fail) -> PyErr {
        match f {
            Fail::Mesh(m) => MeshError::new_err(m),
            Fail::Edit(m) => EditError::new_err(m),
            Fail::Recipe(m) => RecipeError::new_err(m),
            Fail::Io { message, not_found } => {
                if not_found {
                    PyFileNotFoundError::new_err(message)
                } else {
                    PyOSError::new_err(message)
                }
            }
            Fail::Python(e) => e,
        }
    }
}

impl From<PyErr> for Fail {
    fn from(e: PyErr) -> Self {
        Fail::Python(e)
    }
}

impl From<halfedge::Error> for Fail {
    fn from(e: halfedge::Error) -> Self {
        match &e {
            halfedge::Error::Io { source, .. } => Fail::Io {
                not_found: source.kind() == std::io::ErrorKind::NotFound,
                message: e.to_string(),
            },
            _ => Fail::Mesh(e.to_string()),
        }
    }
}

impl From<edit::Error> for Fail {
    fn from(e: edit::Error) -> Self {
        Fail::Edit(e.to_string())
    }
}

impl From<edit::lee::LeeError> for Fail {
    fn from(e: edit::lee::LeeError) -> Self {
        Fail::Edit(e.to_string())
    }
}

impl From<edit::bendels_klein::BendelsKleinError> for Fail {
    fn from(e: edit::bendels_klein::BendelsKleinError) -> Self {
        Fail::Edit(e.to_string())
    }
}

impl From<edit::deform::DeformError> for Fail {
    fn from(e: edit::deform::DeformError) -> Self {
        Fail::Edit(e.to_string())
    }
}

impl From<multires::recipe::RecipeError> for Fail {
    fn from(e: multires::recipe::RecipeError) -> Self {
        match &e {
            multires::recipe::RecipeError::Io { source, .. } => Fail::Io {
                not_found: source.kind() == std::io::ErrorKind::NotFound,
                message: e.to_string(),
            },
            _ => Fail::Recipe(e.to_string()),
        }
    }
}

impl From<multires::Error> for Fail {
    fn from(e: multires::Error) -> Self {
        match e {
            multires::Error::Mesh(e) => e.into(),
            multires::Error::Edit(e) => e.into(),
            multires::Error::Recipe(e) => e.into(),
            multires::Error::Io { ref source, .. } => Fail::Io {
                not_found: source.kind() == std::io::ErrorKind::NotFound,
                message: e.to_string(),
            },
            other => Fail::Mesh(other.to_string()),
        }
    }
}

/// A `MeshError` with `message`.
pub fn mesh_err(message: impl Into<String>) -> PyErr {
    MeshError::new_err(message.into())
}
