//! The blend every Bendels & Klein session shares, on meshes, polylines and pictures
//! (*Image and 3D-object editing with precisely specified editing regions*, Secs. 3–5):
//! the role of every vertex or point, its distances to the handle's and the fixed area's
//! borders, its weight `α = f(d_fixed / (d_fixed + d_handle))` with the shape function
//! `f`, and the handle transform `A` with its power `α ⊙ A = exp(α log A)` (Alexa 2002).
//! A handle vertex moves to `A p`, a deformable one to `(α ⊙ A) p`, a fixed one stays.
//!
//! [`BlendCore`] keeps those; the sessions ([`BlendSession`](super::BlendSession),
//! [`PolylineSession`](super::polyline::PolylineSession),
//! [`ImageSessionOf`](super::image::ImageSessionOf)) add their medium: where the
//! distances come from, where the points are stored, how they are drawn.
//!
//! Degenerate distances ([`blend_ratio`]): a vertex that only the handle reaches
//! (`d_fixed = ∞`) follows the handle (α = 1), one that only the fixed area reaches stays
//! (α = 0), one neither reaches (or at distance 0 from both) stays too.

use std::ops::{Deref, DerefMut};

use glam::{DMat3, DMat4, DVec2, DVec3};
use halfedge::{Mesh, VertexData};
use rayon::prelude::*;

use crate::bendels_klein::affine_power::{embed_affine2, AffinePower};
use crate::bendels_klein::error::Result;
use crate::bendels_klein::regions::Role;
use crate::bendels_klein::shape::ShapeFunction;

/// A point the blend moves (Bendels & Klein, Secs. 2 and 7): [`DVec2`] (polylines in the
/// plane and pictures; transforms are 3×3 homogeneous [`DMat3`]) or [`DVec3`] (meshes and
/// polylines in space; 4×4 [`DMat4`]). The blend works in space; 2-D points live in
/// `z = 0` and their transforms act on `x, y` only ([`embed_affine2`]).
pub trait BlendPoint: Copy + PartialEq + std::fmt::Debug + Send + Sync + 'static {
    /// The homogeneous affine transform of such points.
    type Affine: Copy + PartialEq + std::fmt::Debug + Send + Sync;
    /// The point in space (`z = 0` in 2-D).
    fn to_space(self) -> DVec3;
    /// The point back from space (`z` dropped in 2-D).
    fn from_space(p: DVec3) -> Self;
    /// True when every coordinate is finite.
    fn finite(self) -> bool;
    /// The midpoint of `self` and `other`.
    fn midpoint(self, other: Self) -> Self;
    /// The transform as a 4×4 affine map of space.
    fn embed(a: Self::Affine) -> DMat4;
    /// The identity transform.
    fn identity() -> Self::Affine;
    /// `A p`, with the arithmetic of glam's `transform_point2` / `transform_point3`.
    fn apply(a: &Self::Affine, p: Self) -> Self;
    /// `(α ⊙ A) p` from a prepared power of `embed(A)`.
    fn blend(power: &AffinePower, alpha: f64, p: Self) -> Self;
}

impl BlendPoint for DVec2 {
    type Affine = DMat3;
    #[inline]
    fn to_space(self) -> DVec3 {
        self.extend(0.0)
    }
    #[inline]
    fn from_space(p: DVec3) -> Self {
        p.truncate()
    }
    #[inline]
    fn finite(self) -> bool {
        self.is_finite()
    }
    #[inline]
    fn midpoint(self, other: Self) -> Self {
        // Halves first: finite points give a finite midpoint even near f64::MAX.
        0.5 * self + 0.5 * other
    }
    fn embed(a: DMat3) -> DMat4 {
        embed_affine2(a)
    }
    fn identity() -> DMat3 {
        DMat3::IDENTITY
    }
    #[inline]
    fn apply(a: &DMat3, p: Self) -> Self {
        a.transform_point2(p)
    }
    #[inline]
    fn blend(power: &AffinePower, alpha: f64, p: Self) -> Self {
        power.transform_point2(alpha, p)
    }
}

