//! The error of the jobs of this crate (loading, the workflow, recipes, batches, the
//! command line): the libraries' errors lifted in, and what the jobs themselves refuse.

use std::path::PathBuf;

/// Everything a job of this crate can refuse or meet.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// An error of the kernel (reading a file names the file and the place).
    #[error(transparent)]
    Mesh(#[from] halfedge::Error),
    /// An error of an editing method.
    #[error(transparent)]
    Edit(#[from] edit::Error),
    /// A picture could not be made.
    #[cfg(feature = "render")]
    #[error(transparent)]
    Render(#[from] crate::render::RenderError),
    /// A file or folder could not be read, written or made.
    #[error("{path}: {source}")]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// What went wrong.
        source: std::io::Error,
    },
    /// An option out of its range.
    #[error("{option}: {reason}")]
    InvalidOption {
        /// The option (as the command line names it, e.g. `--plane`).
        option: &'static str,
        /// What is wrong with it.
        reason: String,
    },
    /// The mesh has no vertex (a welding tolerance or a frame needs one).
    #[error("the mesh has no vertices")]
    NoVertices,
    /// The mesh has no face to edit.
    #[error("{path}: the mesh has no faces to edit")]
    NoFaces {
        /// The file.
        path: PathBuf,
    },
    /// `multires check --openmesh`: OpenMesh reads another topology from the file.
    #[error("{path}: OpenMesh reads {theirs}, multires reads {ours}")]
    OpenMeshDisagrees {
        /// The file.
        path: PathBuf,
        /// Our counts.
        ours: String,
        /// OpenMesh's counts.
        theirs: String,
    },
    /// Some meshes of a batch failed (each has its line in the report; the others were
    /// processed).
    #[error("{failed} of {meshes} meshes failed, the first: {first} (see {report})")]
    BatchFailures {
        /// Meshes that failed.
        failed: usize,
        /// The first failed mesh's error (file and reason).
        first: String,
        /// Meshes of the batch.
        meshes: usize,
        /// The report.
        report: PathBuf,
    },
    /// A recipe that cannot be read or applied (names the step and the key).
    #[error(transparent)]
    Recipe(#[from] crate::recipe::RecipeError),
}

impl From<edit::lee::LeeError> for Error {
    fn from(e: edit::lee::LeeError) -> Self {
        Error::Edit(e.into())
    }
}

impl From<edit::bendels_klein::BendelsKleinError> for Error {
    fn from(e: edit::bendels_klein::BendelsKleinError) -> Self {
        Error::Edit(e.into())
    }
}

impl From<edit::deform::DeformError> for Error {
    fn from(e: edit::deform::DeformError) -> Self {
        Error::Edit(e.into())
    }
}

/// `Result` with this crate's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// [`Error::Io`] for `path`.
#[cfg_attr(not(feature = "render"), allow(dead_code))]
pub(crate) fn io_error(path: impl Into<PathBuf>) -> impl FnOnce(std::io::Error) -> Error {
    let path = path.into();
    move |source| Error::Io { path, source }
}
