//! The editing session on a polyline (Bendels & Klein, Secs. 2–6 on a curve): distances
//! once, then any number of handle transforms and shape functions.

use glam::DVec3;
use rayon::prelude::*;

use crate::bendels_klein::blend::{BlendCore, BlendPoint, RefineOptions, RefineReport};
use crate::bendels_klein::distance::euclidean::{BorderGrid, QueryPoints};
use crate::bendels_klein::error::{BendelsKleinError, Result, Site};
use crate::bendels_klein::polyline::curve::{n_segments, segment, Polyline};
use crate::bendels_klein::polyline::regions::CurveRegions;
use crate::bendels_klein::regions::Role;
use crate::bendels_klein::shape::ShapeFunction;

/// Which distance the weights of a polyline edit are built on (Bendels & Klein, Sec. 4,
/// Fig. 3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CurveDistance {
    /// Arc length along the curve through the deformable part, the geodesic distance of
    /// a curve: α grows monotonically from the fixed part to the handle (Fig. 3 b).
    #[default]
    ArcLength,
    /// Euclidean distance to the handle part and to the fixed part (their points and
    /// segments, eq. 1–2): a space deformation; α may go up and down along a curve that
    /// turns back (Fig. 3 a).
    Euclidean,
}

/// Options of a [`PolylineSession`].
///
/// Paper: Bendels & Klein 2003, *Image and 3D-object editing with precisely specified
/// editing regions*, Secs. 4–5 and Fig. 3.
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct PolylineOptions {
    /// The distances. Default: arc length.
    pub distance: CurveDistance,
    /// The shape function. Default: C¹ smoothstep.
    pub shape: ShapeFunction,
}

impl PolylineOptions {
    /// The same options with the distances set to `distance`.
    #[must_use]
    pub fn with_distance(mut self, distance: CurveDistance) -> Self {
        self.distance = distance;
        self
    }

    /// The same options with the shape function set to `shape`.
    #[must_use]
    pub fn with_shape(mut self, shape: ShapeFunction) -> Self {
        self.shape = shape;
        self
    }
}

/// A Bendels & Klein editing session on a polyline (see [the polyline module](super)). The
/// session owns the edited points: [`PolylineSession::points`] are the original points
/// moved by the current transform, always computed from the originals.
#[derive(Clone, Debug)]
pub struct PolylineSession<P: BlendPoint> {
    closed: bool,
    original: Vec<P>,
    current: Vec<P>,
    /// Roles, distances, weights, shape function and transform (shared with the mesh and
    /// picture sessions).
    core: BlendCore<P>,
    distance: CurveDistance,
    grids: Option<(BorderGrid, BorderGrid)>,
}

impl<P: BlendPoint> PolylineSession<P> {
    /// Sets up the session on `curve` with `regions`: computes both distance fields and
    /// the weights. The points start at their original positions.
    ///
    /// # Errors
    /// [`BendelsKleinError::Stale`] when the regions were made for another polyline (even
    /// one of the same length), or for this one before a point was inserted.
    pub fn new(
        curve: &Polyline<P>,
        regions: &CurveRegions,
        options: PolylineOptions,
    ) -> Result<Self> {
        regions.check(curve)?;
        let original = curve.points().to_vec();
        let roles = regions.roles().to_vec();
        let closed = curve.is_closed();
        let (d_handle, d_fixed, grids) = distances(options.distance, &original, &roles, closed)?;
        let alpha = vec![0.0; original.len()];
        Ok(Self {
            closed,
            current: original.clone(),
            original,
            core: BlendCore::new(roles, d_handle, d_fixed, alpha, options.shape),
            distance: options.distance,
            grids,
        })
    }

