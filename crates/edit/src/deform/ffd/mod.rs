//! Shape- and height-surface FFD (Feng, Ma & Peng).

mod attach;
mod bspline;
pub(super) mod frame;

use glam::DVec3;
use halfedge::Mesh;
use rayon::prelude::*;

use crate::deform::barr::bend::Bend;
use crate::deform::barr::deformer::{Deformer, Profile};
use crate::deform::barr::twist::Twist;
use crate::deform::checks::{check_finite_positions, finite, finite_point};
use crate::deform::error::{DeformError, Result, SurfaceProblem};
use crate::error::Error;
use crate::hierarchy_edit::{HierarchyEdit, HierarchyMarks};
use crate::vertices::Vertices;

pub use bspline::BSplineSurface;
use bspline::Patches;
pub use frame::LatticeFrame;

/// Global deformation (the object lies over the shape surface) or local (it crosses the
/// surface's border, whose control points then stay fixed), Feng, Ma & Peng §4.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FfdReach {
    /// Every selected vertex is attached.
    Global,
    /// Some vertices lie outside the footprint of the shape surface.
    Local,
}

/// How many units in the last place of the lattice's largest coordinate a foot may be
/// off along the surface and still count as attached ([`AttachOptions::tolerance`] is
/// added to it).
const ROUNDING_ULPS: f64 = 64.0;

/// Most Newton iterations per vertex [`Ffd::attach`] accepts (a bound on its time).
///
/// Paper: Feng, Ma & Peng 1996, *A new free-form deformation through the control of
/// parametric surfaces*, §3.
pub const MAX_ATTACH_ITERATIONS: usize = 10_000;

/// Options of [`Ffd::attach`].
///
/// Paper: Feng, Ma & Peng 1996, *A new free-form deformation through the control of
/// parametric surfaces*, §3–4.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct AttachOptions {
    /// Layers of shape-surface control points held fixed along a crossed border in local
    /// mode (2: the surface and its normal stay continuous there).
    pub shape_layers: usize,
    /// Layers of height-surface control points held fixed along a crossed border (2: the
    /// heights and their slope stay continuous there).
    pub height_layers: usize,
    /// Newton iterations per vertex at most (at most [`MAX_ATTACH_ITERATIONS`]).
    pub max_iterations: usize,
    /// A vertex is attached when its offset from the foot is along the normal to within
    /// `tolerance ×` the size of the shape surface's control net (plus the rounding of
    /// coordinates as large as the net's, for a lattice far from the origin).
    pub tolerance: f64,
}

impl AttachOptions {
    /// The same options with the layers of shape-surface control points held fixed along a crossed border set to `shape_layers`.
    #[must_use]
    pub fn with_shape_layers(mut self, shape_layers: usize) -> Self {
        self.shape_layers = shape_layers;
        self
    }

    /// The same options with the layers of height-surface control points held fixed along a crossed border set to `height_layers`.
    #[must_use]
    pub fn with_height_layers(mut self, height_layers: usize) -> Self {
        self.height_layers = height_layers;
        self
    }

    /// The same options with the Newton iterations per vertex at most set to `max_iterations`.
    #[must_use]
    pub fn with_max_iterations(mut self, max_iterations: usize) -> Self {
        self.max_iterations = max_iterations;
        self
    }

    /// The same options with the attachment tolerance set to `tolerance`.
    #[must_use]
    pub fn with_tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = tolerance;
        self
    }
}

impl Default for AttachOptions {
    fn default() -> Self {
        Self {
            shape_layers: 2,
            height_layers: 2,
            max_iterations: 50,
            tolerance: 1e-10,
        }
    }
}

