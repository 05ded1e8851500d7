//! The Barr deformer interface, its profiles, and its application to a mesh (Barr 1984).

use glam::DVec3;
use halfedge::Mesh;
use rayon::prelude::*;

use crate::deform::checks::{check_finite_positions, finite};
use crate::deform::error::{DeformError, Result};
use crate::vertices::{scatter, Resolved, Vertices};

/// Barr's global and local deformations (A. H. Barr, *Global and local deformations of
/// solid primitives*, SIGGRAPH 1984), as used by *Interactive editing of multiresolution
/// meshes* §4.3 and as the standard operations of Feng, Ma & Peng's FFD.
///
/// A Barr deformation is a transformation whose matrix is a function of the position
/// along an axis:
///
/// - [`Taper`](crate::deform::Taper): the components perpendicular to the axis are scaled by `r(s)`, `s` the
///   axial coordinate: `X = r(s) x, Y = r(s) y, Z = z`.
/// - [`Twist`](crate::deform::Twist): rotation about the axis by `θ(s)`.
/// - [`Bend`](crate::deform::Bend): the part of the object within a range along the axis is bent onto a
///   circular arc of curvature `k` towards a bending direction; beyond the range it is
///   carried rigidly along the tangent of the arc's ends (Barr's formula, with its
///   inverse).
///
/// Every deformer has a centre (origin of the axial coordinate), an axis, and a range:
/// taper factors and twist angles vary linearly ([`Profile`]) between two axial
/// coordinates and are held constant outside them (Barr's *local* deformation) or
/// continue linearly (*global*). Deformers are exact inverses of each other through
/// [`Taper::inverse`](crate::deform::Taper::inverse), [`Twist::inverse`](crate::deform::Twist::inverse) and [`Bend::inverse`](crate::deform::Bend::inverse) (up to rounding), and
/// identity parameters leave positions bit for bit unchanged: the new position is
/// computed as `p + displacement`, and a zero displacement is never added.
///
/// [`apply_deformer`] applies any [`Deformer`] to the whole mesh or to a vertex set, in parallel.
///
/// A point deformation `R³ → R³` (Barr 1984): the common interface of [`Taper`](crate::deform::Taper),
/// [`Twist`](crate::deform::Twist) and [`Bend`](crate::deform::Bend), applied to meshes by [`apply_deformer`].
pub trait Deformer: Sync {
    /// The deformed position of `p`.
    fn deform_point(&self, p: DVec3) -> DVec3;

    /// True when the deformer moves no point (identity parameters); [`apply_deformer`] then
    /// leaves the mesh untouched.
    fn is_identity(&self) -> bool;

    /// Checks that `p` lies where the deformer is defined (for example a positive global
    /// taper factor); [`apply_deformer`] calls it on every point before changing any.
    fn check_point(&self, _p: DVec3) -> Result<()> {
        Ok(())
    }

    /// True when [`check_point`](Self::check_point) can fail, so that [`apply_deformer`] has to
    /// run it.
    fn needs_check(&self) -> bool {
        false
    }
}

/// Applies `deformer` to `vertices` of `mesh` (Barr's deformation of the object's points,
/// here the mesh vertices), in parallel. On error nothing is changed; a deformed position
/// that is not finite (an inverse taper of a tiny factor, a huge bend) is
/// [`DeformError::Overflow`].
pub fn apply_deformer<D: Deformer + ?Sized>(
    mesh: &mut Mesh,
    deformer: &D,
    vertices: Vertices<'_>,
) -> Result<()> {
    let resolved = vertices.resolve(mesh)?;
    if deformer.is_identity() {
        return Ok(());
    }
    let positions = mesh.positions();
    if deformer.needs_check() {
        match &resolved {
            Resolved::Dense(_) => positions
                .par_iter()
                .try_for_each(|&p| deformer.check_point(p))?,
            Resolved::Sparse(indices) => indices
                .par_iter()
                .try_for_each(|&i| deformer.check_point(positions[i as usize]))?,
        }
    }
    // The new positions are computed apart and checked before any is written.
    match &resolved {
        Resolved::Dense(_) => {
            let new: Vec<DVec3> = positions
                .par_iter()
                .with_min_len(4096)
                .map(|&p| deformer.deform_point(p))
                .collect();
            check_finite_positions("the deformation", &[], &new)?;
            mesh.positions_mut()
                .par_iter_mut()
                .zip(new.par_iter())
                .with_min_len(4096)
                .for_each(|(p, &q)| *p = q);
        }
        Resolved::Sparse(indices) => {
            let new: Vec<DVec3> = indices
                .par_iter()
                .with_min_len(4096)
                .map(|&i| deformer.deform_point(positions[i as usize]))
                .collect();
            check_finite_positions("the deformation", indices, &new)?;
            scatter(mesh.positions_mut(), indices, &new);
        }
    }
    Ok(())
}