    /// The edited points.
    #[must_use]
    pub fn points(&self) -> &[P] {
        &self.current
    }
    /// The edited polyline (a copy of the points).
    #[must_use]
    pub fn polyline(&self) -> Polyline<P> {
        Polyline::from_parts(self.current.clone(), self.closed)
    }
    /// The original points (with the points refinement inserted).
    #[must_use]
    pub fn original_points(&self) -> &[P] {
        &self.original
    }
    /// The role of every point.
    #[must_use]
    pub fn roles(&self) -> &[Role] {
        self.core.roles()
    }
    /// Blend weights: 0 on the fixed part, 1 on the handle.
    #[must_use]
    pub fn alpha(&self) -> &[f64] {
        self.core.alpha()
    }
    /// Distances to the handle (0 on the handle; `∞` where the handle is out of reach,
    /// and on the fixed part).
    #[must_use]
    pub fn handle_distances(&self) -> &[f64] {
        self.core.handle_distances()
    }
    /// Distances to the fixed part (0 on it; `∞` out of reach, and on the handle).
    #[must_use]
    pub fn fixed_distances(&self) -> &[f64] {
        self.core.fixed_distances()
    }
    /// The current handle transform (the identity before the first edit).
    #[must_use]
    pub fn transform(&self) -> P::Affine {
        self.core.transform()
    }
    /// The distance kind.
    #[must_use]
    pub fn distance_kind(&self) -> CurveDistance {
        self.distance
    }
    /// The shape function.
    #[must_use]
    pub fn shape(&self) -> &ShapeFunction {
        self.core.shape()
    }

    /// Applies the handle transform `a` (3×3 homogeneous in 2-D, 4×4 in 3-D): the
    /// handle to `A p`, each deformable point to `exp(α log A) p`, the fixed part not
    /// written. `log A` is computed once. On error nothing changes.
    ///
    /// # Errors
    /// [`BendelsKleinError::NoRealLogarithm`] (a reflection, a singular map, a half
    /// turn), [`BendelsKleinError::NotAffine`] or [`BendelsKleinError::NonFiniteMatrix`];
    /// [`BendelsKleinError::Overflow`] naming the first point that would leave the finite
    /// range (then nothing changes).
    pub fn apply(&mut self, a: P::Affine) -> Result<()> {
        let previous = self.core.set_transform(a)?;
        let saved = self.current.clone();
        self.write_all();
        if let Some(index) = self.current.iter().position(|p| !p.finite()) {
            let position = self.current[index].to_space();
            self.current = saved;
            self.core.restore(previous);
            return Err(BendelsKleinError::Overflow {
                what: "the blended transform",
                site: Site::Point(index),
                position,
            });
        }
        Ok(())
    }

    /// Changes the shape function (the paper's Fig. 8): recomputes the weights and
    /// moves the points for the current transform.
    pub fn set_shape(&mut self, shape: ShapeFunction) {
        self.core.set_shape(shape);
        self.write_all();
    }

    /// Back to the identity transform: every point at its original position.
    pub fn reset(&mut self) {
        self.core.reset_transform();
        self.current.clone_from(&self.original);
    }

    /// Moves every point from its original by the blend; the fixed part is not written.
    fn write_all(&mut self) {
        let core = &self.core;
        self.current
            .par_iter_mut()
            .zip(self.original.par_iter())
            .zip(core.alpha().par_iter())
            .zip(core.roles().par_iter())
            .with_min_len(4096)
            .for_each(|(((c, &o), &alpha), &role)| {
                if role != Role::Fixed {
                    *c = core.place(role, alpha, o);
                }
            });
    }

    /// Deformed length of segment `(a, b)`.
    fn deformed_length(&self, a: usize, b: usize) -> f64 {
        self.current[a]
            .to_space()
            .distance(self.current[b].to_space())
    }

    fn touches_deformable(&self, a: usize, b: usize) -> bool {
        let roles = self.core.roles();
        roles[a] == Role::Deformable || roles[b] == Role::Deformable
    }

