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

pub use error::{Error, Result};
pub use hierarchy_edit::{HierarchyEdit, HierarchyMarks};
pub use vertices::{Snapshot, Vertices};
