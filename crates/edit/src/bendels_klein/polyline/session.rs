//! The editing session on a polyline (Bendels & Klein, Secs. 2–6 on a curve): distances
//! once, then any number of handle transforms and shape functions.

use glam::{DMat4, DVec3};
use rayon::prelude::*;

use super::curve::{n_segments, segment, CurvePoint, Polyline};
use super::regions::CurveRegions;
use super::CurveResult;
use crate::bendels_klein::affine_power::AffinePower;
use crate::bendels_klein::distance::euclidean::{BorderGrid, QueryPoints};
use crate::bendels_klein::mesh::{blend_ratio, RefineOptions, RefineReport, MAX_NEW_VERTICES};
use crate::bendels_klein::regions::Role;
use crate::bendels_klein::shape::ShapeFunction;
use crate::EditError;

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
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PolylineOptions {
    /// The distances. Default: arc length.
    pub distance: CurveDistance,
    /// The shape function. Default: C¹ smoothstep.
    pub shape: ShapeFunction,
}

/// A Bendels & Klein editing session on a polyline (see the module docs of
/// [`crate::polyline`]). The session owns the edited points: [`PolylineSession::points`]
/// are the original points moved by the current transform, always computed from the
/// originals.
#[derive(Clone, Debug)]
pub struct PolylineSession<P: CurvePoint> {
    closed: bool,
    roles: Vec<Role>,
    original: Vec<P>,
    current: Vec<P>,
    d_handle: Vec<f64>,
    d_fixed: Vec<f64>,
    alpha: Vec<f64>,
    distance: CurveDistance,
    shape: ShapeFunction,
    transform: P::Affine,
    power: AffinePower,
    grids: Option<(BorderGrid, BorderGrid)>,
}

impl<P: CurvePoint> PolylineSession<P> {
    /// Sets up the session on `curve` with `regions`: computes both distance fields and
    /// the weights. The points start at their original positions.
    ///
    /// # Errors
    /// [`CurveError::Mismatch`](super::CurveError::Mismatch) when the regions were
    /// made for another polyline.
    pub fn new(
        curve: &Polyline<P>,
        regions: &CurveRegions,
        options: PolylineOptions,
    ) -> CurveResult<Self> {
        regions.check(curve)?;
        let original = curve.points().to_vec();
        let roles = regions.roles().to_vec();
        let closed = curve.is_closed();
        let (d_handle, d_fixed, grids) = distances(options.distance, &original, &roles, closed)?;
        let mut session = Self {
            closed,
            current: original.clone(),
            alpha: vec![0.0; original.len()],
            original,
            roles,
            d_handle,
            d_fixed,
            distance: options.distance,
            shape: options.shape,
            transform: P::identity(),
            power: AffinePower::from_log(DMat4::IDENTITY, DMat4::ZERO),
            grids,
        };
        session.update_alpha();
        Ok(session)
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
        &self.roles
    }
    /// Blend weights: 0 on the fixed part, 1 on the handle.
    #[must_use]
    pub fn alpha(&self) -> &[f64] {
        &self.alpha
    }
    /// Distances to the handle (0 on the handle; `∞` where the handle is out of reach,
    /// and on the fixed part).
    #[must_use]
    pub fn handle_distances(&self) -> &[f64] {
        &self.d_handle
    }
    /// Distances to the fixed part (0 on it; `∞` out of reach, and on the handle).
    #[must_use]
    pub fn fixed_distances(&self) -> &[f64] {
        &self.d_fixed
    }
    /// The current handle transform (the identity before the first edit).
    #[must_use]
    pub fn transform(&self) -> P::Affine {
        self.transform
    }
    /// The distance kind.
    #[must_use]
    pub fn distance_kind(&self) -> CurveDistance {
        self.distance
    }
    /// The shape function.
    #[must_use]
    pub fn shape(&self) -> &ShapeFunction {
        &self.shape
    }

    /// Applies the handle transform `a` (3×3 homogeneous in 2-D, 4×4 in 3-D): the
    /// handle to `A p`, each deformable point to `exp(α log A) p`, the fixed part not
    /// written. `log A` is computed once. On error nothing changes.
    ///
    /// # Errors
    /// [`CurveError::Edit`](super::CurveError::Edit) with
    /// [`EditError::NoRealLogarithm`] (a reflection, a singular map, a half turn),
    /// [`EditError::NotAffine`] or [`EditError::NonFiniteMatrix`];
    /// [`EditError::Overflow`] naming the first point that would leave the finite
    /// range (then nothing changes).
    pub fn apply(&mut self, a: P::Affine) -> CurveResult<()> {
        let power = AffinePower::new(P::embed(a))?;
        let old_power = std::mem::replace(&mut self.power, power);
        let old_transform = std::mem::replace(&mut self.transform, a);
        let saved = self.current.clone();
        self.write_all();
        if let Some(index) = self.current.iter().position(|p| !p.finite()) {
            self.current = saved;
            self.power = old_power;
            self.transform = old_transform;
            return Err(EditError::Overflow(format!(
                "point {index} would move to a non-finite position under {a:?}"
            ))
            .into());
        }
        Ok(())
    }

