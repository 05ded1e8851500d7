//! The Lee 1999 editing session ([`AreaSession`]): scale parameter, fit and drag.

use glam::{DAffine3, DVec2, DVec3};
use halfedge::{Mesh, VertexId};
use rayon::prelude::*;

use crate::error::Error;
use crate::hierarchy_edit::{HierarchyEdit, HierarchyMarks};
use crate::lee::area::EditingArea;
use crate::lee::embedding::{Embedding, EmbeddingOptions};
use crate::lee::error::{LeeError, Result};
use crate::lee::fit::{self, CellIndex, FitPlan, FitState, FIRST_LEVEL};
use crate::lee::frames::{FrameKind, LocalFrames};
use crate::lee::mba::{level_size, LatticeBasis, MAX_LEVELS};
use crate::vertices::{first_non_finite, scatter};

/// Options of [`AreaSession::new`].
///
/// Paper: Lee 1999, *Interactive multiresolution editing of arbitrary meshes* §3.6 and §5.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct SessionOptions {
    /// How the area is embedded.
    pub embedding: EmbeddingOptions,
    /// Local frames.
    pub frames: FrameKind,
    /// Scale parameter `s ∈ [0, 1]` (Lee 1999 §3.6): 0 moves only the primitive, 1 the
    /// whole area; in between the edit reaches about `0.45 s` of the rectangle's side
    /// from the primitive up to `s = 1/2` (motion down to 10 % of the drag), the same on
    /// coarse and fine meshes.
    pub scale: f64,
    /// Number `l` of dense B-spline levels, `3 ..=` [`MAX_SESSION_LEVELS`] (level 3,
    /// four cells, is the coarsest with a free control point once the border is fixed).
    /// `None`: the smallest `l ≥ 5` whose finest cell is at most twice the mean embedded
    /// edge length (capped at [`MAX_SESSION_LEVELS`]), so the finest level resolves the
    /// mesh. Scales below `2^{3−l}` blend the finest level with moving the primitive
    /// alone.
    pub levels: Option<usize>,
    /// Interior vertices from which a drag's evaluation is split over rayon's threads
    /// (one contiguous block each). Measured on the project's shared 2-core machine
    /// under load, handing a 100k-vertex evaluation (1.4 ms sequentially) to the
    /// thread pool cost more in wake-up and waiting than it saved, so the default,
    /// [`DEFAULT_PARALLEL_THRESHOLD`] (262,144), keeps areas of that size sequential;
    /// lower it on machines with idle cores.
    pub parallel_threshold: usize,
}

impl SessionOptions {
    /// The same options with the embedding options set to `embedding`.
    #[must_use]
    pub fn with_embedding(mut self, embedding: EmbeddingOptions) -> Self {
        self.embedding = embedding;
        self
    }

    /// The same options with the local frames set to `frames`.
    #[must_use]
    pub fn with_frames(mut self, frames: FrameKind) -> Self {
        self.frames = frames;
        self
    }

    /// The same options with the scale parameter `s` set to `scale`.
    #[must_use]
    pub fn with_scale(mut self, scale: f64) -> Self {
        self.scale = scale;
        self
    }

    /// The same options with the number of dense B-spline levels set to `levels`.
    #[must_use]
    pub fn with_levels(mut self, levels: usize) -> Self {
        self.levels = Some(levels);
        self
    }

    /// The same options with the interior vertex count from which a drag is evaluated in parallel set to `parallel_threshold`.
    #[must_use]
    pub fn with_parallel_threshold(mut self, parallel_threshold: usize) -> Self {
        self.parallel_threshold = parallel_threshold;
        self
    }
}

impl Default for SessionOptions {
    fn default() -> Self {
        Self {
            embedding: EmbeddingOptions::default(),
            frames: FrameKind::Global,
            scale: 0.5,
            levels: None,
            parallel_threshold: DEFAULT_PARALLEL_THRESHOLD,
        }
    }
}

/// Default of [`SessionOptions::parallel_threshold`].
///
/// Paper: Lee 1999, *Interactive multiresolution editing of arbitrary meshes* §5 (the
/// evaluation of a drag).
pub const DEFAULT_PARALLEL_THRESHOLD: usize = 1 << 18;
/// Most dense B-spline levels of a session: the finest lattice then has `(2^11 + 3)²`
/// control points (101 MB of `DVec3`; a drag holds about 2.5 such lattices), far finer
/// than the embedded edges of any area that fits in memory.
///
/// Paper: Lee 1999, *Interactive multiresolution editing of arbitrary meshes* §5; Lee,
/// Wolberg & Shin 1997, *Scattered data interpolation with multilevel B-splines*.
pub const MAX_SESSION_LEVELS: usize = MAX_LEVELS;
const NONE: u32 = u32::MAX;

