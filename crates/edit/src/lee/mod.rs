//! Lee 1999, *Interactive multiresolution editing of arbitrary meshes*: area editing.
//!
//! The user specifies an **editing area**, a disk-shaped region of the mesh
//! ([`EditingArea`], §3.2); it is embedded once onto a rectangle by a **harmonic map**
//! ([`Embedding`], §4). An edit moves the vertices of an **editing primitive** (any vertex
//! set of the area, §3.3); their displacements become offsets in **local frames**
//! ([`LocalFrames`], §3.4–3.5), the offsets at the primitive's embedded positions are
//! spread over the rectangle by **multilevel B-spline approximation** ([`mba`], after Lee,
//! Wolberg & Shin 1997) with a **continuous scale parameter** and a fixed border (§5; the
//! session's form of it is described at [`AreaSession`]), and every vertex of the area
//! moves by the offset found at its embedded position. The [`AreaSession`] ties the steps
//! together so that a drag costs only the fit and the evaluation.
//!
//! ```text
//! picks ──shortest paths──▶ loop ──flood fill──▶ EditingArea ──harmonic map──▶ (u, v) ∈ R   (once)
//! primitive + Δp ──frames──▶ Δd at (u, v) ──MBA(s)──▶ f_s ──frames──▶ p_rest + Δ at every vertex   (every drag)
//! ```
//!
//! Everything the family can refuse is a [`LeeError`]. An [`AreaSession`] used at a coarse
//! level of a hierarchy tells it what the drag did through
//! [`HierarchyEdit`](crate::HierarchyEdit).

mod area;
mod embedding;
pub(crate) mod error;
mod fit;
mod frames;
pub mod mba;
mod session;

pub use area::{AreaSide, EditingArea};
pub use embedding::{
    BoundaryMapping, Embedding, EmbeddingOptions, EmbeddingSolver, EmbeddingWeights,
};
pub use error::{LeeError, SolveFailure};
pub use frames::{FrameKind, LocalFrames};
pub use session::{AreaSession, SessionOptions, DEFAULT_PARALLEL_THRESHOLD, MAX_SESSION_LEVELS};
