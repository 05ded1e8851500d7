//! Barr's twist: rotation about an axis by an angle that varies along it.

use glam::DVec3;

use crate::deform::barr::deformer::{Deformer, Profile};
use crate::deform::checks::{finite_point, unit_direction};
use crate::deform::error::Result;

/// Barr's twist (1984, §"Twisting"): rotation of `p` about the line through `centre`
/// along `axis` by `θ(s)`, `s = (p − centre)·axis`, counter-clockwise seen from the tip of
/// the axis. The axial coordinate is unchanged, so [`inverse`](Self::inverse) (the angle
/// negated) undoes it up to rounding.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Twist {
    centre: DVec3,
    axis: DVec3,
    angle: Profile,
}

impl Twist {
    /// A twist about the line through `centre` along `axis` (normalised here); angles in
    /// radians.
    pub fn new(centre: DVec3, axis: DVec3, angle: Profile) -> Result<Self> {
        Ok(Self {
            centre: finite_point("twist centre", centre)?,
            axis: unit_direction("twist axis", axis)?,
            angle,
        })
    }

    /// Barr's usual twist: angle 0 at axial coordinate `start` growing linearly to
    /// `angle` at `end`, constant beyond (local).
    pub fn linear(centre: DVec3, axis: DVec3, start: f64, end: f64, angle: f64) -> Result<Self> {
        Self::new(centre, axis, Profile::local(start, end, 0.0, angle)?)
    }

    /// The inverse twist (every angle negated).
    pub fn inverse(&self) -> Self {
        Self {
            angle: self.angle.map_values(|a| -a),
            ..*self
        }
    }

    /// The rotation angle at axial coordinate `s`.
    #[inline]
    pub fn angle_at(&self, s: f64) -> f64 {
        self.angle.value(s)
    }

    /// The centre.
    pub fn centre(&self) -> DVec3 {
        self.centre
    }
    /// The unit axis.
    pub fn axis(&self) -> DVec3 {
        self.axis
    }
    /// The angle profile.
    pub fn profile(&self) -> Profile {
        self.angle
    }
}

/// Displacement of `q` (relative to a point on the axis) under rotation by `angle` about
/// the unit `axis`: `(cos θ − 1) q⊥ + sin θ (axis × q)`; exactly zero for a zero angle.
#[inline]
pub(crate) fn rotation_displacement(axis: DVec3, q: DVec3, angle: f64) -> DVec3 {
    if angle == 0.0 {
        return DVec3::ZERO;
    }
    let (sin, cos) = angle.sin_cos();
    let perpendicular = q - q.dot(axis) * axis;
    (cos - 1.0) * perpendicular + sin * axis.cross(q)
}

impl Deformer for Twist {
    #[inline]
    fn deform_point(&self, p: DVec3) -> DVec3 {
        let q = p - self.centre;
        let angle = self.angle.value(q.dot(self.axis));
        let d = rotation_displacement(self.axis, q, angle);
        if d == DVec3::ZERO {
            p
        } else {
            p + d
        }
    }

    fn is_identity(&self) -> bool {
        self.angle.is_constant(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn quarter_turn_at_the_end_of_the_range() {
        let t = Twist::linear(DVec3::ZERO, DVec3::Z, 0.0, 1.0, FRAC_PI_2).unwrap();
        let q = t.deform_point(DVec3::new(1.0, 0.0, 1.0));
        assert!((q - DVec3::new(0.0, 1.0, 1.0)).length() < 1e-15);
        let q = t.deform_point(DVec3::new(1.0, 0.0, 0.5));
        let h = std::f64::consts::FRAC_1_SQRT_2;
        assert!((q - DVec3::new(h, h, 0.5)).length() < 1e-15);
        assert_eq!(
            t.deform_point(DVec3::new(1.0, 0.0, -1.0)),
            DVec3::new(1.0, 0.0, -1.0)
        );
    }
}