/// The editing session (Lee 1999, §3.1 and §3.3): the area is specified and embedded
/// once; then any number of edits with editing primitives of any vertex set, at any scale
/// and with either kind of local frames, each re-running only the multilevel B-spline
/// fit of the primitive's offsets and its evaluation at the area's vertices.
///
/// Positions are always `rest + f_s(offsets)`, where `rest` are the area's positions when
/// the edit began ([`AreaSession::commit`], called by
/// [`AreaSession::set_primitive`]): dragging again replaces the previous drag of the
/// same edit instead of accumulating on it, and changing the scale or the frames
/// re-shapes the current edit ([`AreaSession::apply`]). If the area's positions are
/// changed by other means, call [`AreaSession::commit`] before the next edit, or the
/// next drag overwrites them with `rest + f_s`.
///
/// # The fit
///
/// The offsets are spread by the multilevel B-spline fit of Lee 1999 §5 with three
/// repairs that make the paper's intent hold on areas of any size (details in the
/// `fit` submodule's docs):
///
/// - **Boundary fixing at every level** (§5.3): each level's lattice keeps its three
///   border rows and columns at zero, so the offsets fall to zero on the border with their
///   first and second derivatives, over a band as wide as the edit (the paper fixes the
///   finest lattice only, which creases the surface one or two rings inside the border at
///   large scales).
/// - **The scale is a fraction of the area** (§3.6, §5.2): the coarsest lattice has
///   `m = 4/s` cells (`s = 1, 1/2, 1/4, …` ↔ `m = 4, 8, 16, …`, linear between), whatever
///   the number of levels, so a given `s` reaches the same part of an area on a coarse
///   and on a fine mesh: about `0.45 s` of the rectangle's side from the primitive up to
///   `s = 1/2` (the measured table is in `docs/guide/area-editing.md`).
/// - **Detail levels at the primitive**: up to six sparse levels finer than the dense
///   lattice fit what is left at the primitive's vertices, so a primitive of several
///   vertices is reached to `1e-9` of the drag (away from the border band, where fixing
///   wins as in §5.3).
///
/// The number of dense levels `l` follows the embedded resolution
/// ([`SessionOptions::levels`]); it only decides where the smallest scales turn into
/// moving the primitive alone.
///
/// # Speed and memory
///
/// Per area (once): the embedding, and for every interior vertex the index and the
/// B-spline weights of its 4 × 4 control points in the finest lattice. Per primitive:
/// which control points each primitive vertex touches at every level, and the vertices
/// the detail levels reach. Per drag: the fit touches only the primitive's control points
/// plus one dense refinement per level; the evaluation is 16 lattice reads per interior
/// vertex (weights stored as `f32`), in slot order so that the writes into the mesh's
/// position array run forward; in parallel over contiguous blocks of that array for very
/// large areas ([`SessionOptions::parallel_threshold`]); boundary vertices are never
/// written. The dense lattice has `(2^{l−1} + 3)²` control points; `l ≤`
/// [`MAX_SESSION_LEVELS`] keeps a drag under about 250 MB.
///
/// ```
/// use edit::lee::{AreaSession, EditingArea, SessionOptions};
/// use glam::DVec3;
/// let mut mesh = halfedge::generators::icosphere(3);
/// let top = mesh.vertices().max_by(|&a, &b| mesh.position(a).z.total_cmp(&mesh.position(b).z)).unwrap();
/// let area = EditingArea::disk_around(&mesh, top, 150).unwrap();
/// let mut session = AreaSession::new(&mesh, area, &SessionOptions::default()).unwrap();
/// session.set_primitive(&mesh, &[top]).unwrap();
/// let before = mesh.position(top);
/// session.drag(&mut mesh, DVec3::new(0.0, 0.0, 0.2)).unwrap();
/// assert!((mesh.position(top) - (before + DVec3::new(0.0, 0.0, 0.2))).length() < 1e-9);
/// ```
#[derive(Clone, Debug)]
pub struct AreaSession {
    area: EditingArea,
    embedding: Embedding,
    levels: usize,
    scale: f64,
    frame_kind: FrameKind,
    frames: LocalFrames,
    rest: Vec<DVec3>,
    interior_slots: Vec<u32>,
    eval: Vec<CompactBasis>,
    cells: CellIndex,
    primitive: Vec<u32>,
    primitive_bases: Vec<LatticeBasis>,
    plan: FitPlan,
    data_of_local: Vec<u32>,
    displacements: Vec<DVec3>,
    offsets: Vec<DVec3>,
    state: FitState,
    lattice: Vec<DVec3>,
    parallel_threshold: usize,
}

