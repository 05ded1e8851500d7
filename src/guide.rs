//! # Guides
//!
//! One guide per method: what it does, the paper and section it implements, its
//! parameters and sensible defaults, the errors a user can hit, and a runnable example on
//! a generated mesh. The text lives in `docs/guide/*.md` (readable on its own) and is
//! included here, so `cargo test --doc -p multires` compiles and runs every example.
//!
//! - [`hierarchy`]: the kernel, collapse / split, the progressive hierarchy (rounds or
//!   QEM), detail coefficients and sub-mesh labels (crate `halfedge`).
//! - [`area_editing`]: Lee 1999 area editing, harmonic map + multilevel B-splines with a
//!   scale parameter ([`edit::lee`]).
//! - [`bendels_klein`]: Bendels & Klein precisely specified regions, distance fields,
//!   shape functions, `exp(α log A)` and adaptive refinement
//!   ([`edit::bendels_klein`]).
//! - [`images_and_polylines`]: the same edit on polylines / polygons and on pictures
//!   (grid mesh, exact distance transform, resampling)
//!   ([`edit::bendels_klein::polyline`], [`edit::bendels_klein::image`]).
//! - [`submesh_edits`]: sub-mesh edits with propagation levels, Barr's deformers and
//!   Taubin smoothing ([`edit::deform`]).
//! - [`ffd`]: Feng, Ma & Peng's shape/height-surface free-form deformation
//!   ([`edit::deform::Ffd`]).
//! - [`workflow`]: simplify → edit → refine, the job of `multires workflow`
//!   ([`crate::workflow`]).
//! - [`coarse_edits`]: how coarse edits come back at full resolution (detail modes, exact
//!   regions, affine marks) and the `coarse_edit` example that measures it.
//! - [`hierarchy_file`]: saving and loading a hierarchy (`.mrh`): the layout, the checks
//!   and the version policy.
//! - [`cli`]: the `multires` command line: subcommands, exit codes, reports, batches.
//! - [`recipes`]: edit recipes (TOML): steps, levels, portable regions, errors
//!   ([`crate::recipe`]).
//! - [`architecture`]: how the crates and modules fit together and the rules they keep.
//! - [`python`]: the Python package (`pip install ./python`, `import multires`).

#[doc = include_str!("../docs/guide/hierarchy.md")]
pub mod hierarchy {}

#[doc = include_str!("../docs/guide/area-editing.md")]
pub mod area_editing {}

#[doc = include_str!("../docs/guide/bendels-klein.md")]
pub mod bendels_klein {}

#[doc = include_str!("../docs/guide/images-and-polylines.md")]
pub mod images_and_polylines {}

#[doc = include_str!("../docs/guide/submesh-edits.md")]
pub mod submesh_edits {}

#[doc = include_str!("../docs/guide/ffd.md")]
pub mod ffd {}

#[doc = include_str!("../docs/guide/workflow.md")]
pub mod workflow {}

#[doc = include_str!("../docs/guide/coarse-edits.md")]
pub mod coarse_edits {}

#[doc = include_str!("../docs/guide/hierarchy-file.md")]
pub mod hierarchy_file {}

#[doc = include_str!("../docs/guide/cli.md")]
pub mod cli {}

#[doc = include_str!("../docs/guide/recipes.md")]
pub mod recipes {}

#[doc = include_str!("../docs/guide/architecture.md")]
pub mod architecture {}

#[doc = include_str!("../docs/guide/python.md")]
pub mod python {}
