//! The motion a mark gives the vertices it names ([`Hierarchy::mark_affine`],
//! [`Hierarchy::mark_field`]): an affine map, or any map of space (a deformation defined
//! everywhere, such as a Barr twist whose strength ramps along its axis), which
//! refinement applies to the recorded positions of the finer vertices.
//!
//! [`Hierarchy::mark_affine`]: super::Hierarchy::mark_affine
//! [`Hierarchy::mark_field`]: super::Hierarchy::mark_field

use std::fmt;
use std::sync::Arc;

use glam::{DAffine3, DVec3};

/// A map of space given by a function (see [`super::Hierarchy::mark_field`]).
pub type Field = Arc<dyn Fn(DVec3) -> DVec3 + Send + Sync>;

/// An affine map or a field.
#[derive(Clone)]
pub(crate) enum Motion {
    Affine(DAffine3),
    Field(Field),
}

impl fmt::Debug for Motion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Motion::Affine(a) => f.debug_tuple("Affine").field(a).finish(),
            Motion::Field(_) => f.write_str("Field(..)"),
        }
    }
}

impl Motion {
    /// Where the motion takes `p`.
    #[inline]
    pub(crate) fn apply(&self, p: DVec3) -> DVec3 {
        match self {
            Motion::Affine(a) => a.transform_point3(p),
            Motion::Field(f) => f(p),
        }
    }

    /// `next` after `self`.
    pub(crate) fn then(&self, next: &Motion) -> Motion {
        match (self, next) {
            (Motion::Affine(a), Motion::Affine(b)) => Motion::Affine(*b * *a),
            (first, second) => {
                let (first, second) = (first.clone(), second.clone());
                Motion::Field(Arc::new(move |p| second.apply(first.apply(p))))
            }
        }
    }

    /// The size of a coordinate the motion's rounding is relative to at `p`, besides
    /// `p` and its image: an affine map's translation.
    #[inline]
    pub(crate) fn scale_at(&self, p: DVec3, image: DVec3) -> f64 {
        let own = match self {
            Motion::Affine(a) => a.translation.abs().max_element(),
            Motion::Field(_) => (image - p).abs().max_element(),
        };
        own.max(image.abs().max_element())
            .max(p.abs().max_element())
    }
}
