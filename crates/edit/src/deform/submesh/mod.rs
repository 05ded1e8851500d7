//! Sub-mesh edits with propagation levels (*Interactive editing of multiresolution meshes* §4).

pub(super) mod axis;
pub(super) mod edits;
pub(super) mod frontier;
pub(super) mod plane;

pub use axis::Axis;
pub use edits::{AppliedSubmeshEdit, Falloff, Propagation, SubmeshEdit, Variation};
pub use frontier::SubMesh;
pub use plane::Plane;