impl BlendPoint for DVec3 {
    type Affine = DMat4;
    #[inline]
    fn to_space(self) -> DVec3 {
        self
    }
    #[inline]
    fn from_space(p: DVec3) -> Self {
        p
    }
    #[inline]
    fn finite(self) -> bool {
        self.is_finite()
    }
    #[inline]
    fn midpoint(self, other: Self) -> Self {
        // Halves first: finite points give a finite midpoint even near f64::MAX.
        0.5 * self + 0.5 * other
    }
    fn embed(a: DMat4) -> DMat4 {
        a
    }
    fn identity() -> DMat4 {
        DMat4::IDENTITY
    }
    #[inline]
    fn apply(a: &DMat4, p: Self) -> Self {
        a.transform_point3(p)
    }
    #[inline]
    fn blend(power: &AffinePower, alpha: f64, p: Self) -> Self {
        power.transform_point(alpha, p)
    }
}

/// `d_fixed / (d_fixed + d_handle)` with the conventions of the module docs (Bendels &
/// Klein, Sec. 4): the argument of the shape function.
#[inline]
#[must_use]
pub fn blend_ratio(d_fixed: f64, d_handle: f64) -> f64 {
    match (d_fixed.is_finite(), d_handle.is_finite()) {
        (true, true) => {
            let sum = d_fixed + d_handle;
            if sum > 0.0 {
                d_fixed / sum
            } else {
                0.0
            }
        }
        (false, true) => 1.0,
        _ => 0.0,
    }
}

/// The weight of a vertex or point with `role` at distances `d_fixed`, `d_handle`: 0
/// fixed, 1 handle, `f(d_fixed / (d_fixed + d_handle))` deformable (Bendels & Klein,
/// Sec. 5).
#[inline]
pub(crate) fn weight(shape: &ShapeFunction, role: Role, d_fixed: f64, d_handle: f64) -> f64 {
    match role {
        Role::Fixed => 0.0,
        Role::Handle => 1.0,
        Role::Deformable => shape.eval(blend_ratio(d_fixed, d_handle)),
    }
}

/// The largest [`RefineOptions::max_new_vertices`] accepted: about 400 MB of new mesh
/// elements and per-vertex session data.
///
/// Paper: Bendels & Klein 2003, *Image and 3D-object editing with precisely specified
/// editing regions*, Sec. 6.
pub const MAX_NEW_VERTICES: usize = 1 << 22;

/// Options of the adaptive refinement of a Bendels & Klein edit (Sec. 6, after *Mesh
/// forging*), on a mesh ([`BlendSession::refine`](super::BlendSession::refine)) or a
/// polyline ([`PolylineSession::refine`](super::polyline::PolylineSession::refine)).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct RefineOptions {
    /// Edges of the deformable area longer than this (after the edit) are split.
    pub max_edge_length: f64,
    /// At most this many vertices are added (a guard against run-away refinement; at
    /// most [`MAX_NEW_VERTICES`]).
    pub max_new_vertices: usize,
}

impl Default for RefineOptions {
    /// Edges longer than 1 are split, at most a million new vertices.
    fn default() -> Self {
        Self::new(1.0)
    }
}

impl RefineOptions {
    /// Split edges longer than `max_edge_length`, at most a million new vertices.
    #[must_use]
    pub fn new(max_edge_length: f64) -> Self {
        Self {
            max_edge_length,
            max_new_vertices: 1_000_000,
        }
    }

    /// The same options, splitting edges longer than `max_edge_length`.
    #[must_use]
    pub fn with_max_edge_length(mut self, max_edge_length: f64) -> Self {
        self.max_edge_length = max_edge_length;
        self
    }

    /// The same options, adding at most `max_new_vertices` vertices.
    #[must_use]
    pub fn with_max_new_vertices(mut self, max_new_vertices: usize) -> Self {
        self.max_new_vertices = max_new_vertices;
        self
    }

