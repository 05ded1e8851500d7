//! Barr's taper, twist and bend (Barr 1984).

pub(super) mod bend;
pub(super) mod deformer;
mod taper;
pub(super) mod twist;

pub use bend::Bend;
pub use deformer::{apply_deformer, Deformer, Profile};
pub use taper::Taper;
pub use twist::Twist;
