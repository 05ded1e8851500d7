//! Barr's bend: a region along an axis bent onto a circular arc.

use glam::DVec3;

use crate::deform::barr::deformer::Deformer;
use crate::deform::checks::{finite, finite_point, unit_direction};
use crate::deform::error::{DeformError, Result};

/// Barr's bend (1984, §"Global and local bending"), along `axis` (Barr's `y`) towards
/// `direction` (Barr's `z`, made perpendicular to the axis here), with bending rate
/// (curvature) `k`, centre of the bend at `centre` (Barr's `y₀ = 0` in local
/// coordinates) and bent range `[y_min, y_max]` (relative to the centre; `None`: the
/// whole axis). With `ŷ = clamp(y, y_min, y_max)`, `θ = k ŷ`, `C = cos θ`, `S = sin θ`:
///
/// ```text
/// Y = −S (z − 1/k) + C (y − ŷ)
/// Z =  C (z − 1/k) + 1/k + S (y − ŷ)
/// ```
///
/// (`x`, the third coordinate, is unchanged). The centre of curvature lies at `z = 1/k`
/// on the `direction` side for `k > 0`. The points inside the range go onto the arc,
/// the ones beyond move rigidly with the arc's end tangents.
///
/// [`inverse`](Self::inverse) is Barr's inverse bend. It is exact (to rounding) on the
/// domain where the bend is one-to-one: points on the near side of the centre of
/// curvature (`k·z < 1`) and a bent range of less than half a turn (`|k|·(y_max − y_min)
/// < π`; for an unbounded range, `|k y| < π` on the object).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bend {
    centre: DVec3,
    axis: DVec3,
    direction: DVec3,
    rate: f64,
    range: (f64, f64),
    inverted: bool,
}

impl Bend {
    /// A bend; `rate` is the curvature `k` (1 / radius), 0 for no bend.
    pub fn new(
        centre: DVec3,
        axis: DVec3,
        direction: DVec3,
        rate: f64,
        range: Option<(f64, f64)>,
    ) -> Result<Self> {
        let centre = finite_point("bend centre", centre)?;
        let axis = unit_direction("bend axis", axis)?;
        let direction = unit_direction("bend direction", direction)?;
        let direction = unit_direction(
            "bend direction (perpendicular to the axis)",
            direction - direction.dot(axis) * axis,
        )?;
        let rate = finite("bend rate", rate)?;
        let range = match range {
            None => (f64::NEG_INFINITY, f64::INFINITY),
            Some((lo, hi)) => {
                finite("bend range start", lo)?;
                finite("bend range end", hi)?;
                if lo > hi {
                    return Err(DeformError::InvalidParameter {
                        name: "bend range",
                        reason: format!("start {lo} is after end {hi}"),
                    });
                }
                (lo, hi)
            }
        };
        Ok(Self {
            centre,
            axis,
            direction,
            rate,
            range,
            inverted: false,
        })
    }

    /// The inverse bend (Barr's inverse formula; see the domain in the type docs).
    pub fn inverse(&self) -> Self {
        Self {
            inverted: !self.inverted,
            ..*self
        }
    }

    /// The curvature `k`.
    pub fn rate(&self) -> f64 {
        self.rate
    }
    /// The centre.
    pub fn centre(&self) -> DVec3 {
        self.centre
    }
    /// The unit axis (Barr's `y`).
    pub fn axis(&self) -> DVec3 {
        self.axis
    }
    /// The unit bending direction (Barr's `z`), perpendicular to the axis.
    pub fn direction(&self) -> DVec3 {
        self.direction
    }

    /// Forward bend of local coordinates `(y, z)`.
    #[inline]
    fn forward(&self, y: f64, z: f64) -> (f64, f64) {
        let k = self.rate;
        let clamped = y.clamp(self.range.0, self.range.1);
        let theta = k * clamped;
        let (s, c) = theta.sin_cos();
        let one_minus_cos = one_minus_cos(s, c);
        let a = y - clamped;
        // Y = −S (z − 1/k) + C a,  Z = C (z − 1/k) + 1/k + S a, written without 1/k alone.
        let big_y = -s * z + s / k + c * a;
        let big_z = c * z + one_minus_cos / k + s * a;
        (big_y, big_z)
    }

