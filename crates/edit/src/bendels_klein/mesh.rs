//! The Bendels & Klein editing session on a mesh, with adaptive refinement (Secs. 3–6).

use glam::{DMat4, DVec3};
use halfedge::hierarchy::Hierarchy;
use halfedge::{Mesh, VertexData, VertexId};
use rayon::prelude::*;

use crate::bendels_klein::blend::{BlendCore, RefineOptions, RefineReport};
use crate::bendels_klein::distance::euclidean::{BorderGrid, QueryPoints};
use crate::bendels_klein::distance::geodesic::{FastMarching, MarchSource};
use crate::bendels_klein::error::{BendelsKleinError, Result, Site};
use crate::bendels_klein::regions::{Regions, Role};
use crate::bendels_klein::shape::ShapeFunction;
use crate::error::Error;
use crate::hierarchy_edit::{HierarchyEdit, HierarchyMarks};
use crate::vertices::{first_non_finite, scatter};

/// Which distance the blend weights are built on (Bendels & Klein, Sec. 4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DistanceKind {
    /// Distance in space to the border polylines: behaves like a space deformation.
    Euclidean,
    /// Distance on the surface (fast marching within the deformable area): behaves like
    /// spline editing; α grows monotonically along the surface (the paper's Fig. 3).
    #[default]
    Geodesic,
}

/// Options of a [`BlendSession`].
///
/// Paper: Bendels & Klein 2003, *Image and 3D-object editing with precisely specified
/// editing regions*, Secs. 4–5.
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct BlendOptions {
    /// The distance fields. Default: geodesic.
    pub distance: DistanceKind,
    /// The shape function. Default: C¹ smoothstep.
    pub shape: ShapeFunction,
}