impl AreaSession {
    /// Specifies the editing area: embeds it (once for the whole session), computes the
    /// frames and the per-vertex lattice bases, and records the current positions as the
    /// rest positions.
    ///
    /// # Errors
    /// The errors of [`Embedding::new`] and [`LocalFrames::new`];
    /// [`LeeError::InvalidParameter`] for a bad scale or level count.
    pub fn new(mesh: &Mesh, area: EditingArea, options: &SessionOptions) -> Result<Self> {
        check_scale(options.scale)?;
        if let Some(l) = options.levels {
            check_levels(l)?;
        }
        let embedding = Embedding::new(mesh, &area, &options.embedding)?;
        let levels = options
            .levels
            .unwrap_or_else(|| auto_levels(&embedding, &area.local_triangles(mesh)));
        let rest: Vec<DVec3> = area.vertices().iter().map(|&v| mesh.position(v)).collect();
        let centre_seed = nearest_to_centre(&area, &embedding);
        let frames = LocalFrames::new(mesh, &area, &rest, &options.frames, centre_seed)?;
        let interior_slots = area
            .interior()
            .iter()
            .map(|&v| mesh.vertex_index(v) as u32)
            .collect();
        let mut session = Self {
            data_of_local: vec![NONE; area.n_interior()],
            area,
            embedding,
            levels,
            scale: options.scale,
            frame_kind: options.frames.clone(),
            frames,
            rest,
            interior_slots,
            eval: Vec::new(),
            cells: CellIndex::default(),
            primitive: Vec::new(),
            primitive_bases: Vec::new(),
            plan: FitPlan::default(),
            displacements: Vec::new(),
            offsets: Vec::new(),
            state: FitState::default(),
            lattice: Vec::new(),
            parallel_threshold: options.parallel_threshold,
        };
        session.compute_area_bases();
        session.compute_primitive_plan();
        Ok(session)
    }

    /// Every interior vertex's basis in the finest dense lattice, and the cell index.
    fn compute_area_bases(&mut self) {
        let size = self.embedding.size();
        let m = level_size(self.levels);
        let uv = &self.embedding.uv()[..self.area.n_interior()];
        self.eval = uv
            .par_iter()
            .with_min_len(1024)
            .map(|&p| CompactBasis::from(LatticeBasis::locate(p, DVec2::ZERO, size, m)))
            .collect();
        self.cells = CellIndex::new(uv, size, m);
    }

    /// The primitive's finest dense bases and its fit plan.
    fn compute_primitive_plan(&mut self) {
        let size = self.embedding.size();
        let uv = self.embedding.uv();
        let points: Vec<DVec2> = self.primitive.iter().map(|&i| uv[i as usize]).collect();
        let m = level_size(self.levels);
        self.primitive_bases = points
            .iter()
            .map(|&p| LatticeBasis::locate(p, DVec2::ZERO, size, m))
            .collect();
        self.plan = FitPlan::new(
            &points,
            size,
            self.levels,
            &uv[..self.area.n_interior()],
            &self.cells,
            true,
        );
    }

    /// The editing area.
    #[must_use]
    pub fn area(&self) -> &EditingArea {
        &self.area
    }

    /// The area's embedding onto the rectangle.
    #[must_use]
    pub fn embedding(&self) -> &Embedding {
        &self.embedding
    }

    /// Number of dense B-spline levels `l`.
    #[must_use]
    pub fn levels(&self) -> usize {
        self.levels
    }

    /// The scale `2^{3−l}` below which the finest dense level blends with moving the
    /// primitive alone (the smallest scale with a B-spline reach of its own).
    #[must_use]
    pub fn finest_scale(&self) -> f64 {
        fit::scale_of_level(self.levels)
    }