    /// Refinement (Sec. 6 on a curve): while a segment with a deformable end is longer
    /// than `options.max_edge_length` after the edit, its original midpoint is inserted
    /// after its first point, joins the deformable part and is placed by the blend.
    /// Arc-length distances of the new points are exact (recomputed along the refined
    /// curve); Euclidean ones come from the distance grids. Points inserted shift the
    /// indices of the points after them.
    ///
    /// # Errors
    /// [`BendelsKleinError::InvalidParameter`] for a threshold that is not finite and
    /// positive or a point budget above
    /// [`MAX_NEW_VERTICES`](crate::bendels_klein::MAX_NEW_VERTICES); nothing changes then.
    pub fn refine(&mut self, options: RefineOptions) -> Result<RefineReport> {
        options.check()?;
        let max = options.max_edge_length;
        let mut report = RefineReport::default();
        while report.passes < 64 && report.new_vertices < options.max_new_vertices {
            let n = self.original.len();
            let budget = options.max_new_vertices - report.new_vertices;
            let split: Vec<bool> = {
                let mut left = budget;
                (0..n_segments(n, self.closed))
                    .map(|k| {
                        let (a, b) = segment(k, n);
                        let long = left > 0
                            && self.touches_deformable(a, b)
                            && self.deformed_length(a, b) > max;
                        left -= usize::from(long);
                        long
                    })
                    .collect()
            };
            let added = split.iter().filter(|&&s| s).count();
            if added == 0 {
                break;
            }
            report.passes += 1;
            report.new_vertices += added;
            self.insert_midpoints(&split, added);
        }
        let n = self.original.len();
        report.longest_edge = (0..n_segments(n, self.closed))
            .map(|k| segment(k, n))
            .filter(|&(a, b)| self.touches_deformable(a, b))
            .map(|(a, b)| self.deformed_length(a, b))
            .fold(0.0, f64::max);
        Ok(report)
    }

    /// Inserts the original midpoint of every segment `k` with `split[k]`.
    fn insert_midpoints(&mut self, split: &[bool], added: usize) {
        let n = self.original.len();
        let m = n + added;
        let mut original = Vec::with_capacity(m);
        let mut roles = Vec::with_capacity(m);
        let mut fresh = Vec::with_capacity(m);
        let mut d_handle = Vec::with_capacity(m);
        let mut d_fixed = Vec::with_capacity(m);
        let core = &self.core;
        for i in 0..n {
            original.push(self.original[i]);
            roles.push(core.roles()[i]);
            fresh.push(false);
            d_handle.push(core.handle_distances()[i]);
            d_fixed.push(core.fixed_distances()[i]);
            if split.get(i).copied().unwrap_or(false) {
                let (a, b) = segment(i, n);
                original.push(self.original[a].midpoint(self.original[b]));
                roles.push(Role::Deformable);
                fresh.push(true);
                d_handle.push(f64::INFINITY);
                d_fixed.push(f64::INFINITY);
            }
        }
        match (&self.grids, self.distance) {
            (Some((handle, fixed)), _) => {
                let values: Vec<(usize, f64, f64)> = (0..m)
                    .into_par_iter()
                    .filter(|&i| fresh[i])
                    .map(|i| {
                        let p = original[i].to_space();
                        (i, handle.distance(p), fixed.distance(p))
                    })
                    .collect();
                for (i, h, f) in values {
                    d_handle[i] = h;
                    d_fixed[i] = f;
                }
            }
            _ => {
                // Exact along the refined curve; only the new points take the values, so
                // the old points keep theirs bit for bit.
                let space: Vec<DVec3> = original.iter().map(|p| p.to_space()).collect();
                let (h, f) = arc_distances(&space, &roles, self.closed);
                for i in (0..m).filter(|&i| fresh[i]) {
                    d_handle[i] = h[i];
                    d_fixed[i] = f[i];
                }
            }
        }
        let mut alpha = Vec::with_capacity(m);
        let mut current = Vec::with_capacity(m);
        let mut old = 0;
        for i in 0..m {
            if fresh[i] {
                let a = core.weight(Role::Deformable, d_fixed[i], d_handle[i]);
                alpha.push(a);
                current.push(core.place(Role::Deformable, a, original[i]));
            } else {
                alpha.push(core.alpha()[old]);
                current.push(self.current[old]);
                old += 1;
            }
        }
        self.original = original;
        self.core.replace_fields(roles, d_handle, d_fixed, alpha);
        self.current = current;
    }
}

type Fields = (Vec<f64>, Vec<f64>, Option<(BorderGrid, BorderGrid)>);