    /// Checks the options: a finite, positive length and a budget of at most
    /// [`MAX_NEW_VERTICES`].
    pub(crate) fn check(&self) -> Result<()> {
        use crate::bendels_klein::error::BendelsKleinError;
        let max = self.max_edge_length;
        if !(max.is_finite() && max > 0.0) {
            return Err(BendelsKleinError::InvalidParameter {
                name: "max_edge_length",
                reason: format!("must be finite and positive, got {max}"),
            });
        }
        // Each pass may double the edges near the edit: the budget bounds the memory.
        if self.max_new_vertices > MAX_NEW_VERTICES {
            return Err(BendelsKleinError::InvalidParameter {
                name: "max_new_vertices",
                reason: format!("{} is more than {MAX_NEW_VERTICES}", self.max_new_vertices),
            });
        }
        Ok(())
    }
}

/// What a refinement did (Bendels & Klein, Sec. 6).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RefineReport {
    /// Vertices (or points) added, one per edge (or segment) split.
    pub new_vertices: usize,
    /// Passes over the edges.
    pub passes: usize,
    /// Longest deformed edge of the deformable area afterwards.
    pub longest_edge: f64,
}

/// The state every Bendels & Klein session shares (see the module docs): the
/// role, the two distances and the weight α of every vertex or point (stored as `F`: a
/// `Vec<f64>`, or per-vertex data of a mesh), the shape function, and the handle
/// transform with its prepared power. It computes the weights and the blended points;
/// the sessions own the points.
#[derive(Clone, Debug)]
pub(crate) struct BlendCore<P: BlendPoint, F = Vec<f64>> {
    roles: Vec<Role>,
    d_handle: F,
    d_fixed: F,
    alpha: F,
    /// True while every α is in [0, 1].
    alphas_in_unit: bool,
    shape: ShapeFunction,
    transform: P::Affine,
    power: AffinePower,
}

/// The transform and its power a core had, to put back when an edit fails.
pub(crate) struct SavedTransform<P: BlendPoint> {
    transform: P::Affine,
    power: AffinePower,
}