impl BlendOptions {
    /// The same options with the distance fields set to `distance`.
    #[must_use]
    pub fn with_distance(mut self, distance: DistanceKind) -> Self {
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

/// The editing session of Bendels & Klein, *Image and 3D-object editing with precisely
/// specified editing regions*: set the regions once, compute the two distance fields
/// once, then apply any number of handle transforms and shape functions interactively.
///
/// For a deformable vertex `i` with distances `d_fixed` and `d_handle` to the two
/// borders (Sec. 4), `α_i = f(d_fixed / (d_fixed + d_handle))` with the shape function
/// `f` (Sec. 5), and the vertex moves to `(α_i ⊙ A) p_i = exp(α_i log A) p_i` (Sec. 3,
/// after Alexa 2002), always from its *original* position `p_i`. The handle moves to
/// `A p_i`, the fixed area never moves (its positions are not even written, so they stay
/// bit for bit). An edit computes `log A` once ([`AffinePower`](super::affine_power::AffinePower)) and transforms the
/// vertices in parallel; a change of shape function recomputes the α only.
///
/// Degenerate distances: a vertex that only the handle reaches (`d_fixed = ∞`) follows
/// the handle (α = 1), one that only the fixed area reaches stays (α = 0), one neither
/// reaches (or at distance 0 from both) stays too.
///
/// **Adaptive refinement** (Sec. 6, after *Mesh forging*): where the deformation
/// stretched triangles of the deformable area, [`BlendSession::refine`] splits every
/// edge longer than a threshold, longest first (Rivara's longest-edge bisection; each
/// split cuts both triangles of the edge, so the mesh stays conforming and passes
/// `check()`). The new vertex sits at the midpoint of the *original* edge; its distance
/// to each border comes from a *virtual origin* at the intersection of the spheres of
/// radii δ₀, δ₁ around the edge's ends: for the midpoint, which lies on the axis of the
/// intersection circle, that is `√((δ₀² + δ₁²)/2 − L²/4)` (at least `|δ₀ − δ₁|/2`).
/// That point model is exact for fronts from a point, but far off next to a straight
/// border: an edge parallel to the border at distance `d ≤ L/2` gets 0. The geodesic
/// fields therefore carry the front radius `R` the march reached each vertex with (0
/// from a point, `∞` from a border curve, see `distance::geodesic`), and the virtual
/// origin becomes the centre of a source circle of radius `R`: spheres of radii
/// `δ₀ + R`, `δ₁ + R`, distance `√(((δ₀+R)² + (δ₁+R)²)/2 − L²/4) − R`. `R = 0` is the
/// paper's formula; `R → ∞` tends to `(δ₀ + δ₁)/2`, exact for straight fronts. With
/// Euclidean fields the exact distance is cheap instead (one grid query per new vertex)
/// and is used. The new vertex is then placed by the blend like every other.
///
/// An editing session with precisely specified regions on a mesh.
#[derive(Clone, Debug)]
pub struct BlendSession {
    regions: Regions,
    distance: DistanceKind,
    original: VertexData<DVec3>,
    /// Roles, distances, weights, shape function and transform (shared with the polyline
    /// and picture sessions).
    core: BlendCore<DVec3, VertexData<f64>>,
    /// Front radii of the geodesic fields (handle, fixed); `∞` for Euclidean fields.
    r_handle: VertexData<f64>,
    r_fixed: VertexData<f64>,
    /// The largest coordinate magnitude of the original positions of non-fixed vertices
    /// (at least 1; `∞` when one is not finite).
    extent: f64,
    grids: Option<(BorderGrid, BorderGrid)>,
    /// The mesh the session was made on (see [`halfedge::Binding`]).
    binding: halfedge::Binding,
}

impl BlendSession {
    /// Sets up the session: records the original positions and computes both distance
    /// fields and the blend weights. The mesh is not changed.
    ///
    /// # Errors
    /// [`BendelsKleinError::Stale`] when `regions` were made for another mesh (even one
    /// with as many vertices), or for this one before a change of connectivity.
    pub fn new(mesh: &Mesh, regions: Regions, options: BlendOptions) -> Result<Self> {
        regions.binding().check(mesh, "the regions")?;
        let slots = mesh.vertex_slots();
        let original = VertexData::new(mesh, mesh.positions().to_vec())?;
        // Distances are wanted on the deformable area and on both borders (refinement
        // interpolates them along edges that end on a border).
        let mut wanted = vec![false; slots];
        for &v in regions.deformable() {
            wanted[mesh.vertex_index(v)] = true;
        }
        for &v in regions
            .handle_border()
            .vertices
            .iter()
            .chain(&regions.fixed_border().vertices)
        {
            wanted[mesh.vertex_index(v)] = true;
        }
        let (mut d_handle, mut d_fixed, r_handle, r_fixed, grids) = match options.distance {
            DistanceKind::Euclidean => {
                let cell = 2.0 * mesh.mean_edge_length();
                let cell = if cell > 0.0 && cell.is_finite() {
                    cell
                } else {
                    1.0
                };
                let segments = |edges: &[(VertexId, VertexId)]| {
                    edges
                        .iter()
                        .map(|&(a, b)| (mesh.position(a), mesh.position(b)))
                        .collect::<Vec<_>>()
                };
                let handle_grid =
                    BorderGrid::from_segments(cell, segments(&regions.handle_border().edges))?;
                let fixed_grid =
                    BorderGrid::from_segments(cell, segments(&regions.fixed_border().edges))?;
                let indices: Vec<usize> = (0..slots).filter(|&i| wanted[i]).collect();
                let points: Vec<DVec3> = indices.iter().map(|&i| original[i]).collect();
                let queries = QueryPoints::new(&points, cell);
                let (dh, df) = handle_grid.distances_to_pair(&fixed_grid, &queries);
                let mut d_handle = vec![f64::INFINITY; slots];
                let mut d_fixed = vec![f64::INFINITY; slots];
                for (k, &i) in indices.iter().enumerate() {
                    d_handle[i] = dh[k];
                    d_fixed[i] = df[k];
                }
                let infinite = VertexData::filled(mesh, f64::INFINITY);
                (
                    VertexData::new(mesh, d_handle)?,
                    VertexData::new(mesh, d_fixed)?,
                    infinite.clone(),
                    infinite,
                    Some((handle_grid, fixed_grid)),
                )
            }
            DistanceKind::Geodesic => {
                // The marches run within `wanted`: the solver needs no stencils beyond it.
                let wanted = VertexData::new(mesh, wanted)?;
                let marching = FastMarching::within(mesh, &wanted)?;
                // A border of one vertex is a point source; longer borders are curves
                // (locally straight fronts, see `distance::geodesic`).
                let sources = |vs: &[VertexId]| {
                    vs.iter()
                        .map(|&v| {
                            if vs.len() == 1 {
                                MarchSource::point(mesh.vertex_index(v))
                            } else {
                                MarchSource::on_curve(mesh.vertex_index(v))
                            }
                        })
                        .collect::<Vec<_>>()
                };
                let (d_handle, r_handle) = marching.distances_and_radii(
                    &sources(&regions.handle_border().vertices),
                    Some(&wanted),
                )?;
                let (d_fixed, r_fixed) = marching.distances_and_radii(
                    &sources(&regions.fixed_border().vertices),
                    Some(&wanted),
                )?;
                (d_handle, d_fixed, r_handle, r_fixed, None)
            }
        };
        let extent = original
            .iter()
            .zip(regions.roles())
            .filter(|(_, &role)| role != Role::Fixed)
            .map(|(p, _)| magnitude(*p))
            .fold(1.0, f64::max);
        // Exact zeros on the borders themselves.
        for (i, role) in regions.roles().iter().enumerate() {
            match role {
                Role::Handle => d_handle[i] = 0.0,
                Role::Fixed => d_fixed[i] = 0.0,
                Role::Deformable => {}
            }
        }
        let core = BlendCore::new(
            regions.roles().to_vec(),
            d_handle,
            d_fixed,
            VertexData::filled(mesh, 0.0),
            options.shape,
        );
        Ok(Self {
            binding: mesh.binding(),
            extent,
            regions,
            distance: options.distance,
            original,
            core,
            r_handle,
            r_fixed,
            grids,
        })
    }

    /// The regions.
    #[must_use]
    pub fn regions(&self) -> &Regions {
        &self.regions
    }
    /// The distance kind.
    #[must_use]
    pub fn distance_kind(&self) -> DistanceKind {
        self.distance
    }
    /// The shape function.
    #[must_use]
    pub fn shape(&self) -> &ShapeFunction {
        self.core.shape()
    }
    /// The current handle transform (identity before the first edit), with its bottom
    /// row exactly `(0, 0, 0, 1)`.
    #[must_use]
    pub fn transform(&self) -> DMat4 {
        self.core.power().transform()
    }
    /// Blend weights by vertex index: 0 on the fixed area, 1 on the handle; bound to
    /// the mesh the session edits.
    #[must_use]
    pub fn alpha(&self) -> &VertexData<f64> {
        self.core.alpha()
    }
    /// Distances to the handle border by vertex index (`∞` off the deformable area and
    /// its borders).
    #[must_use]
    pub fn handle_distances(&self) -> &VertexData<f64> {
        self.core.handle_distances()
    }
    /// Distances to the fixed border by vertex index.
    #[must_use]
    pub fn fixed_distances(&self) -> &VertexData<f64> {
        self.core.fixed_distances()
    }
    /// Original (undeformed) positions by vertex index.
    #[must_use]
    pub fn original_positions(&self) -> &VertexData<DVec3> {
        &self.original
    }

    /// Changes the shape function and recomputes the weights (the paper's Fig. 8). Call
    /// [`BlendSession::reapply`] to see it on the mesh.
    pub fn set_shape(&mut self, shape: ShapeFunction) {
        self.core.set_shape(shape);
    }

    /// Fails unless `mesh` is the mesh the session was made on, at the same hierarchy
    /// level and with the same connectivity (see [`halfedge::Binding`]).
    fn check_mesh(&self, mesh: &Mesh) -> Result<()> {
        Ok(self.binding.check(mesh, "the blend session")?)
    }

    /// Applies the handle transform `a`: the handle to `A p`, each deformable vertex to
    /// `(α ⊙ A) p`, from the original positions. Computes `log A` once. On error the
    /// mesh is unchanged.
    ///
    /// # Errors
    /// [`BendelsKleinError::Stale`] for another mesh (or this one at another level); the errors of
    /// [`AffinePower::new`](super::affine_power::AffinePower::new) (no real logarithm, not affine, not finite);
    /// [`BendelsKleinError::Overflow`] when a moved vertex would not land on a finite position
    /// (a translation of 1e308). The mesh and the session's transform are unchanged on
    /// error.
    pub fn apply(&mut self, mesh: &mut Mesh, a: DMat4) -> Result<()> {
        self.check_mesh(mesh)?;
        let previous = self.core.set_transform(a)?;
        let written = self.write(mesh);
        if written.is_err() {
            self.core.restore(previous);
        }
        written
    }

    /// Applies the current transform again (after [`BlendSession::set_shape`]).
    ///
    /// # Errors
    /// [`BendelsKleinError::Stale`] for another mesh (or this one at another level); [`BendelsKleinError::Overflow`] as
    /// [`apply`](Self::apply) (the mesh is unchanged on error).
    pub fn reapply(&self, mesh: &mut Mesh) -> Result<()> {
        self.check_mesh(mesh)?;
        self.write(mesh)
    }

    /// Puts the handle and the deformable area back at their original positions.
    ///
    /// # Errors
    /// [`BendelsKleinError::Stale`] for another mesh (or this one at another level).
    pub fn reset(&self, mesh: &mut Mesh) -> Result<()> {
        self.check_mesh(mesh)?;
        let roles = self.core.roles();
        mesh.positions_mut()
            .par_iter_mut()
            .zip(self.original.par_iter())
            .enumerate()
            .with_min_len(4096)
            .for_each(|(i, (p, &o))| {
                if roles[i] != Role::Fixed {
                    *p = o;
                }
            });
        Ok(())
    }

    /// True when no written position can overflow: for α ∈ [0, 1],
    /// `‖exp(α L)‖∞ ≤ exp(‖L‖∞)`, so every coordinate of `(α ⊙ A) p` is at most
    /// `exp(‖L‖∞) · max(‖p‖∞, 1)`; with that far below `f64::MAX` (and finite original
    /// positions) the positions are written without a check.
    fn cannot_overflow(&self) -> bool {
        let l = self.core.power().log();
        let norm = (0..3)
            .map(|r| l.row(r).abs().element_sum())
            .fold(0.0, f64::max);
        self.core.alphas_in_unit() && norm < 600.0 && norm.exp() * self.extent < 1e300
    }

    /// Writes `(α ⊙ A) p` for every non-fixed vertex from its original position; when
    /// that could overflow, the positions are computed apart and checked first
    /// ([`BendelsKleinError::Overflow`], nothing written).
    fn write(&self, mesh: &mut Mesh) -> Result<()> {
        let core = &self.core;
        let roles = core.roles();
        if !self.cannot_overflow() {
            let indices: Vec<u32> = (0..roles.len() as u32)
                .filter(|&i| roles[i as usize] != Role::Fixed)
                .collect();
            let new: Vec<DVec3> = indices
                .par_iter()
                .map(|&i| core.place_index(i as usize, self.original[i as usize]))
                .collect();
            if let Some((slot, position)) = first_non_finite(&indices, &new) {
                let vertex = mesh.vertex_at(slot).expect("a moving vertex is live");
                return Err(BendelsKleinError::Overflow {
                    what: "the blended transform",
                    site: Site::Vertex(vertex),
                    position,
                });
            }
            scatter(mesh.positions_mut(), &indices, &new);
            return Ok(());
        }
        mesh.positions_mut()
            .par_iter_mut()
            .zip(self.original.par_iter())
            .zip(core.alpha().par_iter())
            .zip(roles.par_iter())
            .with_min_len(4096)
            .for_each(|(((p, &o), &alpha), &role)| {
                if role != Role::Fixed {
                    *p = core.place(role, alpha, o);
                }
            });
        Ok(())
    }

    /// Adaptive refinement of the deformable area (Sec. 6): splits, longest first, every
    /// edge with a deformable end whose current (deformed) length exceeds
    /// `options.max_edge_length`, until none does or the vertex budget is spent. New
    /// vertices join the deformable area with distances from the virtual origin (see
    /// [`BlendSession`]) and are placed by the current blend. The mesh passes `check()`.
    /// On the mesh of a [`Hierarchy`], whose records cannot take new vertices at a
    /// coarse level, use [`refine_in_hierarchy`](Self::refine_in_hierarchy).
    ///
    /// # Errors
    /// [`BendelsKleinError::Stale`] for another mesh (or this one at another level); [`BendelsKleinError::InvalidParameter`]
    /// for a threshold that is not finite and positive or a vertex budget above
    /// [`MAX_NEW_VERTICES`](super::MAX_NEW_VERTICES). An edge whose split point would not be finite is left
    /// alone.
    pub fn refine(&mut self, mesh: &mut Mesh, options: RefineOptions) -> Result<RefineReport> {
        self.check_mesh(mesh)?;
        options.check()?;
        let max = options.max_edge_length;
        let mut report = RefineReport::default();
        loop {
            let roles = self.core.roles();
            let mut long: Vec<(f64, halfedge::HalfedgeId)> = mesh
                .edges()
                .filter(|&h| {
                    roles[mesh.vertex_index(mesh.from_vertex(h))] == Role::Deformable
                        || roles[mesh.vertex_index(mesh.to_vertex(h))] == Role::Deformable
                })
                .map(|h| (mesh.edge_length(h), h))
                .filter(|&(l, _)| l > max)
                .collect();
            if long.is_empty() || report.new_vertices >= options.max_new_vertices {
                break;
            }
            report.passes += 1;
            long.sort_by(|a, b| b.0.total_cmp(&a.0));
            for (_, h) in long {
                if report.new_vertices >= options.max_new_vertices {
                    break;
                }
                // Earlier splits of this pass may have shortened or moved this edge.
                if mesh.edge_length(h) <= max {
                    continue;
                }
                let (a, b) = (mesh.from_vertex(h), mesh.to_vertex(h));
                let (ia, ib) = (mesh.vertex_index(a), mesh.vertex_index(b));
                let roles = self.core.roles();
                if roles[ia] != Role::Deformable && roles[ib] != Role::Deformable {
                    continue;
                }
                if self.split(mesh, h, ia, ib) {
                    report.new_vertices += 1;
                }
            }
            if report.passes >= 64 {
                break;
            }
        }
        // The session follows its own new vertices.
        self.rebind(mesh);
        let roles = self.core.roles();
        report.longest_edge = mesh
            .edges()
            .filter(|&h| {
                roles[mesh.vertex_index(mesh.from_vertex(h))] == Role::Deformable
                    || roles[mesh.vertex_index(mesh.to_vertex(h))] == Role::Deformable
            })
            .map(|h| mesh.edge_length(h))
            .fold(0.0, f64::max);
        Ok(report)
    }

    /// The marks of the session's current edit (see its [`HierarchyEdit`] impl).
    fn marks(&self, mesh: &Mesh) -> Result<HierarchyMarks> {
        self.check_mesh(mesh)?;
        let map = glam::DAffine3::from_mat4(self.core.power().transform());
        Ok(HierarchyMarks::new(
            mesh,
            self.moving_vertices(mesh),
            vec![(self.regions.handle().to_vec(), map)],
        )?
        .bound_to(self.binding))
    }

    /// Gives the marks of the current edit to `hierarchy`, replacing the affine marks the
    /// handle had ([`HierarchyMarks::replace`]): the session applies every transform from
    /// the original positions.
    fn mark_replacing(&self, hierarchy: &mut Hierarchy) -> Result<()> {
        self.check_mesh(hierarchy.mesh())?;
        if hierarchy.detail_mode() == halfedge::hierarchy::DetailMode::LocalFrame {
            self.marks(hierarchy.mesh())?.replace(hierarchy)?;
        }
        Ok(())
    }

    /// The live vertices of the handle and the deformable region (what a blend may move).
    fn moving_vertices(&self, mesh: &Mesh) -> Vec<halfedge::VertexId> {
        let roles = self.core.roles();
        mesh.vertices()
            .filter(|&v| {
                roles
                    .get(mesh.vertex_index(v))
                    .is_some_and(|&r| r != Role::Fixed)
            })
            .collect()
    }

    /// Adaptive refinement (Sec. 6) of an edit made at a coarse level of a hierarchy:
    /// the session was made on `hierarchy`'s mesh at its current level and its edit
    /// applied there. The hierarchy can only keep new vertices at its input, so the
    /// refinement is made there ([`Hierarchy::edit_input`]): the edit is marked as
    /// [`HierarchyEdit::mark`] marks it (the handle with the session's transform, with
    /// local-frame detail) so that it lands exactly, the hierarchy walks to level 0 carrying the edit, every
    /// input edge with an end that descends from the handle or the deformable area and
    /// is longer than `options.max_edge_length` is split at its midpoint, longest first,
    /// in passes (at most `options.max_new_vertices` new vertices), the hierarchy is
    /// built again, and it goes back to the level. The threshold is a length at full
    /// resolution. The session describes the coarse mesh before the refinement: make a
    /// new one to edit further.
    ///
    /// # Errors
    /// [`BendelsKleinError::Stale`] when the session was not made on the hierarchy's mesh
    /// at its current level; [`BendelsKleinError::BetweenLevels`] when the hierarchy is
    /// between two levels; [`BendelsKleinError::InvalidParameter`] for a threshold that is
    /// not finite and positive or a vertex budget above
    /// [`MAX_NEW_VERTICES`](super::MAX_NEW_VERTICES) (nothing changed then); the
    /// hierarchy's errors (it is then back at its level).
    pub fn refine_in_hierarchy(
        &self,
        hierarchy: &mut Hierarchy,
        options: RefineOptions,
    ) -> Result<RefineReport> {
        self.check_mesh(hierarchy.mesh())?;
        options.check()?;
        let max = options.max_edge_length;
        let level = hierarchy
            .current_level()
            .ok_or(BendelsKleinError::BetweenLevels)?;
        let ancestors = hierarchy.ancestors(level)?;
        let roles = self.core.roles();
        // Whether the input vertex at this index descends from a moving vertex.
        let moving: Vec<bool> = ancestors
            .iter()
            .map(|&a| roles.get(a as usize).is_some_and(|&r| r != Role::Fixed))
            .collect();
        self.mark_replacing(hierarchy)?;
        let report = hierarchy.edit_input(|mesh| {
            Ok::<_, BendelsKleinError>(split_long_edges(
                mesh,
                &moving,
                max,
                options.max_new_vertices,
            ))
        })?;
        Ok(report)
    }

    /// Binds the session and its per-vertex data to `mesh` as its own splits left it
    /// (new slots get neutral values until the split fills them in).
    fn rebind(&mut self, mesh: &Mesh) {
        self.original.rebind(mesh, DVec3::ZERO);
        self.core.rebind(mesh);
        self.r_handle.rebind(mesh, f64::INFINITY);
        self.r_fixed.rebind(mesh, f64::INFINITY);
        self.binding = mesh.binding();
    }

    /// Splits the edge `h = (a → b)` at the blended image of the original midpoint;
    /// false (nothing changed) when the kernel refuses the split (the two triangles beside
    /// the edge share their third vertex, or the image is not finite).
    fn split(&mut self, mesh: &mut Mesh, h: halfedge::HalfedgeId, ia: usize, ib: usize) -> bool {
        let (pa, pb) = (self.original[ia], self.original[ib]);
        let origin = 0.5 * (pa + pb);
        let length = pa.distance(pb);
        let mean_radius = |r: &[f64]| {
            if r[ia].is_finite() && r[ib].is_finite() {
                0.5 * (r[ia] + r[ib])
            } else {
                f64::INFINITY
            }
        };
        let (rh, rf) = (mean_radius(&self.r_handle), mean_radius(&self.r_fixed));
        let (dh, df) = match &self.grids {
            Some((handle, fixed)) => (handle.distance(origin), fixed.distance(origin)),
            None => {
                let (d_handle, d_fixed) =
                    (self.core.handle_distances(), self.core.fixed_distances());
                (
                    virtual_origin_distance(d_handle[ia], d_handle[ib], length, rh),
                    virtual_origin_distance(d_fixed[ia], d_fixed[ib], length, rf),
                )
            }
        };
        let alpha = self.core.weight(Role::Deformable, df, dh);
        let position = self.core.place(Role::Deformable, alpha, origin);
        let Ok(m) = mesh.split_edge(h, position) else {
            return false;
        };
        let i = mesh.vertex_index(m);
        let slots = mesh.vertex_slots();
        self.rebind(mesh);
        debug_assert_eq!(self.core.alpha().len(), slots);
        self.original[i] = origin;
        self.extent = self.extent.max(magnitude(origin));
        self.core.set_new(i, dh, df, alpha);
        self.r_handle[i] = rh;
        self.r_fixed[i] = rf;
        self.regions.push_deformable(mesh, m);
        true
    }
}

/// The largest coordinate magnitude of `p`, `∞` when one is not finite.
fn magnitude(p: DVec3) -> f64 {
    if p.is_finite() {
        p.abs().max_element()
    } else {
        f64::INFINITY
    }
}

/// Distance of the midpoint of an edge of length `length` from the virtual origin
/// (Bendels & Klein, Sec. 6, *Mesh forging*), for a front of radius `radius` reaching
/// the ends at distances `d0`, `d1`: the centre of the source circle lies at `d0 + R`
/// and `d1 + R` from the ends, so the midpoint is at
/// `√(((d0+R)² + (d1+R)²)/2 − L²/4) − R`, at least `|d0 − d1|/2`. `R = 0` is the
/// paper's virtual origin (exact for a point source); `R = ∞` gives `(d0 + d1)/2`
/// (exact for a straight front). Infinite distances stay infinite.
#[inline]
#[must_use]
pub fn virtual_origin_distance(d0: f64, d1: f64, length: f64, radius: f64) -> f64 {
    if !(d0.is_finite() && d1.is_finite()) {
        return f64::INFINITY;
    }
    let floor = 0.5 * (d0 - d1).abs();
    let mean = 0.5 * (d0 + d1);
    if !radius.is_finite() {
        return mean.max(floor);
    }
    // (m + R)² + q with q = ((d0 − d1)² − L²)/4, written to stay accurate for large R.
    let s = mean + radius.max(0.0);
    let q = 0.25 * ((d0 - d1) * (d0 - d1) - length * length);
    let inside = s * s + q;
    if inside <= 0.0 {
        return floor;
    }
    (mean + q / (inside.sqrt() + s)).max(floor)
}

/// Splits, longest first and in passes, every edge of `mesh` with an end whose `moving`
/// entry is true (vertices beyond the list, added by earlier splits, count as moving) and
/// longer than `max`, at its midpoint; at most `budget` new vertices.
fn split_long_edges(mesh: &mut Mesh, moving: &[bool], max: f64, budget: usize) -> RefineReport {
    let is_moving =
        |mesh: &Mesh, v: VertexId| moving.get(mesh.vertex_index(v)).copied().unwrap_or(true);
    let touches =
        |mesh: &Mesh, h| is_moving(mesh, mesh.from_vertex(h)) || is_moving(mesh, mesh.to_vertex(h));
    let mut report = RefineReport::default();
    while report.passes < 64 && report.new_vertices < budget {
        let mut long: Vec<(f64, halfedge::HalfedgeId)> = mesh
            .edges()
            .filter(|&h| touches(mesh, h))
            .map(|h| (mesh.edge_length(h), h))
            .filter(|&(l, _)| l > max)
            .collect();
        if long.is_empty() {
            break;
        }
        report.passes += 1;
        long.sort_by(|a, b| b.0.total_cmp(&a.0));
        for (_, h) in long {
            if report.new_vertices >= budget {
                break;
            }
            if mesh.edge_length(h) > max {
                let midpoint =
                    0.5 * (mesh.position(mesh.from_vertex(h)) + mesh.position(mesh.to_vertex(h)));
                // A refused split (the two triangles share their third vertex) leaves the
                // edge as it is.
                if mesh.split_edge(h, midpoint).is_ok() {
                    report.new_vertices += 1;
                }
            }
        }
    }
    report.longest_edge = mesh
        .edges()
        .filter(|&h| touches(mesh, h))
        .map(|h| mesh.edge_length(h))
        .fold(0.0, f64::max);
    report
}

impl HierarchyEdit for BlendSession {
    /// What the session's current edit did, for a [`Hierarchy`] whose mesh (at its
    /// current level) the session was made on: the handle moved by the session's
    /// transform `A`, and the handle and the deformable region as the edit's region.
    /// Refinement then puts every finer vertex of the handle at `A` of its original
    /// position, places the finer vertices of the deformable region by their local-frame
    /// detail on the blended neighbourhood, and leaves the fixed region bit for bit.
    ///
    /// # Errors
    /// [`BendelsKleinError::Stale`] when the session was not made on `mesh` at its
    /// current level.
    fn hierarchy_marks(&self, mesh: &Mesh) -> std::result::Result<HierarchyMarks, Error> {
        Ok(self.marks(mesh)?)
    }

    /// Tells `hierarchy` what the session's current edit did: the handle is marked with
    /// the session's transform, replacing the affine mark it had
    /// ([`Hierarchy::set_affine_mark`]), since the session applies every transform from
    /// the original positions (mark after each [`apply`](BlendSession::apply), as an
    /// interactive drag does), and the handle and the deformable region are the edit's
    /// region ([`Hierarchy::mark_region`]), so that refinement interpolates the blend's
    /// motion over them while the fixed region stays exactly where it was. The edit may
    /// have been applied to a copy of the hierarchy's mesh whose positions were copied
    /// back. With the paper's translations ([`halfedge::hierarchy::DetailMode::Translation`])
    /// nothing is marked.
    ///
    /// # Errors
    /// As [`hierarchy_marks`](Self::hierarchy_marks); nothing is marked then.
    fn mark(&self, hierarchy: &mut Hierarchy) -> std::result::Result<(), Error> {
        Ok(self.mark_replacing(hierarchy)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn virtual_origin_is_exact_for_point_and_line_sources() {
        // A point source at the origin, edge from (3, 4) to (3, -4): midpoint at 3.
        let d = virtual_origin_distance(5.0, 5.0, 8.0, 0.0);
        assert!((d - 3.0).abs() < 1e-15);
        // Along a ray from the source: 2 and 6, midpoint at 4.
        assert!((virtual_origin_distance(2.0, 6.0, 4.0, 0.0) - 4.0).abs() < 1e-15);
        // Spheres that miss each other: half the difference.
        assert_eq!(virtual_origin_distance(0.0, 1.0, 5.0, 0.0), 0.5);
        assert!(virtual_origin_distance(f64::INFINITY, 1.0, 1.0, 0.0).is_infinite());
        // A straight front: the mean, also for an edge parallel to it, close to it.
        assert_eq!(
            virtual_origin_distance(0.05, 0.05, 0.2, f64::INFINITY),
            0.05
        );
        assert_eq!(virtual_origin_distance(0.05, 0.05, 0.2, 0.0), 0.0);
        // A front from a source circle of radius 1 around the origin: a chord at radius 3.
        let a = DVec3::new(3.0, 0.0, 0.0);
        let b = DVec3::new(3.0 * 0.5f64.cos(), 3.0 * 0.5f64.sin(), 0.0);
        let d = virtual_origin_distance(2.0, 2.0, a.distance(b), 1.0);
        assert!((d - (0.5 * (a + b)).length() + 1.0).abs() < 1e-14);
        // Large radii tend to the mean without cancellation.
        let d = virtual_origin_distance(1.0, 2.0, 1.5, 1e12);
        assert!((d - 1.5).abs() < 1e-9);
    }
}