/// Both distance fields of a polyline: `(d_handle, d_fixed, grids)`.
fn distances<P: BlendPoint>(
    kind: CurveDistance,
    points: &[P],
    roles: &[Role],
    closed: bool,
) -> Result<Fields> {
    let space: Vec<DVec3> = points.iter().map(|p| p.to_space()).collect();
    match kind {
        CurveDistance::ArcLength => {
            let (h, f) = arc_distances(&space, roles, closed);
            Ok((h, f, None))
        }
        CurveDistance::Euclidean => {
            let n = space.len();
            let segments = n_segments(n, closed);
            let total: f64 = (0..segments)
                .map(|k| {
                    let (a, b) = segment(k, n);
                    space[a].distance(space[b])
                })
                .sum();
            let cell = 2.0 * total / segments.max(1) as f64;
            let cell = if cell.is_finite() && cell > 0.0 {
                cell
            } else {
                1.0
            };
            let part = |role: Role| -> Vec<(DVec3, DVec3)> {
                let mut list = Vec::new();
                for i in 0..n {
                    if roles[i] != role {
                        continue;
                    }
                    // The segment to the next point when it is of the same part; a
                    // point with no such neighbour on either side stands alone.
                    let next = (i + 1 < n || closed).then(|| (i + 1) % n);
                    let prev = (i > 0 || closed).then(|| (i + n - 1) % n);
                    let joins = |j: Option<usize>| j.is_some_and(|j| j != i && roles[j] == role);
                    if joins(next) {
                        list.push((space[i], space[(i + 1) % n]));
                    } else if !joins(prev) {
                        list.push((space[i], space[i]));
                    }
                }
                list
            };
            let handle = BorderGrid::from_segments(cell, part(Role::Handle))?;
            let fixed = BorderGrid::from_segments(cell, part(Role::Fixed))?;
            let indices: Vec<usize> = (0..n).filter(|&i| roles[i] == Role::Deformable).collect();
            let queries: Vec<DVec3> = indices.iter().map(|&i| space[i]).collect();
            let (h, f) = handle.distances_to_pair(&fixed, &QueryPoints::new(&queries, cell));
            let mut d_handle = vec![f64::INFINITY; n];
            let mut d_fixed = vec![f64::INFINITY; n];
            for (k, &i) in indices.iter().enumerate() {
                d_handle[i] = h[k];
                d_fixed[i] = f[k];
            }
            for (i, role) in roles.iter().enumerate() {
                match role {
                    Role::Handle => d_handle[i] = 0.0,
                    Role::Fixed => d_fixed[i] = 0.0,
                    Role::Deformable => {}
                }
            }
            Ok((d_handle, d_fixed, Some((handle, fixed))))
        }
    }
}

/// Arc-length distances of every deformable point to the handle and to the fixed part,
/// along the curve through deformable points only (the geodesic distance of a curve):
/// two sweeps, forward and backward, each carrying the distance from the last handle or
/// fixed point passed. `∞` where a part is out of reach; 0 on the part itself.
pub(crate) fn arc_distances(
    points: &[DVec3],
    roles: &[Role],
    closed: bool,
) -> (Vec<f64>, Vec<f64>) {
    let n = points.len();
    let mut d_handle = vec![f64::INFINITY; n];
    let mut d_fixed = vec![f64::INFINITY; n];
    for (i, role) in roles.iter().enumerate() {
        match role {
            Role::Handle => d_handle[i] = 0.0,
            Role::Fixed => d_fixed[i] = 0.0,
            Role::Deformable => {}
        }
    }
    // A closed polygon is swept from one of its handle or fixed points, once around.
    let start = if closed {
        roles
            .iter()
            .position(|&r| r != Role::Deformable)
            .unwrap_or(0)
    } else {
        0
    };
    for forward in [true, false] {
        let index = |k: usize| match (closed, forward) {
            (false, true) => k,
            (false, false) => n - 1 - k,
            (true, true) => (start + k) % n,
            (true, false) => (start + n - k) % n,
        };
        let mut anchor: Option<Role> = None;
        let mut dist = 0.0;
        let mut prev: Option<usize> = None;
        for k in 0..n {
            let i = index(k);
            if roles[i] == Role::Deformable {
                if let Some(p) = prev {
                    dist += points[p].distance(points[i]);
                }
                match anchor {
                    Some(Role::Handle) => d_handle[i] = d_handle[i].min(dist),
                    Some(Role::Fixed) => d_fixed[i] = d_fixed[i].min(dist),
                    _ => {}
                }
            } else {
                anchor = Some(roles[i]);
                dist = 0.0;
            }
            prev = Some(i);
        }
    }
    (d_handle, d_fixed)
}