    /// The scale parameter `s`.
    #[must_use]
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// The local frames in use.
    #[must_use]
    pub fn frames(&self) -> &LocalFrames {
        &self.frames
    }

    /// The vertices of the current editing primitive.
    #[must_use]
    pub fn primitive(&self) -> Vec<VertexId> {
        self.primitive
            .iter()
            .map(|&i| self.area.vertices()[i as usize])
            .collect()
    }

    /// The rest positions of the area's local vertices (positions when the current edit
    /// began).
    #[must_use]
    pub fn rest_positions(&self) -> &[DVec3] {
        &self.rest
    }

    /// Sets the scale parameter `s ∈ [0, 1]` (Lee 1999 §3.6); takes effect at the next
    /// [`drag`](Self::drag) or [`apply`](Self::apply). No re-embedding.
    ///
    /// # Errors
    /// [`LeeError::InvalidParameter`] outside `[0, 1]` or NaN.
    pub fn set_scale(&mut self, s: f64) -> Result<()> {
        check_scale(s)?;
        self.scale = s;
        Ok(())
    }

    /// Sets the number of dense B-spline levels; recomputes the lattice bases. The scale
    /// keeps its reach.
    ///
    /// # Errors
    /// [`LeeError::InvalidParameter`] outside `3 ..=` [`MAX_SESSION_LEVELS`]; nothing
    /// changes then.
    pub fn set_levels(&mut self, levels: usize) -> Result<()> {
        self.levels = check_levels(levels)?;
        self.compute_area_bases();
        self.compute_primitive_plan();
        Ok(())
    }

    /// Changes the local frames (computed at the rest positions); takes effect at the next
    /// drag or apply. No re-embedding.
    ///
    /// # Errors
    /// [`LeeError::Stale`]; the errors of [`LocalFrames::new`].
    pub fn set_frames(&mut self, mesh: &Mesh, kind: FrameKind) -> Result<()> {
        self.area.check_mesh(mesh)?;
        let seed = nearest_to_centre(&self.area, &self.embedding);
        self.frames = LocalFrames::new(mesh, &self.area, &self.rest, &kind, seed)?;
        self.frame_kind = kind;
        Ok(())
    }

    /// Chooses the editing primitive (Lee 1999 §3.3): any set of interior vertices of the
    /// area (a single vertex, a chain, a closed loop, a scattered set; duplicates
    /// ignored). Starts a new edit: the mesh's current positions become the rest
    /// positions ([`commit`](Self::commit)).
    ///
    /// # Errors
    /// [`LeeError::EmptyPrimitive`], [`halfedge::Error::InvalidHandle`] (as `LeeError::Mesh`),
    /// [`LeeError::PrimitiveOutsideArea`], [`LeeError::PrimitiveOnAreaBoundary`],
    /// [`LeeError::Stale`]; nothing changes on error.
    pub fn set_primitive(&mut self, mesh: &Mesh, vertices: &[VertexId]) -> Result<()> {
        self.area.check_mesh(mesh)?;
        if vertices.is_empty() {
            return Err(LeeError::EmptyPrimitive);
        }
        let mut primitive = Vec::with_capacity(vertices.len());
        for &v in vertices {
            mesh.ensure_vertex(v)?;
            let i = self
                .area
                .local_index(mesh, v)
                .ok_or(LeeError::PrimitiveOutsideArea { vertex: v })?;
            if i >= self.area.n_interior() {
                return Err(LeeError::PrimitiveOnAreaBoundary { vertex: v });
            }
            primitive.push(i as u32);
        }
        // duplicates out, first occurrence kept
        let mut seen = vec![false; self.area.n_interior()];
        primitive.retain(|&i| !std::mem::replace(&mut seen[i as usize], true));
        self.commit(mesh)?;
        for &i in &self.primitive {
            self.data_of_local[i as usize] = NONE;
        }
        for (c, &i) in primitive.iter().enumerate() {
            self.data_of_local[i as usize] = c as u32;
        }
        self.displacements = vec![DVec3::ZERO; primitive.len()];
        self.offsets = vec![DVec3::ZERO; primitive.len()];
        self.primitive = primitive;
        self.compute_primitive_plan();
        Ok(())
    }