/// Shape- and height-surface free-form deformation (J. Feng, L. Ma, Q. Peng, *A new
/// free-form deformation through the control of parametric surfaces*).
///
/// Two clamped B-spline surfaces ([`BSplineSurface`]) drive the deformation: the
/// **shape surface** `S(u, v)`, initially on the XZ plane of a placement [`LatticeFrame`], and
/// the **height surface** `H(u, v)`, initially on the plane `y = 1`. They may differ in
/// degree and control grid; they share the parameter square `[0, 1]²`.
///
/// - **Attach** (§3, once): every vertex `P` is projected onto `S` along the surface
///   normal: `(u_p, v_p)` is the closest point (Newton's method from the best sample of
///   a coarse grid), `h_p = (P − S(u_p, v_p))·N_s` its directed distance. The triple
///   `(u, v, h)` is all that is stored per vertex. A vertex whose foot is not along the
///   normal (its closest point is on the border of `S`: it lies outside the surface's
///   footprint) is not attached and never moves.
/// - **Deform** (§3, many times): `P_new = S_new(u, v) + H_new,y(u, v) · h · n_new(u, v)`,
///   `n_new` the unit normal of `S_new` and `H_new,y` the frame-`y` coordinate of
///   `H_new`. Undisplaced surfaces give back the object.
/// - **Global or local** (§4): when the whole object lies over `S` the deformation is
///   global; otherwise it is local and the control points along the borders of `S` that
///   the object crosses stay fixed (two layers of `S`, so that the surface *and* its
///   normal are unchanged along the border, and two of `H`, so that heights and their
///   slope are too),
///   which keeps the deformed object continuous with its unattached part.
/// - **Standard operations** (§4): [`Ffd::bend`] (Barr's bend of the shape surface),
///   [`Ffd::taper`] (the shape surface narrowed and the height surface sloped together,
///   as the paper's Fig. 9–10) and [`Ffd::twist`] (the shape surface twisted about its
///   `u` axis), plus [`Ffd::translate`] and [`Ffd::scale_heights`].
///
/// Deforming is the hot path: each surface is converted once per call into polynomial
/// patches in power form (one per knot cell), so that a vertex costs a few Horner
/// loops, without per-vertex basis storage (24 bytes per vertex in all), in parallel.
///
/// A shape/height-surface FFD attached to a mesh.
#[derive(Clone, Debug)]
pub struct Ffd {
    frame: LatticeFrame,
    shape_rest: BSplineSurface,
    height_rest: BSplineSurface,
    shape: BSplineSurface,
    height: BSplineSurface,
    binding: halfedge::Binding,
    /// Per vertex slot `(u, v, h)`; `u` is NaN for a vertex not attached.
    params: Vec<[f64; 3]>,
    attached: usize,
    crossed: [bool; 4],
    pinned_shape: Vec<bool>,
    pinned_height: Vec<bool>,
}

/// Number of coarse samples per direction for initial guesses.
fn sample_count(spans: usize) -> usize {
    (4 * spans + 1).clamp(9, 33)
}

/// Pins `layers` rows/columns along every crossed border of a `count` grid.
fn pins(count: [usize; 2], crossed: [bool; 4], layers: usize) -> Vec<bool> {
    let mut pinned = vec![false; count[0] * count[1]];
    for i in 0..count[0] {
        for j in 0..count[1] {
            pinned[i * count[1] + j] = (crossed[0] && i < layers)
                || (crossed[1] && i + layers >= count[0])
                || (crossed[2] && j < layers)
                || (crossed[3] && j + layers >= count[1]);
        }
    }
    pinned
}

