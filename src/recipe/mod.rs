//! Edit recipes: a sequence of editing steps, each an editing method at a hierarchy level
//! with its parameters and its region, written in TOML, that `multires edit` replays on a
//! saved hierarchy (`.mrh`), `multires batch` maps over a corpus and the viewer writes
//! from the edits made in it.
//!
//! Regions are given in terms that carry over between meshes: a point in space and its
//! nearest vertex, the vertex furthest along an axis, a radius as a fraction of the
//! bounding-box diagonal, a cutting plane, a sub-mesh label — so a recipe made on one
//! resolution of a model applies sensibly to another, and replays bit for bit on the
//! same mesh (points and transforms are written with every digit of their `f64`s).
//!
//! ```toml
//! version = 1
//!
//! [hierarchy]            # how `multires batch` simplifies a mesh first (optional)
//! method = "rounds"      # or "qem"
//! target_faces = 2000
//!
//! [[step]]
//! method = "lee_drag"    # Lee 1999: an editing area dragged by its primitive
//! level = 3              # the hierarchy level it is made at (clamped to the coarsest)
//! area = { kind = "disk", around = { extreme = "+z" }, vertices = 300 }
//! along_normal = 0.15    # the drag, as a fraction of the diagonal along the normal
//! scale = 0.6            # Lee's scale parameter s
//!
//! [[step]]
//! method = "blend"       # Bendels & Klein: handle, fixed, and the blend between
//! level = 3
//! handle = { kind = "ball", around = { extreme = "-x" }, radius = 0.08 }
//! fixed = { kind = "beyond", around = { extreme = "-x" }, radius = 0.3 }
//! rotate = { axis = [0.0, 0.0, 1.0], degrees = 25.0 }
//!
//! [[step]]
//! method = "taper"       # a sub-mesh edit (pull, scale, rotate, taper, twist)
//! level = 3
//! region = { kind = "cut", axis = "+y", at = 0.72 }
//! factor = 0.6
//! propagation = 2
//! ```
//!
//! Every key is checked: an unknown key, a value of the wrong type or out of range is
//! refused with a [`RecipeError`] naming the step (from 1) and the key, and the TOML
//! parser's line and column. The full schema is in the
//! [recipes guide](https://example.invalid/multires/docs/guide/recipes.md) (`docs/guide/recipes.md`).

mod apply;
mod region;
pub(crate) use region::axis_name;
mod schema;

pub use apply::{apply, apply_to_mesh, StepOutcome};
pub use region::{parse_axis, resolve_place, resolve_region, Frame};
pub use schema::{
    AxisSpec, Blend, Falloff, HierarchySpec, LeeDrag, Matrix, Place, Pull, Recipe, Region, Rotate,
    RotateStep, Scale, Smooth, Step, StepKind, Taper, Twist, Variation, RECIPE_VERSION,
};

use std::path::PathBuf;

/// What can be wrong with a recipe, or with applying one.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RecipeError {
    /// The file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        source: std::io::Error,
    },
    /// The text is not a recipe: TOML syntax, an unknown key, a value of the wrong type
    /// (the message names the key, the line and the column).
    #[error("{path}: {message}")]
    Parse {
        /// The file (or `<recipe>` for text).
        path: PathBuf,
        /// The parser's message, with the step and the key.
        message: String,
    },
    /// A recipe of another version.
    #[error("recipe version {found} is not supported (this program reads version {supported})")]
    Version {
        /// The version the recipe declares.
        found: u32,
        /// The version this program reads.
        supported: u32,
    },
    /// A value out of its range.
    #[error("step {step} ({method}): {key}: {reason}")]
    Invalid {
        /// The step, from 1 (0: the `[hierarchy]` table).
        step: usize,
        /// The step's method.
        method: &'static str,
        /// The key.
        key: &'static str,
        /// What is wrong with it.
        reason: String,
    },
    /// A region that selects nothing usable on this mesh, or a step the editing method
    /// refused (its error says why).
    #[error("step {step} ({method}): {reason}")]
    Step {
        /// The step, from 1.
        step: usize,
        /// The step's method.
        method: &'static str,
        /// Why it could not be applied.
        reason: String,
    },
}

/// `Result` with a [`RecipeError`].
pub type RecipeResult<T> = std::result::Result<T, RecipeError>;