    /// Ends the current edit: the mesh's positions of the area become the rest positions
    /// (and normal-based frames are recomputed there); the primitive stays, its
    /// displacements are reset.
    ///
    /// # Errors
    /// [`LeeError::Stale`].
    pub fn commit(&mut self, mesh: &Mesh) -> Result<()> {
        self.area.check_mesh(mesh)?;
        let rest: Vec<DVec3> = self
            .area
            .vertices()
            .iter()
            .map(|&v| mesh.position(v))
            .collect();
        if !self.frames.is_global() {
            let seed = nearest_to_centre(&self.area, &self.embedding);
            self.frames = LocalFrames::new(mesh, &self.area, &rest, &self.frame_kind, seed)?;
        }
        self.rest = rest;
        self.displacements.fill(DVec3::ZERO);
        Ok(())
    }

    /// Undoes the current edit: the area's interior vertices go back to the rest positions.
    ///
    /// # Errors
    /// [`LeeError::Stale`].
    pub fn cancel(&mut self, mesh: &mut Mesh) -> Result<()> {
        self.area.check_mesh(mesh)?;
        let positions = mesh.positions_mut();
        for (i, &slot) in self.interior_slots.iter().enumerate() {
            positions[slot as usize] = self.rest[i];
        }
        self.displacements.fill(DVec3::ZERO);
        Ok(())
    }

    /// First mode of Lee 1999 §3.3: moves the whole primitive by `displacement` from its
    /// rest positions and updates the mesh at once. Calling it again during the same edit
    /// replaces the previous displacement.
    ///
    /// # Errors
    /// [`LeeError::NonFiniteDisplacement`], [`LeeError::EmptyPrimitive`],
    /// [`LeeError::Stale`], [`LeeError::Overflow`] when a moved vertex would not
    /// land on a finite position (a displacement of 1e308); the mesh and the current
    /// displacement are unchanged on error.
    pub fn drag(&mut self, mesh: &mut Mesh, displacement: DVec3) -> Result<()> {
        if !displacement.is_finite() {
            return Err(LeeError::NonFiniteDisplacement { displacement });
        }
        self.ready(mesh)?;
        let previous = std::mem::replace(
            &mut self.displacements,
            vec![displacement; self.primitive.len()],
        );
        self.update(mesh)
            .inspect_err(|_| self.displacements = previous)
    }

    /// Second mode of Lee 1999 §3.3: sets the target position of one primitive vertex;
    /// the mesh changes at [`apply`](Self::apply). Vertices not moved keep their rest
    /// position as target (they hold the surface there).
    ///
    /// # Errors
    /// [`LeeError::NonFiniteTarget`], [`LeeError::NotInPrimitive`],
    /// [`LeeError::Stale`].
    pub fn move_vertex(&mut self, mesh: &Mesh, v: VertexId, target: DVec3) -> Result<()> {
        self.area.check_mesh(mesh)?;
        if !target.is_finite() {
            return Err(LeeError::NonFiniteTarget { vertex: v, target });
        }
        let c = self
            .area
            .local_index(mesh, v)
            .filter(|&i| i < self.area.n_interior())
            .map(|i| self.data_of_local[i])
            .filter(|&c| c != NONE)
            .ok_or(LeeError::NotInPrimitive { vertex: v })?;
        let i = self.primitive[c as usize] as usize;
        self.displacements[c as usize] = target - self.rest[i];
        Ok(())
    }

    /// Updates the mesh from the current displacements of the primitive, scale and
    /// frames (after [`move_vertex`](Self::move_vertex), or to show a new scale).
    ///
    /// # Errors
    /// [`LeeError::EmptyPrimitive`], [`LeeError::Stale`], [`LeeError::Overflow`]
    /// (targets too far for the coordinates); the mesh is unchanged on error.
    pub fn apply(&mut self, mesh: &mut Mesh) -> Result<()> {
        self.ready(mesh)?;
        self.update(mesh)
    }

    fn ready(&self, mesh: &Mesh) -> Result<()> {
        self.area.check_mesh(mesh)?;
        if self.primitive.is_empty() {
            return Err(LeeError::EmptyPrimitive);
        }
        Ok(())
    }