    /// Changes the shape function (the paper's Fig. 8): recomputes the weights and
    /// moves the points for the current transform.
    pub fn set_shape(&mut self, shape: ShapeFunction) {
        self.shape = shape;
        self.update_alpha();
        self.write_all();
    }

    /// Back to the identity transform: every point at its original position.
    pub fn reset(&mut self) {
        self.transform = P::identity();
        self.power = AffinePower::from_log(DMat4::IDENTITY, DMat4::ZERO);
        self.current.clone_from(&self.original);
    }

    fn update_alpha(&mut self) {
        let shape = &self.shape;
        let (roles, dh, df) = (&self.roles, &self.d_handle, &self.d_fixed);
        self.alpha
            .par_iter_mut()
            .enumerate()
            .with_min_len(4096)
            .for_each(|(i, a)| *a = weight(shape, roles[i], df[i], dh[i]));
    }

    fn write_all(&mut self) {
        let (power, transform) = (&self.power, &self.transform);
        self.current
            .par_iter_mut()
            .zip(self.original.par_iter())
            .zip(self.alpha.par_iter())
            .zip(self.roles.par_iter())
            .with_min_len(4096)
            .for_each(|(((c, &o), &alpha), &role)| match role {
                Role::Fixed => {}
                Role::Handle => *c = P::apply(transform, o),
                Role::Deformable => *c = P::blend(power, alpha, o),
            });
    }

    /// Deformed length of segment `(a, b)`.
    fn deformed_length(&self, a: usize, b: usize) -> f64 {
        self.current[a]
            .to_space()
            .distance(self.current[b].to_space())
    }

    fn touches_deformable(&self, a: usize, b: usize) -> bool {
        self.roles[a] == Role::Deformable || self.roles[b] == Role::Deformable
    }

    /// Refinement (Sec. 6 on a curve): while a segment with a deformable end is longer
    /// than `options.max_edge_length` after the edit, its original midpoint is inserted
    /// after its first point, joins the deformable part and is placed by the blend.
    /// Arc-length distances of the new points are exact (recomputed along the refined
    /// curve); Euclidean ones come from the distance grids. Points inserted shift the
    /// indices of the points after them.
    ///
    /// # Errors
    /// [`CurveError::Edit`](super::CurveError::Edit) with
    /// [`EditError::InvalidParameter`] for a threshold that is not finite and positive or
    /// a point budget above [`MAX_NEW_VERTICES`]; nothing changes then.
    pub fn refine(&mut self, options: RefineOptions) -> CurveResult<RefineReport> {
        let max = options.max_edge_length;
        if !(max.is_finite() && max > 0.0) {
            return Err(EditError::InvalidParameter {
                name: "max_edge_length",
                reason: format!("must be finite and positive, got {max}"),
            }
            .into());
        }
        if options.max_new_vertices > MAX_NEW_VERTICES {
            return Err(EditError::InvalidParameter {
                name: "max_new_vertices",
                reason: format!(
                    "{} is more than {MAX_NEW_VERTICES}",
                    options.max_new_vertices
                ),
            }
            .into());
        }
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
        for i in 0..n {
            original.push(self.original[i]);
            roles.push(self.roles[i]);
            fresh.push(false);
            d_handle.push(self.d_handle[i]);
            d_fixed.push(self.d_fixed[i]);
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
                let a = weight(&self.shape, Role::Deformable, d_fixed[i], d_handle[i]);
                alpha.push(a);
                current.push(P::blend(&self.power, a, original[i]));
            } else {
                alpha.push(self.alpha[old]);
                current.push(self.current[old]);
                old += 1;
            }
        }
        self.original = original;
        self.roles = roles;
        self.d_handle = d_handle;
        self.d_fixed = d_fixed;
        self.alpha = alpha;
        self.current = current;
    }
}

#[inline]
fn weight(shape: &ShapeFunction, role: Role, d_fixed: f64, d_handle: f64) -> f64 {
    match role {
        Role::Fixed => 0.0,
        Role::Handle => 1.0,
        Role::Deformable => shape.eval(blend_ratio(d_fixed, d_handle)),
    }
}

type Fields = (Vec<f64>, Vec<f64>, Option<(BorderGrid, BorderGrid)>);

/// Both distance fields of a polyline: `(d_handle, d_fixed, grids)`.
fn distances<P: CurvePoint>(
    kind: CurveDistance,
    points: &[P],
    roles: &[Role],
    closed: bool,
) -> CurveResult<Fields> {
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