impl<P, F> BlendCore<P, F>
where
    P: BlendPoint,
    F: Deref<Target = [f64]> + DerefMut,
{
    /// A core with the identity transform and the weights of `shape` computed; `alpha`
    /// is the storage the weights are written to (as long as `roles`).
    pub(crate) fn new(
        roles: Vec<Role>,
        d_handle: F,
        d_fixed: F,
        alpha: F,
        shape: ShapeFunction,
    ) -> Self {
        let mut core = Self {
            roles,
            d_handle,
            d_fixed,
            alpha,
            alphas_in_unit: true,
            shape,
            transform: P::identity(),
            power: AffinePower::from_log(DMat4::IDENTITY, DMat4::ZERO),
        };
        core.update_alpha();
        core
    }

    /// The role of every vertex or point.
    pub(crate) fn roles(&self) -> &[Role] {
        &self.roles
    }
    /// The weights: 0 on the fixed area, 1 on the handle.
    pub(crate) fn alpha(&self) -> &F {
        &self.alpha
    }
    /// Distances to the handle's border.
    pub(crate) fn handle_distances(&self) -> &F {
        &self.d_handle
    }
    /// Distances to the fixed area's border.
    pub(crate) fn fixed_distances(&self) -> &F {
        &self.d_fixed
    }
    /// The shape function.
    pub(crate) fn shape(&self) -> &ShapeFunction {
        &self.shape
    }
    /// The handle transform as given (the identity before the first edit).
    pub(crate) fn transform(&self) -> P::Affine {
        self.transform
    }
    /// The prepared power of the transform.
    pub(crate) fn power(&self) -> &AffinePower {
        &self.power
    }
    /// True while every weight is in [0, 1].
    pub(crate) fn alphas_in_unit(&self) -> bool {
        self.alphas_in_unit
    }

    /// Changes the shape function and recomputes the weights (the paper's Fig. 8).
    pub(crate) fn set_shape(&mut self, shape: ShapeFunction) {
        self.shape = shape;
        self.update_alpha();
    }

    /// Takes `a` as the handle transform (computing `log A` once) and returns the one it
    /// had, to put back with [`restore`](Self::restore) if the edit fails.
    ///
    /// # Errors
    /// The errors of [`AffinePower::new`]; nothing changes then.
    pub(crate) fn set_transform(&mut self, a: P::Affine) -> Result<SavedTransform<P>> {
        let power = AffinePower::new(P::embed(a))?;
        Ok(SavedTransform {
            transform: std::mem::replace(&mut self.transform, a),
            power: std::mem::replace(&mut self.power, power),
        })
    }

    /// Puts back a transform [`set_transform`](Self::set_transform) replaced.
    pub(crate) fn restore(&mut self, saved: SavedTransform<P>) {
        self.transform = saved.transform;
        self.power = saved.power;
    }

    /// Back to the identity transform.
    pub(crate) fn reset_transform(&mut self) {
        self.transform = P::identity();
        self.power = AffinePower::from_log(DMat4::IDENTITY, DMat4::ZERO);
    }

    /// The weight of a new vertex or point with `role` at the given distances.
    pub(crate) fn weight(&self, role: Role, d_fixed: f64, d_handle: f64) -> f64 {
        weight(&self.shape, role, d_fixed, d_handle)
    }

    /// Where the blend puts a vertex or point with `role` and weight `alpha` whose
    /// original position is `o`: `o` fixed, `A o` handle, `(α ⊙ A) o` deformable.
    #[inline]
    pub(crate) fn place(&self, role: Role, alpha: f64, o: P) -> P {
        match role {
            Role::Fixed => o,
            Role::Handle => P::apply(&self.transform, o),
            Role::Deformable => P::blend(&self.power, alpha, o),
        }
    }

    /// Where the blend puts vertex or point `i` whose original position is `o`.
    #[inline]
    pub(crate) fn place_index(&self, i: usize, o: P) -> P {
        self.place(self.roles[i], self.alpha[i], o)
    }

    /// Takes new roles, distances and weights (after points were inserted), as long as
    /// each other.
    pub(crate) fn replace_fields(&mut self, roles: Vec<Role>, d_handle: F, d_fixed: F, alpha: F) {
        self.alphas_in_unit = alpha.par_iter().all(|a| (0.0..=1.0).contains(a));
        self.roles = roles;
        self.d_handle = d_handle;
        self.d_fixed = d_fixed;
        self.alpha = alpha;
    }

    /// Recomputes every weight from the distances and the shape function.
    fn update_alpha(&mut self) {
        let shape = &self.shape;
        let roles = &self.roles;
        let (dh, df): (&[f64], &[f64]) = (&self.d_handle, &self.d_fixed);
        self.alpha
            .par_iter_mut()
            .enumerate()
            .with_min_len(4096)
            .for_each(|(i, a)| *a = weight(shape, roles[i], df[i], dh[i]));
        self.alphas_in_unit = self.alpha.par_iter().all(|a| (0.0..=1.0).contains(a));
    }
}

impl<P: BlendPoint> BlendCore<P, VertexData<f64>> {
    /// Binds the per-vertex data to `mesh` as the session's own splits left it: new
    /// slots get neutral values (fixed, at infinite distances, weight 0) until the split
    /// fills them in with [`set_new`](Self::set_new).
    pub(crate) fn rebind(&mut self, mesh: &Mesh) {
        self.d_handle.rebind(mesh, f64::INFINITY);
        self.d_fixed.rebind(mesh, f64::INFINITY);
        self.alpha.rebind(mesh, 0.0);
        self.roles.resize(mesh.vertex_slots(), Role::Fixed);
    }

    /// Fills in a vertex a split created: deformable, with its distances and weight.
    pub(crate) fn set_new(&mut self, i: usize, d_handle: f64, d_fixed: f64, alpha: f64) {
        self.roles[i] = Role::Deformable;
        self.d_handle[i] = d_handle;
        self.d_fixed[i] = d_fixed;
        self.alpha[i] = alpha;
        self.alphas_in_unit &= (0.0..=1.0).contains(&alpha);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blend_ratio_conventions() {
        assert_eq!(blend_ratio(1.0, 3.0), 0.25);
        assert_eq!(blend_ratio(0.0, 0.0), 0.0);
        assert_eq!(blend_ratio(f64::INFINITY, 2.0), 1.0);
        assert_eq!(blend_ratio(2.0, f64::INFINITY), 0.0);
        assert_eq!(blend_ratio(f64::INFINITY, f64::INFINITY), 0.0);
    }
}