/// A value varying linearly along the deformation axis (Barr's `r(z)` of the taper and
/// `θ(z)` of the twist): `at_start` at axial coordinate `start`, `at_end` at `end`;
/// outside `[start, end]` it is held constant for a *local* profile and extended
/// linearly for a *global* one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Profile {
    start: f64,
    end: f64,
    at_start: f64,
    at_end: f64,
    local: bool,
}

impl Profile {
    /// The same value everywhere.
    pub fn constant(value: f64) -> Result<Self> {
        finite("profile value", value)?;
        Ok(Self {
            start: 0.0,
            end: 0.0,
            at_start: value,
            at_end: value,
            local: true,
        })
    }

    /// Linear from `at_start` at `start` to `at_end` at `end`, constant outside (Barr's
    /// local deformation). `start == end` gives a step.
    pub fn local(start: f64, end: f64, at_start: f64, at_end: f64) -> Result<Self> {
        for (name, x) in [
            ("profile start", start),
            ("profile end", end),
            ("profile value at start", at_start),
            ("profile value at end", at_end),
        ] {
            finite(name, x)?;
        }
        Ok(Self {
            start,
            end,
            at_start,
            at_end,
            local: true,
        })
    }

    /// Linear through `(start, at_start)` and `(end, at_end)` everywhere (Barr's global
    /// deformation). Needs `start != end`.
    pub fn global(start: f64, end: f64, at_start: f64, at_end: f64) -> Result<Self> {
        let mut p = Self::local(start, end, at_start, at_end)?;
        if start == end {
            return Err(DeformError::InvalidParameter {
                name: "profile range",
                reason: "a global profile needs start != end".into(),
            });
        }
        p.local = false;
        Ok(p)
    }

    /// The value at axial coordinate `s`.
    #[inline]
    pub fn value(&self, s: f64) -> f64 {
        if self.at_start == self.at_end {
            return self.at_start;
        }
        let t = if self.start == self.end {
            if s < self.start {
                0.0
            } else {
                1.0
            }
        } else {
            let t = (s - self.start) / (self.end - self.start);
            if self.local {
                t.clamp(0.0, 1.0)
            } else {
                t
            }
        };
        self.at_start + (self.at_end - self.at_start) * t
    }

    /// True when the value is the same everywhere and equal to `v`.
    pub fn is_constant(&self, v: f64) -> bool {
        self.at_start == v && self.at_end == v
    }

    /// True for a local (clamped) profile.
    pub fn is_local(&self) -> bool {
        self.local
    }

    /// The axial range `(start, end)`.
    pub fn range(&self) -> (f64, f64) {
        (self.start, self.end)
    }

    /// The values `(at_start, at_end)`.
    pub fn values(&self) -> (f64, f64) {
        (self.at_start, self.at_end)
    }

    /// The same profile with every value transformed by `f` (used for inverses).
    pub(crate) fn map_values(&self, f: impl Fn(f64) -> f64) -> Self {
        Self {
            at_start: f(self.at_start),
            at_end: f(self.at_end),
            ..*self
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profile_local_clamps_and_global_extends() {
        let l = Profile::local(0.0, 2.0, 1.0, 3.0).unwrap();
        assert_eq!(l.value(-1.0), 1.0);
        assert_eq!(l.value(1.0), 2.0);
        assert_eq!(l.value(5.0), 3.0);
        let g = Profile::global(0.0, 2.0, 1.0, 3.0).unwrap();
        assert_eq!(g.value(-1.0), 0.0);
        assert_eq!(g.value(4.0), 5.0);
        let step = Profile::local(1.0, 1.0, 0.0, 1.0).unwrap();
        assert_eq!(step.value(0.5), 0.0);
        assert_eq!(step.value(1.0), 1.0);
        assert!(Profile::global(1.0, 1.0, 0.0, 1.0).is_err());
        assert!(Profile::local(f64::NAN, 1.0, 0.0, 1.0).is_err());
    }
}