impl Ffd {
    /// Attaches `vertices` of `mesh` to the shape surface `shape` (§3); `height` is the
    /// height surface (identity when its frame-`y` coordinates are all 1). In local mode
    /// (some vertex outside the shape surface's footprint) the border control points
    /// are pinned as [`AttachOptions`] says.
    pub fn attach(
        mesh: &Mesh,
        vertices: Vertices<'_>,
        frame: LatticeFrame,
        shape: BSplineSurface,
        height: BSplineSurface,
        options: AttachOptions,
    ) -> Result<Self> {
        finite("attach tolerance", options.tolerance)?;
        if options.max_iterations > MAX_ATTACH_ITERATIONS {
            return Err(DeformError::InvalidParameter {
                name: "max_iterations",
                reason: format!(
                    "{} is more than {MAX_ATTACH_ITERATIONS}",
                    options.max_iterations
                ),
            });
        }
        let selected = vertices.resolve(mesh)?;
        if selected.len() == 0 {
            return Err(DeformError::EmptySubMesh);
        }
        let slots = mesh.vertex_slots();
        // Feet are found about the frame's origin, so that a lattice far from the world's
        // origin keeps the precision of its own size.
        let origin = frame.origin;
        let local: Vec<DVec3> = shape.control_points().iter().map(|&p| p - origin).collect();
        let patches = Patches::new(shape.degree(), shape.count(), &local);
        let spans = patches.spans();
        let samples =
            attach::Samples::new(&patches, [sample_count(spans[0]), sample_count(spans[1])]);
        let (lo, hi) = local
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(*p), hi.max(*p))
            });
        // (plus the rounding of positions far from the origin: a lattice 10⁷ units away
        // cannot place a foot closer than about 10⁻⁹)
        let magnitude = lo.abs().max(hi.abs()).max_element();
        let tolerance = options.tolerance * (hi - lo).length().max(f64::MIN_POSITIVE)
            + ROUNDING_ULPS * f64::EPSILON * magnitude;

        let positions = mesh.positions();
        let indices = selected.to_indices();
        let feet: Vec<attach::Foot> = indices
            .par_iter()
            .with_min_len(256)
            .map(|&i| {
                attach::foot(
                    &patches,
                    &samples,
                    positions[i as usize] - origin,
                    options.max_iterations,
                )
            })
            .collect();

        let mut params = vec![[f64::NAN, 0.0, 0.0]; slots];
        let mut attached = 0;
        let mut crossed = [false; 4];
        for (&i, f) in indices.iter().zip(&feet) {
            if f.residual <= tolerance && f.h.is_finite() {
                params[i as usize] = [f.u, f.v, f.h];
                attached += 1;
            } else {
                crossed[0] |= f.u <= 0.0;
                crossed[1] |= f.u >= 1.0;
                crossed[2] |= f.v <= 0.0;
                crossed[3] |= f.v >= 1.0;
            }
        }
        if attached == 0 {
            return Err(DeformError::NothingAttached);
        }
        let pinned_shape = pins(shape.count(), crossed, options.shape_layers);
        let pinned_height = pins(height.count(), crossed, options.height_layers);
        Ok(Self {
            frame,
            shape_rest: shape.clone(),
            height_rest: height.clone(),
            shape,
            height,
            binding: mesh.binding(),
            params,
            attached,
            crossed,
            pinned_shape,
            pinned_height,
        })
    }

    /// Attaches `vertices` to surfaces built over their footprint: the bounding
    /// rectangle of the vertices in the frame's XZ plane, grown by `margin` times its
    /// size on each side; the shape surface on the frame's `y = 0`, the height surface on
    /// `y = 1` (the paper's initial placement), with the given degrees and grid sizes.
    pub fn covering(
        mesh: &Mesh,
        vertices: Vertices<'_>,
        frame: LatticeFrame,
        shape_grid: ([usize; 2], [usize; 2]),
        height_grid: ([usize; 2], [usize; 2]),
        margin: f64,
        options: AttachOptions,
    ) -> Result<Self> {
        finite("margin", margin)?;
        let selected = vertices.resolve(mesh)?;
        let positions = mesh.positions();
        let (lo, hi) = selected
            .to_indices()
            .par_iter()
            .map(|&i| {
                let l = frame.to_local(positions[i as usize]);
                (l, l)
            })
            .reduce(
                || (DVec3::INFINITY, DVec3::NEG_INFINITY),
                |a, b| (a.0.min(b.0), a.1.max(b.1)),
            );
        if !lo.is_finite() {
            return Err(DeformError::EmptySubMesh);
        }
        let size = (hi - lo).max(DVec3::splat(f64::MIN_POSITIVE));
        let min = [lo.x - margin * size.x, lo.z - margin * size.z];
        let max = [hi.x + margin * size.x, hi.z + margin * size.z];
        let shape = BSplineSurface::planar(&frame, shape_grid.0, shape_grid.1, min, max, 0.0)?;
        let height = BSplineSurface::planar(&frame, height_grid.0, height_grid.1, min, max, 1.0)?;
        Self::attach(mesh, vertices, frame, shape, height, options)
    }

    /// The placement frame.
    pub fn frame(&self) -> &LatticeFrame {
        &self.frame
    }
    /// Global or local deformation (Feng, Ma & Peng §4).
    pub fn reach(&self) -> FfdReach {
        if self.crossed.iter().any(|&c| c) {
            FfdReach::Local
        } else {
            FfdReach::Global
        }
    }
    /// Which borders of the shape surface the object crosses: `[u = 0, u = 1, v = 0, v = 1]`.
    pub fn crossed_borders(&self) -> [bool; 4] {
        self.crossed
    }
    /// Number of attached vertices.
    pub fn attached(&self) -> usize {
        self.attached
    }
    /// The attachment `(u, v, h)` of the vertex with index `index`, `None` when it is not
    /// attached.
    pub fn parameters(&self, index: usize) -> Option<(f64, f64, f64)> {
        let [u, v, h] = *self.params.get(index)?;
        (!u.is_nan()).then_some((u, v, h))
    }
    /// The current shape surface.
    pub fn shape(&self) -> &BSplineSurface {
        &self.shape
    }
    /// The current shape surface, to move its control points (pinned ones are ignored by
    /// [`deform`](Self::deform)).
    pub fn shape_mut(&mut self) -> &mut BSplineSurface {
        &mut self.shape
    }
    /// The current height surface.
    pub fn height(&self) -> &BSplineSurface {
        &self.height
    }
    /// The current height surface, to move its control points.
    pub fn height_mut(&mut self) -> &mut BSplineSurface {
        &mut self.height
    }
    /// The surfaces at attach time `(shape, height)`.
    pub fn rest(&self) -> (&BSplineSurface, &BSplineSurface) {
        (&self.shape_rest, &self.height_rest)
    }
    /// True when shape-surface control point `(i, j)` is pinned (local mode).
    pub fn is_shape_pinned(&self, i: usize, j: usize) -> bool {
        let c = self.shape.count();
        i < c[0] && j < c[1] && self.pinned_shape[i * c[1] + j]
    }
    /// True when height-surface control point `(i, j)` is pinned (local mode).
    pub fn is_height_pinned(&self, i: usize, j: usize) -> bool {
        let c = self.height.count();
        i < c[0] && j < c[1] && self.pinned_height[i * c[1] + j]
    }
    /// Puts both surfaces back to their rest shape.
    pub fn reset(&mut self) {
        self.shape = self.shape_rest.clone();
        self.height = self.height_rest.clone();
    }

    /// Moves every (unpinned) shape control point by `t`: the object follows rigidly.
    ///
    /// # Errors
    /// [`DeformError::InvalidParameter`] for a non-finite `t`; [`DeformError::Overflow`]
    /// (nothing changed) when a control point would not stay finite. The same holds for
    /// every edit of the surfaces below.
    pub fn translate(&mut self, t: DVec3) -> Result<()> {
        let t = finite_point("translation", t)?;
        let saved = self.saved();
        let pinned = &self.pinned_shape;
        for (p, &fixed) in self.shape.control_points_mut().iter_mut().zip(pinned) {
            if !fixed {
                *p += t;
            }
        }
        self.keep_if_finite(saved, "the translation")
    }

    /// The surfaces as they are, to put back by [`keep_if_finite`](Self::keep_if_finite).
    fn saved(&self) -> (BSplineSurface, BSplineSurface) {
        (self.shape.clone(), self.height.clone())
    }

    /// Keeps the edited surfaces if all their control points are finite; otherwise puts
    /// `saved` back and fails with [`DeformError::ControlPointOverflow`].
    fn keep_if_finite(
        &mut self,
        saved: (BSplineSurface, BSplineSurface),
        what: &'static str,
    ) -> Result<()> {
        let bad = self
            .shape
            .control_points()
            .iter()
            .chain(self.height.control_points())
            .find(|p| !p.is_finite())
            .copied();
        match bad {
            None => Ok(()),
            Some(p) => {
                (self.shape, self.height) = saved;
                Err(DeformError::ControlPointOverflow { what, position: p })
            }
        }
    }

    /// Multiplies the frame-`y` coordinate of every (unpinned) height control point by
    /// `k`: every height `h` becomes `k h`.
    pub fn scale_heights(&mut self, k: f64) -> Result<()> {
        let k = finite("height scale", k)?;
        let saved = self.saved();
        let frame = self.frame;
        let pinned = &self.pinned_height;
        for (p, &fixed) in self.height.control_points_mut().iter_mut().zip(pinned) {
            if !fixed {
                let y = (*p - frame.origin).dot(frame.y);
                *p += (k - 1.0) * y * frame.y;
            }
        }
        self.keep_if_finite(saved, "the height scale")
    }

    /// The rest footprint of the shape surface in frame coordinates:
    /// `(x_min, x_max, mean y, z centre)`.
    fn footprint(&self) -> (f64, f64, f64, f64) {
        let local: Vec<DVec3> = self
            .shape_rest
            .control_points()
            .iter()
            .map(|&p| self.frame.to_local(p))
            .collect();
        let (lo, hi) = local
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(*p), hi.max(*p))
            });
        let mean_y = local.iter().map(|p| p.y).sum::<f64>() / local.len() as f64;
        (lo.x, hi.x, mean_y, 0.5 * (lo.z + hi.z))
    }

    /// Applies a Barr deformer to the (unpinned) shape control points.
    fn deform_shape(&mut self, d: &impl Deformer) {
        let pinned = &self.pinned_shape;
        for (p, &fixed) in self.shape.control_points_mut().iter_mut().zip(pinned) {
            if !fixed {
                *p = d.deform_point(*p);
            }
        }
    }

    /// Bending (§4 (1), Fig. 7–8): the shape surface is bent by `angle` radians along
    /// its `u` direction (Barr's bend of its control net about the middle of the
    /// footprint, towards `+y` for a positive angle); the height surface is unchanged.
    pub fn bend(&mut self, angle: f64) -> Result<()> {
        let angle = finite("bend angle", angle)?;
        let (x0, x1, y, zc) = self.footprint();
        let half = 0.5 * (x1 - x0);
        let centre = self.frame.to_world(DVec3::new(0.5 * (x0 + x1), y, zc));
        let bend = Bend::new(
            centre,
            self.frame.x,
            self.frame.y,
            angle / (x1 - x0),
            Some((-half, half)),
        )?;
        let saved = self.saved();
        self.deform_shape(&bend);
        self.keep_if_finite(saved, "the bend")
    }

    /// Twisting (§4 (3), Fig. 11–12): the shape surface is twisted about its `u` axis
    /// (the frame-`x` line through the middle of the footprint), the angle growing
    /// linearly from 0 at `u = 0` to `angle` at `u = 1`.
    pub fn twist(&mut self, angle: f64) -> Result<()> {
        let angle = finite("twist angle", angle)?;
        let (x0, x1, y, zc) = self.footprint();
        let centre = self.frame.to_world(DVec3::new(x0, y, zc));
        let twist = Twist::new(
            centre,
            self.frame.x,
            Profile::local(0.0, x1 - x0, 0.0, angle)?,
        )?;
        let saved = self.saved();
        self.deform_shape(&twist);
        self.keep_if_finite(saved, "the twist")
    }

    /// Tapering (§4 (2), Fig. 9–10): the shape surface is narrowed along `z` about its
    /// middle line and the height surface sloped, both by the factor `r(x)` growing
    /// linearly from `start` at `u = 0` to `end` at `u = 1` (factors ≥ 0; 0 merges the
    /// border into its middle point, the paper's triangle). The object is scaled in `y`
    /// and `z` by `r(x)`: Barr's taper along `x`. Exact when both surfaces share degree and
    /// grid; otherwise the height surface follows at its Greville abscissae.
    pub fn taper(&mut self, start: f64, end: f64) -> Result<()> {
        for (name, r) in [("taper start", start), ("taper end", end)] {
            finite(name, r)?;
            if r < 0.0 {
                return Err(DeformError::InvalidParameter {
                    name,
                    reason: format!("{r} is negative"),
                });
            }
        }
        let saved = self.saved();
        let (x0, x1, _, zc) = self.footprint();
        let factor = |x: f64| start + (end - start) * (x - x0) / (x1 - x0);
        let frame = self.frame;
        // shape surface: z offsets from the middle line scaled by r at the rest x
        let [cu, cv] = self.shape.count();
        for i in 0..cu {
            for j in 0..cv {
                let k = i * cv + j;
                if self.pinned_shape[k] {
                    continue;
                }
                let r = factor(frame.to_local(self.shape_rest.control_points()[k]).x);
                let p = self.shape.control_points()[k];
                let dz = frame.to_local(p).z - zc;
                self.shape.control_points_mut()[k] = p + (r - 1.0) * dz * frame.z;
            }
        }
        // height surface: y scaled by r at the matching x
        let same_grid = self.height.count() == self.shape.count()
            && self.height.degree() == self.shape.degree();
        let [hu, hv] = self.height.count();
        let knots = self.height.knots(0);
        let hk = self.height.degree()[0];
        for i in 0..hu {
            let x = if same_grid {
                frame.to_local(self.shape_rest.control_points()[i * cv]).x
            } else {
                let greville = knots[i + 1..=i + hk].iter().sum::<f64>() / hk as f64;
                frame.to_local(self.shape_rest.evaluate(greville, 0.5)).x
            };
            let r = factor(x);
            for j in 0..hv {
                let k = i * hv + j;
                if self.pinned_height[k] {
                    continue;
                }
                let p = self.height.control_points()[k];
                let y = (p - frame.origin).dot(frame.y);
                self.height.control_points_mut()[k] = p + (r - 1.0) * y * frame.y;
            }
        }
        self.keep_if_finite(saved, "the taper")
    }

    /// The surfaces with pinned control points at their rest positions, as patches.
    fn effective_patches(&self) -> (Patches<DVec3>, Patches<f64>) {
        // (about the frame's origin, as the feet were found)
        let frame = self.frame;
        let shape: Vec<DVec3> = self
            .shape
            .control_points()
            .iter()
            .zip(self.shape_rest.control_points())
            .zip(&self.pinned_shape)
            .map(|((&p, &r), &fixed)| (if fixed { r } else { p }) - frame.origin)
            .collect();
        let height: Vec<f64> = self
            .height
            .control_points()
            .iter()
            .zip(self.height_rest.control_points())
            .zip(&self.pinned_height)
            .map(|((&p, &r), &fixed)| (if fixed { r } else { p } - frame.origin).dot(frame.y))
            .collect();
        (
            Patches::new(self.shape.degree(), self.shape.count(), &shape),
            Patches::new(self.height.degree(), self.height.count(), &height),
        )
    }

    /// Moves every attached vertex to `S_new(u, v) + H_new,y(u, v) · h · n_new(u, v)`
    /// (§3, Fig. 2), in parallel. Unattached vertices do not move.
    ///
    /// # Errors
    /// Nothing is changed on error: [`DeformError::Stale`] for another mesh (or this one at
    /// another hierarchy level or with other connectivity),
    /// [`DeformError::InvalidSurface`] when a control point written through
    /// [`BSplineSurface::control_points_mut`] is not finite, [`DeformError::Overflow`] when a
    /// deformed position would not be finite.
    pub fn deform(&self, mesh: &mut Mesh) -> Result<()> {
        self.binding.check(mesh, "the FFD attachment")?;
        for (surface, name) in [(&self.shape, "shape"), (&self.height, "height")] {
            if let Some(k) = surface.control_points().iter().position(|p| !p.is_finite()) {
                let [_, cv] = surface.count();
                return Err(DeformError::InvalidSurface {
                    surface: name,
                    problem: SurfaceProblem::NonFiniteControlPoint {
                        index: [k / cv, k % cv],
                        point: surface.control_points()[k],
                    },
                });
            }
        }
        let (shape, height) = self.effective_patches();
        let origin = self.frame.origin;
        // Computed apart and checked before any position is written.
        let new: Vec<DVec3> = mesh
            .positions()
            .par_iter()
            .zip(self.params.par_iter())
            .with_min_len(4096)
            .map(|(&p, &[u, v, h])| {
                if u.is_nan() {
                    return p;
                }
                let (s, s_s, s_t) = shape.first_local(u, v);
                let n = s_t.cross(s_s).normalize_or_zero();
                let hy = height.value(u, v);
                origin + (s + (hy * h) * n)
            })
            .collect();
        check_finite_positions("the deformation", &[], &new)?;
        mesh.positions_mut()
            .par_iter_mut()
            .zip(new.par_iter())
            .with_min_len(4096)
            .for_each(|(p, &q)| *p = q);
        Ok(())
    }
}

impl HierarchyEdit for Ffd {
    /// What [`deform`](Ffd::deform) means for a [`Hierarchy`](halfedge::hierarchy::Hierarchy)
    /// whose current level `mesh` is: its region is the attached vertices (the
    /// deformation's footprint), so that refined back only their fine vertices move; the
    /// deformation has no affine part.
    ///
    /// # Errors
    /// [`DeformError::Stale`] for another mesh (or this one at another hierarchy level or
    /// with other connectivity).
    fn hierarchy_marks(&self, mesh: &Mesh) -> std::result::Result<HierarchyMarks, Error> {
        self.binding
            .check(mesh, "the FFD attachment")
            .map_err(DeformError::from)?;
        let region = self
            .params
            .iter()
            .enumerate()
            .filter(|(_, p)| !p[0].is_nan())
            .filter_map(|(i, _)| mesh.vertex_at(i))
            .collect();
        let marks = HierarchyMarks::new(mesh, region, Vec::new()).map_err(DeformError::from)?;
        Ok(marks.bound_to(self.binding))
    }
}
