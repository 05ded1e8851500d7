//! # edit
//!
//! Editing methods on the `halfedge` kernel, one module per method.
