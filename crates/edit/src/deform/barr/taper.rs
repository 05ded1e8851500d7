//! Barr's taper: scaling perpendicular to an axis by a factor that varies along it.

use glam::DVec3;

use crate::deform::barr::deformer::{Deformer, Profile};
use crate::deform::checks::{finite_point, unit_direction};
use crate::deform::error::{DeformError, Result};

/// Barr's taper (1984, §"Tapering"): with `s = (p − centre)·axis` and `q⊥` the part of
/// `p − centre` perpendicular to the axis, `p' = centre + s·axis + r(s)·q⊥`.
///
/// The factor `r` follows a [`Profile`]; a local profile must stay positive (a zero or
/// negative factor folds the object through its axis and has no inverse), a global one
/// is checked on every deformed point by [`apply_deformer`](super::apply_deformer).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Taper {
    centre: DVec3,
    axis: DVec3,
    factor: Profile,
    inverted: bool,
}

impl Taper {
    /// A taper about the line through `centre` along `axis` (normalised here).
    pub fn new(centre: DVec3, axis: DVec3, factor: Profile) -> Result<Self> {
        let centre = finite_point("taper centre", centre)?;
        let axis = unit_direction("taper axis", axis)?;
        if factor.is_local() {
            let (a, b) = factor.values();
            let worst = a.min(b);
            if worst <= 0.0 {
                return Err(DeformError::NonPositiveTaper {
                    factor: worst,
                    at: if a <= b {
                        factor.range().0
                    } else {
                        factor.range().1
                    },
                });
            }
        }
        Ok(Self {
            centre,
            axis,
            factor,
            inverted: false,
        })
    }

    /// Barr's usual taper: factor 1 at axial coordinate `start` growing linearly to
    /// `factor` at `end`, constant beyond (local).
    pub fn linear(centre: DVec3, axis: DVec3, start: f64, end: f64, factor: f64) -> Result<Self> {
        Self::new(centre, axis, Profile::local(start, end, 1.0, factor)?)
    }

    /// The inverse deformation: the factor becomes `1 / r(s)` (the axial coordinate is
    /// not changed by a taper, so this undoes it up to rounding).
    pub fn inverse(&self) -> Self {
        Self {
            inverted: !self.inverted,
            ..*self
        }
    }

    /// The scale factor applied at axial coordinate `s`.
    #[inline]
    pub fn factor_at(&self, s: f64) -> f64 {
        let r = self.factor.value(s);
        if self.inverted {
            1.0 / r
        } else {
            r
        }
    }

    /// The centre.
    pub fn centre(&self) -> DVec3 {
        self.centre
    }
    /// The unit axis.
    pub fn axis(&self) -> DVec3 {
        self.axis
    }
    /// The factor profile (of the forward taper).
    pub fn profile(&self) -> Profile {
        self.factor
    }
}

impl Deformer for Taper {
    #[inline]
    fn deform_point(&self, p: DVec3) -> DVec3 {
        let q = p - self.centre;
        let s = q.dot(self.axis);
        let r = self.factor_at(s);
        if r == 1.0 {
            return p;
        }
        let perpendicular = q - s * self.axis;
        let d = (r - 1.0) * perpendicular;
        if d == DVec3::ZERO {
            p
        } else {
            p + d
        }
    }

    fn is_identity(&self) -> bool {
        self.factor.is_constant(1.0)
    }

    fn check_point(&self, p: DVec3) -> Result<()> {
        let s = (p - self.centre).dot(self.axis);
        let r = self.factor.value(s);
        if r > 0.0 {
            Ok(())
        } else {
            Err(DeformError::NonPositiveTaper { factor: r, at: s })
        }
    }

    fn needs_check(&self) -> bool {
        !self.factor.is_local()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scales_perpendicular_distance_only() {
        let t = Taper::linear(DVec3::ZERO, DVec3::Z, 0.0, 2.0, 3.0).unwrap();
        let p = DVec3::new(1.0, 2.0, 1.0);
        let q = t.deform_point(p);
        assert!((q - DVec3::new(2.0, 4.0, 1.0)).length() < 1e-15);
        let back = t.inverse().deform_point(q);
        assert!((back - p).length() < 1e-15);
        // beyond the range the factor is constant
        let q = t.deform_point(DVec3::new(1.0, 0.0, 7.0));
        assert!((q - DVec3::new(3.0, 0.0, 7.0)).length() < 1e-15);
    }

    #[test]
    fn rejects_non_positive_factors() {
        assert!(Taper::linear(DVec3::ZERO, DVec3::Z, 0.0, 1.0, 0.0).is_err());
        assert!(Taper::linear(DVec3::ZERO, DVec3::ZERO, 0.0, 1.0, 2.0).is_err());
        let g = Taper::new(
            DVec3::ZERO,
            DVec3::Z,
            Profile::global(0.0, 1.0, 1.0, 0.5).unwrap(),
        )
        .unwrap();
        assert!(g.check_point(DVec3::new(0.0, 0.0, 1.5)).is_ok());
        assert!(g.check_point(DVec3::new(0.0, 0.0, 2.5)).is_err());
    }
}
