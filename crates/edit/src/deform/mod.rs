//! Sub-mesh edits and deformers.

mod barr;
mod checks;
pub(crate) mod error;
mod ffd;
mod smoothing;
mod submesh;

pub use barr::{apply_deformer, Bend, Deformer, Profile, Taper, Twist};
pub use error::{DeformError, SurfaceProblem};
pub use ffd::{AttachOptions, BSplineSurface, Ffd, FfdReach, LatticeFrame, MAX_ATTACH_ITERATIONS};
pub use smoothing::{taubin, Smoother, SmoothingWeights, TaubinOptions};
pub use submesh::{
    AppliedSubmeshEdit, Axis, Falloff, Plane, Propagation, SubMesh, SubmeshEdit, Variation,
};
