//! # edit
//!
//! Editing methods on the `halfedge` kernel, one module per method family.

mod error;
pub mod guide;
pub mod laplace;

mod hierarchy_edit;
mod vertices;

pub mod bendels_klein;
pub mod deform;
pub mod lee;

pub use error::{EditError, Result};
pub use hierarchy_edit::HierarchyMarks;
pub use vertices::{Snapshot, Vertices};