    /// Fit + evaluate + write; inputs already checked. The new positions are evaluated
    /// apart and checked before any is written.
    fn update(&mut self, mesh: &mut Mesh) -> Result<()> {
        for (c, &i) in self.primitive.iter().enumerate() {
            self.offsets[c] = self.frames.to_offset(i as usize, self.displacements[c]);
        }
        let split = fit::scale_split(self.scale, self.levels);
        self.state
            .fit(&self.plan, split, &self.offsets, &mut self.lattice);
        let evaluator = Evaluator {
            lattice: (split.k <= self.levels).then_some(self.lattice.as_slice()),
            n: level_size(self.levels) + 3,
            data_weight: split.data_weight(self.levels),
            eval: &self.eval,
            primitive_bases: &self.primitive_bases,
            data_of_local: &self.data_of_local,
            offsets: &self.offsets,
            frames: &self.frames,
            rest: &self.rest,
        };
        let slots = &self.interior_slots;
        let mut new: Vec<DVec3> = if slots.len() < self.parallel_threshold.max(1) {
            (0..slots.len()).map(|i| evaluator.position(i)).collect()
        } else {
            // One contiguous block of interior vertices per thread (few, large tasks:
            // little scheduling).
            let per_block = slots.len().div_ceil(rayon::current_num_threads().max(1));
            (0..slots.len())
                .into_par_iter()
                .with_min_len(per_block)
                .map(|i| evaluator.position(i))
                .collect()
        };
        // the detail levels, near the primitive only
        if self.state.detail_used() > 0 {
            let details = self.plan.detail_vertices();
            for (&i, &detail) in details.iter().zip(self.state.detail_offsets()) {
                let i = i as usize;
                new[i] = evaluator.position_with(i, detail);
            }
        }
        if let Some((vertex, position)) = first_non_finite(slots, &new) {
            return Err(LeeError::Overflow {
                what: "the drag",
                vertex,
                position,
            });
        }
        // In slot order: the writes into the mesh's position array run forward.
        scatter(mesh.positions_mut(), slots, &new);
        Ok(())
    }
}

impl HierarchyEdit for AreaSession {
    /// What the edit as last applied ([`drag`](AreaSession::drag) or
    /// [`apply`](AreaSession::apply) since the rest positions were taken) means for a
    /// [`Hierarchy`](halfedge::hierarchy::Hierarchy) whose current level `mesh` is: the region is
    /// the area's interior (its boundary stays, Lee 1999 §5.3), and every primitive
    /// vertex is translated by its displacement, so that refined back the fine vertices
    /// collapsed into the primitive land on the dragged target exactly. Give the marks
    /// once per edit ([`HierarchyEdit::mark`], which composes with earlier edits), for
    /// example when a drag ends.
    ///
    /// # Errors
    /// [`LeeError::Stale`] when `mesh` is not the one the session was made on.
    fn hierarchy_marks(&self, mesh: &Mesh) -> Result<HierarchyMarks, Error> {
        self.area.check_mesh(mesh)?;
        let vertices = self.area.vertices();
        let mut affine: Vec<(Vec<VertexId>, DAffine3)> = Vec::new();
        for (c, &i) in self.primitive.iter().enumerate() {
            let d = self.displacements[c];
            let v = vertices[i as usize];
            match affine.iter_mut().find(|(_, map)| map.translation == d) {
                Some((group, _)) => group.push(v),
                None => affine.push((vec![v], DAffine3::from_translation(d))),
            }
        }
        let marks = HierarchyMarks::new(mesh, self.area.interior().to_vec(), affine)
            .map_err(LeeError::from)?;
        Ok(marks.bound_to(self.area.binding()))
    }
}

/// What the evaluation of one interior vertex reads.
struct Evaluator<'a> {
    lattice: Option<&'a [DVec3]>,
    n: usize,
    data_weight: f64,
    eval: &'a [CompactBasis],
    primitive_bases: &'a [LatticeBasis],
    data_of_local: &'a [u32],
    offsets: &'a [DVec3],
    frames: &'a LocalFrames,
    rest: &'a [DVec3],
}

