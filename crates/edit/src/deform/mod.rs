//! Sub-mesh edits and deformers.

mod barr;
mod ffd;
mod smoothing;
mod submesh;

pub use barr::{apply_deformer, Bend, Deformer, Profile, Taper, Twist};
pub use ffd::{AttachOptions, BSplineSurface, Ffd, FfdReach, LatticeFrame, MAX_ATTACH_ITERATIONS};
pub use smoothing::{taubin, Smoother, SmoothingWeights, TaubinOptions};
pub use submesh::{Axis, Falloff, Plane, Propagation, SubMesh, SubmeshEdit, Variation};
