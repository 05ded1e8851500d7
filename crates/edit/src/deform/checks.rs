//! The parameter checks the deformers share: finite scalars and points, unit directions,
//! and finite new positions before an edit writes them.

use glam::DVec3;

use crate::deform::error::{DeformError, Result};
use crate::vertices::first_non_finite;

/// Checks that `d` is finite and not zero, and returns it normalised.
pub(crate) fn unit_direction(name: &'static str, d: DVec3) -> Result<DVec3> {
    // Scaled by its largest component first: (1e300, 1e300, 0) is a fine direction.
    let largest = d.abs().max_element();
    if !d.is_finite() || largest == 0.0 {
        return Err(DeformError::DegenerateDirection { name, value: d });
    }
    let d = d / largest;
    Ok(d / d.length())
}

/// [`DeformError::Overflow`] naming the first of the new positions (of the vertices
/// with the given slot indices, or of slots `0..` when `indices` is empty) that is not
/// finite: checked before an edit writes them, so that no NaN or infinity ever reaches the
/// mesh through an `Ok`.
pub(crate) fn check_finite_positions(
    what: &'static str,
    indices: &[u32],
    new: &[DVec3],
) -> Result<()> {
    match first_non_finite(indices, new) {
        None => Ok(()),
        Some((vertex, position)) => Err(DeformError::Overflow {
            what,
            vertex,
            position,
        }),
    }
}

/// Checks that a scalar parameter is finite.
pub(crate) fn finite(name: &'static str, x: f64) -> Result<f64> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(DeformError::InvalidParameter {
            name,
            reason: format!("{x} is not finite"),
        })
    }
}

/// Checks that a point is finite.
pub(crate) fn finite_point(name: &'static str, p: DVec3) -> Result<DVec3> {
    if p.is_finite() {
        Ok(p)
    } else {
        Err(DeformError::InvalidParameter {
            name,
            reason: format!("{p} is not finite"),
        })
    }
}