impl Evaluator<'_> {
    #[inline]
    fn position(&self, i: usize) -> DVec3 {
        let c = self.data_of_local[i];
        let offset = if c == NONE {
            match self.lattice {
                Some(phi) => self.eval[i].evaluate(phi, self.n),
                None => return self.rest[i],
            }
        } else {
            self.primitive_offset(c as usize)
        };
        self.rest[i] + self.frames.to_displacement(i, offset)
    }

    /// The position of local vertex `i` with `detail` added to its offset (the vertices
    /// the detail levels reach; off the hot loop).
    fn position_with(&self, i: usize, detail: DVec3) -> DVec3 {
        let c = self.data_of_local[i];
        let offset = if c == NONE {
            self.lattice
                .map_or(DVec3::ZERO, |phi| self.eval[i].evaluate(phi, self.n))
        } else {
            self.primitive_offset(c as usize)
        };
        self.rest[i] + self.frames.to_displacement(i, offset + detail)
    }

    /// The offset at primitive vertex `c`: the primitive's own full-precision basis (it
    /// reaches what the fit aimed at) plus the data-only part.
    #[inline]
    fn primitive_offset(&self, c: usize) -> DVec3 {
        let smooth = match self.lattice {
            Some(phi) => self.primitive_bases[c].evaluate_unchecked(phi, self.n),
            None => DVec3::ZERO,
        };
        smooth + self.offsets[c] * self.data_weight
    }
}

/// A vertex's 4 × 4 control points in the finest lattice with `f32` weights (36 bytes
/// instead of 72: the evaluation of a large area is bound by memory traffic). The
/// weights' relative error of 6·10⁻⁸ is far below what a drag can show; the primitive's
/// vertices use full-precision bases.
#[derive(Clone, Copy, Debug)]
struct CompactBasis {
    base: u32,
    wu: [f32; 4],
    wv: [f32; 4],
}

impl From<LatticeBasis> for CompactBasis {
    fn from(b: LatticeBasis) -> Self {
        Self {
            base: b.base,
            wu: b.wu.map(|w| w as f32),
            wv: b.wv.map(|w| w as f32),
        }
    }
}

impl CompactBasis {
    #[inline]
    fn evaluate(&self, phi: &[DVec3], n: usize) -> DVec3 {
        let wu = self.wu.map(f64::from);
        let mut sum = DVec3::ZERO;
        let base = self.base as usize;
        for (b, &wv) in self.wv.iter().enumerate() {
            let row = &phi[base + b * n..base + b * n + 4];
            let r = row[0] * wu[0] + row[1] * wu[1] + row[2] * wu[2] + row[3] * wu[3];
            sum += r * f64::from(wv);
        }
        sum
    }
}

fn check_scale(s: f64) -> Result<()> {
    if !(0.0..=1.0).contains(&s) {
        return Err(LeeError::InvalidParameter {
            name: "scale",
            reason: format!("{s} is outside [0, 1]"),
        });
    }
    Ok(())
}

fn check_levels(l: usize) -> Result<usize> {
    if !(FIRST_LEVEL..=MAX_SESSION_LEVELS).contains(&l) {
        return Err(LeeError::InvalidParameter {
            name: "levels",
            reason: format!(
                "{l} is outside {FIRST_LEVEL}..={MAX_SESSION_LEVELS} (level {FIRST_LEVEL} is \
                 the coarsest with a free control point once the border is fixed; level \
                 {MAX_SESSION_LEVELS}'s lattice already takes 101 MB)"
            ),
        });
    }
    Ok(l)
}

/// The smallest `l ≥ 5` whose finest cell, `max(width, height) / 2^{l−1}`, is at most
/// twice the mean embedded edge length (each edge once per face side), at most
/// [`MAX_SESSION_LEVELS`]; 5 when the embedding has no edge of positive length.
fn auto_levels(embedding: &Embedding, triangles: &[[u32; 3]]) -> usize {
    let uv = embedding.uv();
    let (sum, count) = triangles
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .fold((0.0, 0usize), |(sum, count), (a, b)| {
            (sum + uv[a as usize].distance(uv[b as usize]), count + 1)
        });
    let mean = sum / count.max(1) as f64;
    let side = embedding.size().max_element();
    let mut l = 5;
    if !(mean > 0.0 && side.is_finite()) {
        return l;
    }
    while side / level_size(l) as f64 > 2.0 * mean && l < MAX_SESSION_LEVELS {
        l += 1;
    }
    l
}

/// The interior vertex embedded nearest to the rectangle's centre (0 without interior).
fn nearest_to_centre(area: &EditingArea, embedding: &Embedding) -> usize {
    let centre = 0.5 * embedding.size();
    embedding.uv()[..area.n_interior()]
        .iter()
        .enumerate()
        .min_by(|a, b| {
            a.1.distance_squared(centre)
                .total_cmp(&b.1.distance_squared(centre))
        })
        .map_or(0, |(i, _)| i)
}