    /// Barr's inverse bend of local coordinates `(Y, Z)`.
    #[inline]
    fn backward(&self, big_y: f64, big_z: f64) -> (f64, f64) {
        let k = self.rate;
        // (Y, Z − 1/k) = Rot(θ)·(y − ŷ, z − 1/k); undoing the rotation by θ gives
        // y − ŷ = C Y + S Z − S/k and z = −S Y + C Z + (1 − C)/k, written without a lone
        // 1/k so that small curvatures keep their precision.
        let unrotate = |theta: f64| {
            let (s, c) = theta.sin_cos();
            let one_minus_cos = one_minus_cos(s, c);
            let along = c * big_y + s * big_z - s / k;
            let z = -s * big_y + c * big_z + one_minus_cos / k;
            (along, z)
        };
        // Polar angle of the point about the centre of curvature, in the convention where
        // a point of the bent range at `ŷ` has angle `k ŷ`.
        let sign = k.signum();
        let polar = (sign * big_y).atan2(sign * (1.0 / k - big_z));
        let (lo, hi) = self.range;
        if !lo.is_finite() {
            let (_, z) = unrotate(polar);
            return (polar / k, z);
        }
        // Points beyond the range lie within a quarter turn past the end angles; with a
        // bent range below half a turn the three sectors do not overlap.
        let middle = 0.5 * k * (lo + hi);
        let delta = wrap_angle(polar - middle);
        if (delta - (k * hi - middle)) * sign > 0.0 {
            let (a, z) = unrotate(k * hi);
            return (hi + a, z);
        }
        if (delta - (k * lo - middle)) * sign < 0.0 {
            let (a, z) = unrotate(k * lo);
            return (lo + a, z);
        }
        let theta = middle + delta;
        let (_, z) = unrotate(theta);
        (theta / k, z)
    }
}

/// `1 − cos θ` from `sin θ` and `cos θ` without cancellation for small angles
/// (`sin² θ / (1 + cos θ)`).
#[inline]
fn one_minus_cos(s: f64, c: f64) -> f64 {
    if c > 0.0 {
        s * s / (1.0 + c)
    } else {
        1.0 - c
    }
}

/// `a` brought into `(−π, π]`.
#[inline]
fn wrap_angle(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let mut a = a % TAU;
    if a > PI {
        a -= TAU;
    } else if a <= -PI {
        a += TAU;
    }
    a
}

impl Deformer for Bend {
    #[inline]
    fn deform_point(&self, p: DVec3) -> DVec3 {
        if self.rate == 0.0 {
            return p;
        }
        let q = p - self.centre;
        let (y, z) = (q.dot(self.axis), q.dot(self.direction));
        let (ny, nz) = if self.inverted {
            self.backward(y, z)
        } else {
            self.forward(y, z)
        };
        let d = (ny - y) * self.axis + (nz - z) * self.direction;
        if d == DVec3::ZERO {
            p
        } else {
            p + d
        }
    }

    fn is_identity(&self) -> bool {
        self.rate == 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn bends_the_axis_onto_a_circle() {
        // k = 1: the axis (z = 0) goes onto the unit circle centred at z = 1.
        let b = Bend::new(DVec3::ZERO, DVec3::Y, DVec3::Z, 1.0, Some((-1.0, 1.0))).unwrap();
        for y in [-1.0, -0.3, 0.0, 0.5, 1.0] {
            let q = b.deform_point(DVec3::new(0.0, y, 0.0));
            assert!((q.distance(DVec3::new(0.0, 0.0, 1.0)) - 1.0).abs() < 1e-14);
            // arc length from the centre equals y
            let angle = q.y.atan2(1.0 - q.z);
            assert!((angle - y).abs() < 1e-14);
        }
        // beyond the range: rigid along the end tangent
        let q = b.deform_point(DVec3::new(0.0, 2.0, 0.0));
        let end = b.deform_point(DVec3::new(0.0, 1.0, 0.0));
        let tangent = DVec3::new(0.0, 1f64.cos(), 1f64.sin());
        assert!((q - (end + tangent)).length() < 1e-14);
    }

    #[test]
    fn inverse_restores_points_in_every_part() {
        for k in [0.7, -0.7, 1e-6, 2.0] {
            let range = (-0.6, 0.9);
            let b = Bend::new(
                DVec3::new(0.1, 0.2, 0.3),
                DVec3::new(0.0, 1.0, 0.1),
                DVec3::Z,
                k,
                Some(range),
            )
            .unwrap();
            let inv = b.inverse();
            for y in [-2.0, -0.6, -0.1, 0.0, 0.4, 0.9, 1.5] {
                for z in [-0.3, 0.0, 0.2] {
                    let p = DVec3::new(0.5, y, z);
                    let back = inv.deform_point(b.deform_point(p));
                    assert!((back - p).length() < 1e-12, "k {k} p {p} back {back}");
                }
            }
        }
        let whole = Bend::new(DVec3::ZERO, DVec3::Y, DVec3::Z, PI / 4.0, None).unwrap();
        let p = DVec3::new(0.0, 1.5, -0.2);
        let back = whole.inverse().deform_point(whole.deform_point(p));
        assert!((back - p).length() < 1e-12);
    }
}
