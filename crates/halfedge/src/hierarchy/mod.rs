//! The progressive hierarchy of the seed paper ("Interactive Editing of Multiresolution
//! Meshes", section 3): a sequence of edge collapses recorded level by level, with
//! detail coefficients, that can be walked coarser and finer at will
//! while the user edits positions (and sub-mesh labels) at any level.
//!
//! - **Building** ([`Hierarchy::build`]) simplifies the mesh with one of two methods
//!   ([`Method`]): the paper's *rounds* (every unlocked edge whose star is nearly planar
//!   collapses to its midpoint, then the edges around the survivor are locked until the
//!   round ends; a round is a level, module [`rounds`]) or a *QEM* priority decimation
//!   (Garland–Heckbert, module [`qem`]) whose levels are cut at fixed face-count ratios so
//!   that they are comparable with rounds. Both share the legality layer of module
//!   [`legality`] (OpenMesh's topological rules, no normal flips, no degenerate faces,
//!   boundary vertices never leave the boundary). The build stops at a target face
//!   count, a level count or an error bound ([`HierarchyOptions`]). The mesh is left at
//!   the coarsest level. [`Hierarchy::build_with_progress`] reports progress, and
//!   [`Hierarchy::build_cancellable`] lets the report stop the build.
//! - **Speed**: walking the records is bound by memory latency (each step touches a few
//!   elements scattered over arrays larger than the caches), so every step prefetches
//!   what the record a few steps ahead will touch (`crate::prefetch`); while the
//!   hierarchy trusts its mesh (its [`Binding`](crate::Binding)), collapsing a record again
//!   skips the legality test the build already made, and splitting one skips its checks.
//! - **Walking**: [`coarsen_to`](Hierarchy::coarsen_to) / [`refine_to`](Hierarchy::refine_to)
//!   / [`go_to_level`](Hierarchy::go_to_level) level by level, or
//!   [`collapse_next`](Hierarchy::collapse_next) / [`split_next`](Hierarchy::split_next)
//!   split by split. Level 0 is the input; higher levels are coarser.
//! - **Detail coefficients** (module [`detail`], [`DetailMode`]): every split re-inserts
//!   `v0` and places both endpoints at the survivor's current position plus their
//!   recorded offsets, expressed in a local frame of the collapsed edge's neighbourhood
//!   (the default), so that edits made at a coarse level ride along to the fine levels
//!   with their detail turned, scaled and sheared with them. A fine vertex moves only when
//!   its ancestor at the edited level moved ([`Hierarchy::ancestors`]): regions an edit
//!   left in place stay exact, bit for bit. Parts moved by an affine map can be marked
//!   ([`Hierarchy::mark_affine`]) to land exactly on its image. The seed paper's centroid
//!   translations remain as [`DetailMode::Translation`]. Without edits refinement
//!   restores the input bit for bit with the same handles and connectivity.
//! - **Atomic walks**: a walk refused part-way (the topology was changed behind the
//!   hierarchy's back) leaves everything where it started.
//! - **Labels**: sub-mesh labels attached with [`Hierarchy::attach_labels`] propagate
//!   through splits with the paper's Fig. 4 rule (see [`crate::labels`]); labels present
//!   when the hierarchy is built hold at every level (only edges within one sub-mesh
//!   collapse, [`HierarchyOptions::respect_labels`]), and
//!   [`Hierarchy::constrain_to_labels`] re-plans the hierarchy for labels defined later.
//!
//! ```
//! use halfedge::{generators, Hierarchy, HierarchyOptions};
//! let mesh = generators::icosphere(3);
//! let faces = mesh.n_faces();
//! let mut h = Hierarchy::build(mesh, &HierarchyOptions::rounds().with_target_faces(100)).unwrap();
//! assert!(h.mesh().n_faces() <= 200);
//! h.refine_to(0).unwrap();
//! assert_eq!(h.mesh().n_faces(), faces);
//! ```

pub mod bookmark;
pub mod detail;
pub mod heap;
pub mod legality;
pub mod motion;
pub mod outcome;
mod placements;
mod placer;
pub mod qem;
mod replan;
pub mod rounds;
mod unfold;

use std::ops::ControlFlow;

use glam::{DAffine3, DVec3};

use crate::attributes::Attribute;
use crate::binding::Binding;
use crate::collapse::Step;
use crate::labels::{self, Label};
use crate::{CollapseRecord, Error, HalfedgeId, Mesh, Result, VertexId};
pub use detail::DetailMode;
use detail::{Collapsed, Details, Placement};
pub use motion::Field;
use motion::Motion;

/// How many splits ahead [`Hierarchy::split_next`] prefetches the memory of the record it
/// will split (see [`crate::prefetch`]): first the collapsed edge, the positions and the
/// vertex halfedges the record names, then the halfedges and faces the collapsed edge's
/// tombstones name, then the links the removed edges' tombstones name.
const SPLIT_PREFETCH_DISTANCE: usize = 16;
const SIDES_PREFETCH_DISTANCE: usize = 11;
const LINKS_PREFETCH_DISTANCE: usize = 6;
/// How many splits ahead [`Hierarchy::split_next`] prefetches the positions a record's
/// detail coefficients read.
const DETAIL_PREFETCH_DISTANCE: usize = 5;
/// As [`SPLIT_PREFETCH_DISTANCE`] and [`SIDES_PREFETCH_DISTANCE`], for
/// [`Hierarchy::collapse_next`].
const COLLAPSE_PREFETCH_DISTANCE: usize = 16;
const COLLAPSE_SIDES_PREFETCH_DISTANCE: usize = 11;
const COLLAPSE_LINKS_PREFETCH_DISTANCE: usize = 7;
/// How many splits ahead [`Hierarchy::split_next`] prefetches the record's neighbour list
/// and coefficients (which the prefetch of the neighbours' positions reads, later).
const LIST_PREFETCH_DISTANCE: usize = 20;
/// How many splits ahead [`Hierarchy::split_next`] prefetches the first, second and third
/// halfedge of the walk around `v1` of the record it will split.
const MOVED_PREFETCH_DISTANCES: [usize; 3] = [6, 4, 2];
/// Prefetches the connectivity the splits a few records below `r` will touch (see
/// [`SPLIT_PREFETCH_DISTANCE`]): their edges, vertices and positions, then the halfedges
/// and faces their tombstones name, then the links, and the walk around `v1`, which is a
/// chain of loads, one more link of it per stage.
#[inline]
fn prefetch_splits_after(mesh: &Mesh, steps: &[Step], r: usize) {
    if let Some(ahead) = r.checked_sub(SPLIT_PREFETCH_DISTANCE) {
        mesh.prefetch_step(&steps[ahead], false);
    }
    if let Some(ahead) = r.checked_sub(SIDES_PREFETCH_DISTANCE) {
        mesh.prefetch_sides(&steps[ahead]);
    }
    if let Some(ahead) = r.checked_sub(LINKS_PREFETCH_DISTANCE) {
        mesh.prefetch_links(&steps[ahead], false);
    }
    for (step, distance) in MOVED_PREFETCH_DISTANCES.into_iter().enumerate() {
        if let Some(ahead) = r.checked_sub(distance) {
            mesh.prefetch_moved(&steps[ahead], step as u32);
        }
    }
}

/// Refinements after an edit of at least this many splits place on one thread and split
/// on another ([`Hierarchy::split_beside`]); shorter ones are not worth the hand-off.
const SPLIT_BESIDE_MIN: usize = 4096;
/// How many collapses ahead [`Hierarchy::collapse_next`] prefetches the first, second, …
/// halfedge of the walk around `v0` (the whole ring: one more than the split's walk and
/// the removed edges).
const RING_PREFETCH_DISTANCES: [usize; 6] = [7, 6, 5, 4, 3, 2];

/// The simplification method of a [`Hierarchy`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// The seed paper's rounds (section 3): planarity criterion, midpoint placement,
    /// locks; one round per level.
    Rounds,
    /// Garland–Heckbert quadric error priority decimation, levels cut every
    /// [`HierarchyOptions::level_ratio`] of the faces.
    Qem,
}

/// How to build a [`Hierarchy`]: the method, its parameters and the stop criteria.
///
/// Stop criteria (whichever comes first): the face count reaches
/// [`target_faces`](Self::target_faces) (the last level may then be a partial round), the
/// hierarchy has [`max_levels`](Self::max_levels) levels below the input, no collapse
/// within [`max_error`](Self::max_error) remains, or a level removes less than
/// [`min_level_reduction`](Self::min_level_reduction) of its faces.
///
/// **Reaching the face target with rounds.** The paper's planarity criterion (60°) runs
/// out on coarse levels: stars stop being nearly planar, and rounds stall thousands of
/// faces above a small target (a 1.6 M-face scan stalls near 8,000). With a face target
/// and [`relax_when_stalled`](Self::relax_when_stalled) (the default), a round that stalls
/// short of the target does not end the build: the planarity bound is widened by 15° and
/// the rounds go on (the stalled round's collapses and the next round's make one level),
/// again at every stall up to 180° (no planarity test), then the flip bound likewise up
/// to 90°. Every level above the first stall keeps the paper's criterion, the widened
/// bounds are kept from the level they were first needed, and
/// [`Hierarchy::build_outcome`] lists every widening. A build that still cannot reach
/// the target (every remaining collapse is topologically illegal, for instance separate
/// small components, or `max_error` forbids it) says why there, with the count of edges
/// each test refused in the last round. Without a face target the rounds stop at the
/// first stall, as in the paper. QEM reaches any target its legality rules allow.
#[derive(Clone, Debug)]
pub struct HierarchyOptions {
    /// The simplification method.
    pub method: Method,
    /// Rounds: the planarity bound, in radians. The star of edge `v0v1` (the faces
    /// around `v0` and `v1`) is planar enough when every face normal is within this angle
    /// of the normalised average of the star's face normals. Default 60°; 90° lets rounds
    /// go down to about a thousand faces on most meshes.
    pub max_normal_deviation: f64,
    /// Both methods: a collapse is refused when it turns a surviving face's normal by more
    /// than this angle, in radians (a flip is more than 90°). Default 45°: a tighter bound
    /// than OpenMesh's 90° keeps coarse levels smooth enough for later rounds to go on.
    pub max_flip_angle: f64,
    /// QEM: each level ends when the face count drops to this fraction of the previous
    /// level's (default 0.55, i.e. about 45 % of the faces removed per level, like rounds).
    pub level_ratio: f64,
    /// QEM: weight of the boundary constraint planes (planes through each boundary edge,
    /// perpendicular to its face), relative to the face planes. Default 10.
    pub boundary_weight: f64,
    /// Stop when the mesh has at most this many faces. Default 0 (no face target).
    pub target_faces: usize,
    /// Stop after this many levels below the input. Default: no limit.
    pub max_levels: usize,
    /// Error bound, a distance. Rounds: a collapse is skipped when the survivor's new
    /// position lies farther than this from the plane of a face of the star. QEM: the
    /// decimation stops when the cheapest collapse's error (the root mean square distance
    /// to the planes of its quadric, area-weighted) exceeds it. Default: no bound.
    pub max_error: f64,
    /// Stop after a level that removed less than this fraction of its faces (default 1 %).
    pub min_level_reduction: f64,
    /// How splits place their vertices after an edit at a coarser level (module
    /// [`detail`]): local frames with exact regions (the default) or the seed paper's
    /// centroid translations.
    pub detail_mode: DetailMode,
    /// Both methods: when the mesh has sub-mesh labels (the vertex attribute
    /// [`labels::LABEL_ATTRIBUTE`]), only edges whose two ends carry the same label
    /// collapse, so no edge ever joins two different sub-meshes at any level and every
    /// fine vertex is collapsed into a vertex of its own sub-mesh (or of the frontier, for
    /// frontier vertices). Default true.
    pub respect_labels: bool,
    /// Rounds with a face target: when a round stalls (removes less than
    /// [`min_level_reduction`](Self::min_level_reduction)) short of the target, widen the
    /// planarity bound, then the flip bound, and go on (see the type's docs). Default
    /// `true`; `false` stops at the first stall, as the paper does.
    pub relax_when_stalled: bool,
}

impl Default for HierarchyOptions {
    fn default() -> Self {
        Self {
            method: Method::Rounds,
            max_normal_deviation: 60f64.to_radians(),
            max_flip_angle: 45f64.to_radians(),
            level_ratio: 0.55,
            boundary_weight: 10.0,
            target_faces: 0,
            max_levels: usize::MAX,
            max_error: f64::INFINITY,
            min_level_reduction: 0.01,
            detail_mode: DetailMode::LocalFrame,
            respect_labels: true,
            relax_when_stalled: true,
        }
    }
}

impl HierarchyOptions {
    /// The paper's rounds with default parameters.
    pub fn rounds() -> Self {
        Self::default()
    }
    /// QEM decimation with default parameters.
    pub fn qem() -> Self {
        Self {
            method: Method::Qem,
            ..Self::default()
        }
    }
    /// Sets [`target_faces`](Self::target_faces).
    pub fn with_target_faces(mut self, faces: usize) -> Self {
        self.target_faces = faces;
        self
    }
    /// Sets [`max_levels`](Self::max_levels).
    pub fn with_max_levels(mut self, levels: usize) -> Self {
        self.max_levels = levels;
        self
    }
    /// Sets [`max_error`](Self::max_error).
    pub fn with_max_error(mut self, error: f64) -> Self {
        self.max_error = error;
        self
    }
    /// Sets [`max_normal_deviation`](Self::max_normal_deviation) (radians).
    pub fn with_max_normal_deviation(mut self, radians: f64) -> Self {
        self.max_normal_deviation = radians;
        self
    }

    /// Sets [`respect_labels`](Self::respect_labels).
    pub fn with_respect_labels(mut self, respect: bool) -> Self {
        self.respect_labels = respect;
        self
    }

    /// Sets [`detail_mode`](Self::detail_mode).
    pub fn with_detail_mode(mut self, mode: DetailMode) -> Self {
        self.detail_mode = mode;
        self
    }

    /// Sets [`max_flip_angle`](Self::max_flip_angle) (radians).
    pub fn with_max_flip_angle(mut self, radians: f64) -> Self {
        self.max_flip_angle = radians;
        self
    }

    /// Sets [`relax_when_stalled`](Self::relax_when_stalled).
    pub fn with_relax_when_stalled(mut self, relax: bool) -> Self {
        self.relax_when_stalled = relax;
        self
    }

    fn validate(&self) -> Result<()> {
        let bad = |what: String| Err(Error::InvalidArgument(what));
        if !(self.max_normal_deviation > 0.0 && self.max_normal_deviation <= std::f64::consts::PI) {
            return bad(format!(
                "max_normal_deviation must be in (0, π], got {}",
                self.max_normal_deviation
            ));
        }
        if !(self.max_flip_angle > 0.0 && self.max_flip_angle <= std::f64::consts::PI) {
            return bad(format!(
                "max_flip_angle must be in (0, π], got {}",
                self.max_flip_angle
            ));
        }
        if !(self.level_ratio > 0.0 && self.level_ratio < 1.0) {
            return bad(format!(
                "level_ratio must be in (0, 1), got {}",
                self.level_ratio
            ));
        }
        if !(self.boundary_weight >= 0.0 && self.boundary_weight.is_finite()) {
            return bad(format!(
                "boundary_weight must be finite and non-negative, got {}",
                self.boundary_weight
            ));
        }
        if self.max_error.is_nan() || self.max_error < 0.0 {
            return bad(format!(
                "max_error must be non-negative, got {}",
                self.max_error
            ));
        }
        if !(0.0..1.0).contains(&self.min_level_reduction) {
            return bad(format!(
                "min_level_reduction must be in [0, 1), got {}",
                self.min_level_reduction
            ));
        }
        Ok(())
    }
}

/// Progress of a [`Hierarchy::build_with_progress`] or
/// [`Hierarchy::build_cancellable`], reported at the end of every level
/// and every 65,536 collapses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BuildProgress {
    /// Levels completed so far (below the input).
    pub levels: usize,
    /// Faces left.
    pub faces: usize,
    /// Faces of the input.
    pub input_faces: usize,
}

/// Hands the build's progress (`levels` and faces now, of `input_faces`) to its callback;
/// [`Error::Cancelled`] when the callback says stop.
#[inline]
pub(crate) fn report(
    h: &Hierarchy,
    input_faces: usize,
    progress: &mut dyn FnMut(BuildProgress) -> ControlFlow<()>,
) -> Result<()> {
    let p = BuildProgress {
        levels: h.built_levels(),
        faces: h.mesh.n_faces(),
        input_faces,
    };
    match progress(p) {
        ControlFlow::Continue(()) => Ok(()),
        ControlFlow::Break(()) => Err(Error::Cancelled(format!(
            "hierarchy build stopped at {} levels, {} of {} faces left",
            p.levels, p.faces, p.input_faces
        ))),
    }
}

/// [`Error::NonFiniteCoordinate`] for the first live vertex with a NaN or infinite
/// coordinate: the build would spread it over the coarse levels.
fn check_positions(mesh: &Mesh) -> Result<()> {
    for v in mesh.vertices() {
        if let Some(&value) = mesh.position(v).to_array().iter().find(|c| !c.is_finite()) {
            return Err(Error::NonFiniteCoordinate {
                vertex: mesh.vertex_index(v),
                value,
            });
        }
    }
    Ok(())
}

/// Sub-mesh labels attached to a hierarchy: the vertex attribute and the number of
/// collapsed records when they were defined.
#[derive(Clone, Copy, Debug)]
struct LabelBinding {
    attribute: Attribute<VertexId, Label>,
    defined_at: usize,
}

/// A mesh with its progressive hierarchy: the collapse records of every level, their
/// detail coefficients, and the current position in the sequence (seed paper, section 3).
///
/// The hierarchy owns its mesh; read it with [`mesh`](Self::mesh) and edit positions or
/// attributes with [`mesh_mut`](Self::mesh_mut) at any level. Topology must only change
/// through the hierarchy (a topological edit would make the following split or collapse
/// fail with an error, never silently).
pub struct Hierarchy {
    mesh: Mesh,
    records: Records,
    /// Survivor position after the record's last collapse and its parameter `t` along
    /// the edge, for collapsing again after an edit and for knowing, when splitting,
    /// whether the survivor moved since: one byte for the rounds' two rules (at `v1`, at
    /// the midpoint), the position and parameter otherwise ([`placements`]).
    placements: placements::Placements,
    details: Details,
    /// Affine maps and fields the user said moved some vertices since the hierarchy
    /// placed them, and the edits' regions ([`Hierarchy::mark_affine`],
    /// [`Hierarchy::mark_field`], [`Hierarchy::mark_region`]).
    marks: Marks,
    /// Records collapsed at the end of each level; `level_ends[0] == 0` (the input).
    level_ends: Vec<usize>,
    /// Face count of each level, finest first.
    level_faces: Vec<usize>,
    /// Records currently collapsed (`records[..applied]`).
    applied: usize,
    method: Method,
    /// The options of the build (for [`Hierarchy::constrain_to_labels`]).
    options: HierarchyOptions,
    labels: Option<LabelBinding>,
    /// The mesh's [`Binding`] after the hierarchy's own last step: while its connectivity
    /// is unchanged nobody else changed it, and splits skip their checks. `None` for good
    /// once somebody else did: every later split is checked.
    stamp: Option<Binding>,
    /// `Some(the mesh's binding)` while no position has been changed since the build
    /// except by the hierarchy's own steps (the hierarchy writes positions without
    /// counting): then every neighbour is where it was when its record was collapsed,
    /// every split restores its recorded positions, and steps skip the detail
    /// coefficients. `None` for good after the first edit.
    clean_positions: Option<Binding>,
    /// Where the vertices were before the edits (see [`Rest`]), newest last; empty while
    /// nothing was edited.
    rests: Vec<Rest>,
    /// Records at or above this index were collapsed since the last call of
    /// [`Hierarchy::mesh_mut`] (or the build): their neighbourhoods were then where the
    /// current positions have them, unless edited since.
    consistent_from: usize,
    /// How the build ended ([`Hierarchy::build_outcome`]).
    outcome: outcome::BuildOutcome,
    /// This hierarchy's number, for the level tags of its mesh (see
    /// [`crate::Binding`]).
    id: u64,
    /// Which records were made again from the current mesh (a walk coarser from an edited
    /// level), and when: a [`bookmark::LevelBookmark`] fits only while the records below
    /// its level are those it was taken with.
    refreshes: bookmark::Refreshes,
}

/// The collapse records of a hierarchy: the compact records the walks use, and apart
/// (cold) what only a checked split compares: each record's fingerprint, and once for all
/// records the mesh instance they were made on.
#[derive(Clone, Debug, Default)]
pub(crate) struct Records {
    steps: Vec<Step>,
    fingerprints: Vec<u64>,
    /// The mesh's [`Binding`] after the hierarchy's last step while it
    /// trusted its mesh: every record was made on that mesh instance (or one it was
    /// cloned from) at or before that change count, which is what
    /// `Mesh::is_own_history` needs to vouch for a record's indices.
    origin: Option<Binding>,
}

impl Records {
    /// Number of records.
    #[inline]
    pub(crate) fn len(&self) -> usize {
        self.steps.len()
    }
    /// Record `r`.
    #[inline]
    pub(crate) fn get(&self, r: usize) -> Option<&Step> {
        self.steps.get(r)
    }
    /// The last record.
    #[inline]
    pub(crate) fn last(&self) -> Option<&Step> {
        self.steps.last()
    }
    /// Appends a record.
    #[inline]
    fn push(&mut self, step: Step, fingerprint: u64) {
        self.steps.push(step);
        self.fingerprints.push(fingerprint);
    }
    /// Empties the records, keeping their memory, with room for `n`.
    pub(crate) fn recycle(&mut self, n: usize) {
        self.steps.clear();
        self.steps.reserve(n);
        self.fingerprints.clear();
        self.fingerprints.reserve(n);
        self.origin = None;
    }
    /// Moves the records into `steps` and `fingerprints` (see [`Prefaulted`]).
    fn adopt(&mut self, steps: Vec<Step>, fingerprints: Vec<u64>) {
        adopt(&mut self.steps, steps);
        adopt(&mut self.fingerprints, fingerprints);
    }
    /// Gives back unused capacity.
    pub(crate) fn shrink_to_fit(&mut self) {
        self.steps.shrink_to_fit();
        self.fingerprints.shrink_to_fit();
    }
    /// Heap bytes.
    fn heap_bytes(&self) -> usize {
        self.steps.capacity() * std::mem::size_of::<Step>() + self.fingerprints.capacity() * 8
    }
}

impl std::ops::Index<usize> for Records {
    type Output = Step;
    #[inline]
    fn index(&self, r: usize) -> &Step {
        &self.steps[r]
    }
}

/// A new hierarchy number.
fn next_hierarchy_id() -> u64 {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
    NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

/// The positions edits started from, for refinement to interpolate the edits' motion
/// ([`DetailMode::LocalFrame`]): a copy of every live vertex's position taken when
/// [`Hierarchy::mesh_mut`] hands out the mesh, kept up to date by the splits of the
/// records it serves (each puts its recorded positions in). It serves the records
/// `floor..ceil`, whose neighbourhoods were at these positions when they were collapsed:
/// those collapsed since the previous edit, up to the level it was taken at; a collapse
/// (which takes the current positions into its record) ends the range below itself.
#[derive(Clone, Debug)]
struct Rest {
    positions: Vec<[f64; 3]>,
    floor: usize,
    ceil: usize,
    /// The splits of records `synced..ceil` have put their positions in (the others are
    /// put in when a split first needs the copy: a refinement whose every survivor moved
    /// with its neighbours, a translation or rotation of the whole level, never does).
    synced: usize,
    /// A split needed the copy: from then on every split puts its positions in.
    active: bool,
}

/// At most this many [`Rest`]s are kept (edits at levels walked coarser from one
/// another); records only older ones served fall back to the local frame alone.
const MAX_RESTS: usize = 4;

impl Rest {
    /// The live vertices' positions of `mesh` (other slots zero, left untouched by the
    /// allocator: a coarse level of a large mesh costs its live vertices only).
    fn take(mesh: &Mesh, floor: usize, ceil: usize) -> Self {
        let mut positions = vec![[0.0f64; 3]; mesh.vertex_slots()];
        for v in mesh.vertices() {
            let i = mesh.vertex_index(v);
            positions[i] = mesh.positions[i].to_array();
        }
        Self {
            positions,
            floor,
            ceil,
            synced: ceil,
            active: false,
        }
    }

    /// True when this copy serves record `r`.
    fn serves(&self, r: usize) -> bool {
        (self.floor..self.ceil).contains(&r)
    }
}

/// The clone's mesh is a mesh instance of its own; the clone trusts it exactly when the
/// original trusts its mesh (see [`Binding`]).
impl Clone for Hierarchy {
    fn clone(&self) -> Self {
        let mesh = self.mesh.clone();
        let trusted = self.trusts_mesh();
        let clean = self.positions_unedited();
        let mut clone = Self {
            stamp: trusted.then(|| mesh.binding()),
            clean_positions: clean.then(|| mesh.binding()),
            rests: self.rests.clone(),
            consistent_from: self.consistent_from,
            mesh,
            records: self.records.clone(),
            placements: self.placements.clone(),
            details: self.details.clone(),
            marks: self.marks.clone(),
            level_ends: self.level_ends.clone(),
            level_faces: self.level_faces.clone(),
            applied: self.applied,
            method: self.method,
            options: self.options.clone(),
            labels: self.labels,
            outcome: self.outcome.clone(),
            id: next_hierarchy_id(),
            refreshes: self.refreshes.clone(),
        };
        clone.tag_level();
        clone
    }
}

impl std::fmt::Debug for Hierarchy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Hierarchy")
            .field("method", &self.method)
            .field("levels", &self.level_faces)
            .field("records", &self.records.len())
            .field("applied", &self.applied)
            .field("mesh", &self.mesh)
            .finish()
    }
}

/// # Building
impl Hierarchy {
    /// Builds the hierarchy of `mesh` with `options` (see [`HierarchyOptions`] and the
    /// [module docs](self)); the mesh is left at the coarsest level.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] for options out of range,
    /// [`Error::NonFiniteCoordinate`] for a vertex position that is NaN or infinite.
    pub fn build(mesh: Mesh, options: &HierarchyOptions) -> Result<Self> {
        Self::build_with_progress(mesh, options, &mut |_| {})
    }

    /// [`build`](Self::build), reporting progress (levels and faces, for a progress bar).
    ///
    /// # Errors
    /// As [`build`](Self::build).
    pub fn build_with_progress(
        mesh: Mesh,
        options: &HierarchyOptions,
        progress: &mut dyn FnMut(BuildProgress),
    ) -> Result<Self> {
        Self::build_cancellable(mesh, options, &mut |p| {
            progress(p);
            ControlFlow::Continue(())
        })
    }

    /// [`build_with_progress`](Self::build_with_progress) whose callback may stop the
    /// build: returning [`ControlFlow::Break`] from a report ends it with
    /// [`Error::Cancelled`] (the mesh, moved in, is dropped). Reports come at the end of
    /// every level and every 65,536 collapses, so a build stops within a fraction of a
    /// second of being asked to — what an interactive application needs for a Cancel
    /// button.
    ///
    /// # Errors
    /// As [`build`](Self::build), and [`Error::Cancelled`].
    pub fn build_cancellable(
        mesh: Mesh,
        options: &HierarchyOptions,
        progress: &mut dyn FnMut(BuildProgress) -> ControlFlow<()>,
    ) -> Result<Self> {
        options.validate()?;
        check_positions(&mesh)?;
        Self::build_validated(mesh, options, Storage::default(), progress)
    }

    /// The build after `options` and the positions of `mesh` were checked: fails only
    /// when `progress` asks it to stop. The records and detail coefficients are written
    /// into `storage`'s buffers (cleared, their memory kept: see
    /// [`edit_input`](Self::edit_input)).
    fn build_validated(
        mesh: Mesh,
        options: &HierarchyOptions,
        storage: Storage,
        progress: &mut dyn FnMut(BuildProgress) -> ControlFlow<()>,
    ) -> Result<Self> {
        let faces = mesh.n_faces();
        let mut h = Self::unbuilt(mesh, options, storage);
        match options.method {
            Method::Rounds => rounds::build(&mut h, options, progress)?,
            Method::Qem => {
                qem::build(&mut h, options, progress)?;
                outcome::finish(&mut h, options, None);
            }
        }
        report(&h, faces, progress)?;
        h.finish_build();
        Ok(h)
    }

    /// A hierarchy of `mesh` with no record yet, its buffers taken from `storage` and
    /// sized for a full build.
    pub(crate) fn unbuilt(mesh: Mesh, options: &HierarchyOptions, storage: Storage) -> Self {
        let faces = mesh.n_faces();
        let expected_records = mesh.n_vertices();
        let Storage {
            mut records,
            mut placements,
            details,
        } = storage;
        records.recycle(expected_records);
        placements.recycle(expected_records, options.method == Method::Qem);
        Self {
            mesh,
            records,
            placements,
            details: match details {
                Some(old) => old.recycled(options.detail_mode, expected_records),
                None => Details::with_capacity(options.detail_mode, expected_records),
            },
            marks: Marks::default(),
            level_ends: vec![0],
            level_faces: vec![faces],
            applied: 0,
            method: options.method,
            options: options.clone(),
            labels: None,
            stamp: None,
            clean_positions: None,
            rests: Vec::new(),
            consistent_from: 0,
            outcome: outcome::BuildOutcome::default(),
            id: next_hierarchy_id(),
            refreshes: bookmark::Refreshes::default(),
        }
    }

    /// Ends a build: the buffers fit the records, the hierarchy trusts its mesh and its
    /// positions, the mesh carries the level tag.
    pub(crate) fn finish_build(&mut self) {
        self.records.shrink_to_fit();
        self.placements.shrink_to_fit();
        self.stamp = Some(self.mesh.binding());
        self.clean_positions = Some(self.mesh.binding());
        self.tag_level();
    }

    /// Collapses `h` while building: records the detail coefficients, collapses, moves the
    /// survivor to `p` (parameter `t` along the edge from `v1` to `v0`), appends the record.
    /// The caller has checked the collapse with [`legality::topology`].
    #[inline]
    pub(crate) fn record_collapse(&mut self, h: HalfedgeId, p: DVec3, t: f64) {
        debug_assert_eq!(self.applied, self.records.len());
        let mesh = &self.mesh;
        let v0 = mesh.from_vertex(h);
        let v1 = mesh.to_vertex(h);
        let at = Collapsed {
            p0: mesh.position(v0),
            p1: mesh.position(v1),
            placed: p,
        };
        let (i0, i1) = (mesh.vertex_index(v0) as u32, mesh.vertex_index(v1) as u32);
        self.details.push(
            mesh.positions(),
            mesh.adjacent_vertices(v0)
                .map(|w| mesh.vertex_index(w) as u32),
            mesh.adjacent_vertices(v1)
                .map(|w| mesh.vertex_index(w) as u32),
            [i0, i1],
            at,
        );
        // The methods have just checked `is_collapse_ok` through the legality layer.
        let (record, fingerprint) = self.mesh.collapse_unchecked(h);
        let i1 = self.mesh.vertex_index(v1);
        self.mesh.positions[i1] = p;
        self.placements.push(&record, p, t);
        self.records.push(record, fingerprint);
        self.applied += 1;
    }

    /// Collapses record `r` of `source` again on this hierarchy's mesh, where the star of
    /// its edge is exactly as it was when `source` took it (same elements, links and
    /// positions: see [`replan`]): the record, its placement and its detail coefficients
    /// are `source`'s, nothing is computed again.
    pub(crate) fn replay_collapse(&mut self, source: &Hierarchy, r: usize) {
        debug_assert_eq!(self.applied, self.records.len());
        let old = &source.records[r];
        let fingerprint = source.records.fingerprints[r];
        let record = self.mesh.recollapse_unchecked(old, fingerprint);
        let p = source.placements.placed(r, old);
        self.mesh.positions[old.v1 as usize] = p;
        self.details.push_copy(&source.details, r);
        self.placements.push_copy(&source.placements, r);
        self.records.push(record, fingerprint);
        self.applied += 1;
    }

    /// True while positions are exactly as the hierarchy's own steps left them (see
    /// `clean_positions`), without forgetting it when they are not.
    pub(crate) fn positions_clean(&self) -> bool {
        self.positions_unedited() && self.trusts_mesh()
    }

    /// The sub-mesh labels collapses must respect while building (by vertex index), or
    /// nothing (see [`HierarchyOptions::respect_labels`]).
    pub(crate) fn label_constraint(&self, options: &HierarchyOptions) -> Vec<Label> {
        if !options.respect_labels {
            return Vec::new();
        }
        self.mesh
            .find_attribute::<VertexId, Label>(labels::LABEL_ATTRIBUTE)
            .and_then(|a| self.mesh.attribute_values(a).ok())
            .map(<[Label]>::to_vec)
            .unwrap_or_default()
    }

    /// Closes the current level at the current record (building only).
    pub(crate) fn close_level(&mut self) {
        if *self.level_ends.last().unwrap_or(&0) < self.applied {
            self.level_ends.push(self.applied);
            self.level_faces.push(self.mesh.n_faces());
        }
    }

    /// Levels below the input built so far.
    pub(crate) fn built_levels(&self) -> usize {
        self.level_ends.len() - 1
    }
}

/// Output buffers for a build's next records, made on another thread while the build
/// runs, with every page of their memory written once: a build writes some 215–250 bytes of
/// records and detail coefficients per collapse into fresh memory, and the page faults
/// of first writes (some fifty thousand pages for 1.6 M faces) otherwise fall in the
/// build's single-threaded loop. The build adopts the buffers when they are ready (see
/// [`Hierarchy::adopt_prefaulted`]); what it holds is the same either way.
#[derive(Debug)]
pub(crate) struct Prefaulted {
    steps: Vec<Step>,
    fingerprints: Vec<u64>,
    rules: Vec<u8>,
    stored: Vec<(DVec3, f64)>,
    details: detail::DetailBuffers,
}

/// Fewest records expected for [`Hierarchy::prefault`] to make buffers ahead (a smaller
/// build is over before they would be ready).
const PREFAULT_RECORDS: usize = 1 << 12;

/// An empty vector with room for `capacity` elements, the memory of the first `touched`
/// mapped (an element a page written with zero bytes).
fn prefaulted<T>((capacity, touched): (usize, usize)) -> Vec<T> {
    let mut v = Vec::with_capacity(capacity);
    let step = (4096 / std::mem::size_of::<T>().max(1)).max(1);
    for slot in v.spare_capacity_mut()[..touched.min(capacity)]
        .iter_mut()
        .step_by(step)
    {
        *slot = std::mem::MaybeUninit::zeroed();
    }
    std::hint::black_box(&mut v);
    v
}

/// Makes `new` (empty) hold `old`'s elements and take its place.
fn adopt<T: Copy>(old: &mut Vec<T>, mut new: Vec<T>) {
    new.clear();
    new.extend_from_slice(old);
    *old = new;
}

impl Hierarchy {
    /// Starts making [`Prefaulted`] buffers, as large as the ones reserved, the memory
    /// of the first `records` records mapped, on another thread; `None` for a small
    /// build (or when no thread can be started). A build that ends first drops the
    /// handle: the thread finishes and frees what it made.
    pub(crate) fn prefault(&self, records: usize) -> Option<std::thread::JoinHandle<Prefaulted>> {
        let capacity = self.records.steps.capacity();
        let records = records.min(capacity);
        if records < PREFAULT_RECORDS {
            return None;
        }
        // The buffers' sizes are read here, the memory is made there.
        let sizes = (capacity, records);
        let (rules, stored) = self.placements.capacities();
        let (rules, stored) = (
            (rules.max(capacity), records),
            (stored, records.min(stored)),
        );
        let details = self.details.prefaulted_sizes(records);
        std::thread::Builder::new()
            .name("prefault".into())
            .spawn(move || Prefaulted {
                steps: prefaulted(sizes),
                fingerprints: prefaulted(sizes),
                rules: prefaulted(rules),
                stored: prefaulted(stored),
                details: details.make(),
            })
            .ok()
    }

    /// Moves the records, placements and detail coefficients into `buffers`.
    pub(crate) fn adopt_prefaulted(&mut self, buffers: Prefaulted) {
        let Prefaulted {
            steps,
            fingerprints,
            rules,
            stored,
            details,
        } = buffers;
        self.records.adopt(steps, fingerprints);
        self.placements.adopt(rules, stored);
        self.details.adopt(details);
    }
}

/// # Levels and stepping
impl Hierarchy {
    /// The mesh at the current position.
    #[inline]
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }
    /// The mesh at the current position, for editing positions and attributes. Do not
    /// change its topology: the next split or collapse of the hierarchy would be refused.
    ///
    /// With [`DetailMode::LocalFrame`], the first call after a walk coarser (or the
    /// build) keeps a copy of the live vertices' positions, which refinement needs to
    /// interpolate the edit's motion (one copy of the current level's vertices).
    #[inline]
    pub fn mesh_mut(&mut self) -> &mut Mesh {
        let covered = self.rests.last().is_some_and(|r| r.ceil >= self.applied);
        if !covered && self.details.mode() == DetailMode::LocalFrame {
            let floor = if self.positions_unedited() {
                0
            } else {
                self.consistent_from
            };
            if self.rests.len() == MAX_RESTS {
                self.rests.remove(0);
            }
            self.rests.push(Rest::take(&self.mesh, floor, self.applied));
        }
        self.consistent_from = self.applied;
        &mut self.mesh
    }
    /// Gives the mesh back, at its current level.
    pub fn into_mesh(self) -> Mesh {
        self.mesh
    }
    /// The method the hierarchy was built with.
    pub fn method(&self) -> Method {
        self.method
    }
    /// Number of levels, the input (level 0) included.
    pub fn n_levels(&self) -> usize {
        self.level_ends.len()
    }
    /// Index of the coarsest level.
    pub fn coarsest_level(&self) -> usize {
        self.level_ends.len() - 1
    }
    /// Face count of every level, finest (the input) first.
    pub fn level_face_counts(&self) -> &[usize] {
        &self.level_faces
    }
    /// Number of records collapsed at the end of every level (`[0, …]`).
    pub fn level_ends(&self) -> &[usize] {
        &self.level_ends
    }
    /// All collapse records, in collapse order, made on demand from the compact records
    /// the hierarchy keeps (a record that is collapsed now fits
    /// [`Mesh::vertex_split`] of the hierarchy's mesh, or of a clone of it, like the
    /// record [`Mesh::collapse`] gives).
    pub fn records(&self) -> Vec<CollapseRecord> {
        let origin = self.origin();
        self.records
            .steps
            .iter()
            .zip(&self.records.fingerprints)
            .filter_map(|(step, &fingerprint)| self.mesh.public_record(step, fingerprint, origin))
            .collect()
    }
    /// Number of collapse records (the collapses from the input to the coarsest level).
    pub fn n_records(&self) -> usize {
        self.records.len()
    }
    /// Number of records currently collapsed: the position in the sequence.
    pub fn applied(&self) -> usize {
        self.applied
    }
    /// The current level, or `None` between two levels (after single steps).
    pub fn current_level(&self) -> Option<usize> {
        self.level_ends.iter().position(|&e| e == self.applied)
    }
    /// The level the mesh is at or, between levels, the finer level it has left.
    pub fn level_at_or_finer(&self) -> usize {
        self.level_ends.partition_point(|&e| e <= self.applied) - 1
    }
    /// Bytes of memory held by the records and detail coefficients.
    pub fn record_bytes(&self) -> usize {
        self.records.heap_bytes() + self.placements.heap_bytes() + self.details.heap_bytes()
    }

    /// The mesh instance and change count every record was made at or before (see
    /// [`Records::origin`]).
    fn origin(&self) -> (u64, u64) {
        self.stamp
            .or(self.records.origin)
            .map_or((0, 0), |b| b.history_point())
    }

    /// True while nobody but the hierarchy changed its mesh's connectivity since its own
    /// last step.
    #[inline]
    fn trusts_mesh(&self) -> bool {
        self.stamp.is_some_and(|b| b.same_connectivity(&self.mesh))
    }

    /// True while no position was changed since the build except by the hierarchy's own
    /// steps (see `clean_positions`).
    #[inline]
    fn positions_unedited(&self) -> bool {
        self.clean_positions
            .is_some_and(|b| b.same_positions(&self.mesh))
    }

    /// Stops trusting the mesh (somebody else changed its connectivity): every later step
    /// is checked.
    fn distrust(&mut self) {
        if let Some(stamp) = self.stamp.take() {
            self.records.origin = Some(stamp);
        }
    }

    fn check_level(&self, level: usize) -> Result<usize> {
        self.level_ends.get(level).copied().ok_or_else(|| {
            Error::InvalidArgument(format!(
                "level {level} does not exist (levels 0..={})",
                self.coarsest_level()
            ))
        })
    }

    /// Moves to `level` (coarser or finer).
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] for a level that does not exist; a refused split or
    /// collapse if the topology was changed behind the hierarchy's back.
    pub fn go_to_level(&mut self, level: usize) -> Result<()> {
        let end = self.check_level(level)?;
        self.seek(end)
    }

    /// Coarsens to `level` (which must not be finer than the current position).
    ///
    /// # Errors
    /// As [`go_to_level`](Self::go_to_level), and [`Error::InvalidArgument`] when `level`
    /// is finer than the current position.
    pub fn coarsen_to(&mut self, level: usize) -> Result<()> {
        let end = self.check_level(level)?;
        if end < self.applied {
            return Err(Error::InvalidArgument(format!(
                "coarsen_to({level}): the mesh is already coarser than level {level}"
            )));
        }
        self.seek(end)
    }

    /// Refines to `level` (which must not be coarser than the current position).
    ///
    /// # Errors
    /// As [`go_to_level`](Self::go_to_level), and [`Error::InvalidArgument`] when `level`
    /// is coarser than the current position.
    pub fn refine_to(&mut self, level: usize) -> Result<()> {
        let end = self.check_level(level)?;
        if end > self.applied {
            return Err(Error::InvalidArgument(format!(
                "refine_to({level}): the mesh is already finer than level {level}"
            )));
        }
        self.seek(end)
    }

    /// Collapses or splits record by record until `applied` records are collapsed.
    ///
    /// The walk is atomic: when a step is refused (the topology was changed behind the
    /// hierarchy's back), the mesh, its positions and attributes, and the hierarchy are
    /// put back exactly as they were before the walk, and the error is returned.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] when `applied` exceeds the number of records; a refused
    /// split or collapse (the topology was changed behind the hierarchy's back).
    pub fn seek(&mut self, applied: usize) -> Result<()> {
        if applied > self.records.len() {
            return Err(Error::InvalidArgument(format!(
                "seek({applied}): the hierarchy has {} records",
                self.records.len()
            )));
        }
        if self.trusts_mesh() {
            // Every step since the build was the hierarchy's own: no step can be refused.
            return self.walk(applied);
        }
        let saved = Saved::take(self, applied);
        match self.walk(applied) {
            Ok(()) => Ok(()),
            Err(e) => {
                saved.restore(self);
                Err(e)
            }
        }
    }

    /// [`seek`](Self::seek) without the way back.
    fn walk(&mut self, applied: usize) -> Result<()> {
        while self.applied < applied {
            self.collapse_next()?;
        }
        let finer = self.applied > applied;
        if self.applied >= applied + SPLIT_BESIDE_MIN
            && self.trusts_mesh()
            && rayon::current_num_threads() > 1
        {
            let clean = self.positions_are_clean();
            self.split_beside(applied, clean)?;
        }
        while self.applied > applied {
            self.split_next()?;
        }
        if finer {
            self.unfold_refinement();
        }
        Ok(())
    }

    /// The attached labels when splitting record `r` must classify its vertex (the labels
    /// were defined at a coarser position).
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] when the label attribute was removed from the mesh.
    fn labels_to_classify(&self, r: usize) -> Result<Option<LabelBinding>> {
        match self.labels.filter(|b| r < b.defined_at) {
            Some(binding) if !self.mesh.has_attribute(binding.attribute) => {
                Err(Error::InvalidArgument(
                    "the label attribute attached to the hierarchy was removed from its mesh \
                     (detach_labels, or attach_labels again)"
                        .into(),
                ))
            }
            labels => Ok(labels),
        }
    }

    /// The parts of the hierarchy that place split vertices ([`placer::Placer`]).
    fn placer(&mut self) -> placer::Placer<'_> {
        placer::Placer {
            steps: &self.records.steps,
            placements: &self.placements,
            details: &self.details,
            marks: &mut self.marks,
            rests: &mut self.rests,
            positions: &mut self.mesh.positions,
        }
    }

    /// [`split_next`](Self::split_next) until `applied` records are collapsed, for a
    /// hierarchy that trusts its mesh (`clean`: its positions are as its own steps left
    /// them, so every vertex goes to its recorded position): the placements run on this thread,
    /// the splits (connectivity and labels) on another, each record split once its
    /// placement is known. The two touch disjoint data (see [`placer`]), and the result
    /// is the same bit for bit. A placement that overflows stops the walk just above its
    /// record, as `split_next` does.
    ///
    /// # Errors
    /// [`Error::Overflow`] as `split_next` (the records above it are split); an
    /// [`Error::InvalidArgument`] when the label attribute was removed (nothing changed).
    fn split_beside(&mut self, applied: usize, clean: bool) -> Result<()> {
        use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
        let top = self.applied;
        let labels = self.labels_to_classify(applied)?;
        // Every record from `placed` up is placed; `failed`: no more will be.
        let placed = AtomicUsize::new(top);
        let failed = AtomicBool::new(false);
        let mut positions = std::mem::take(&mut self.mesh.positions);
        let steps = &self.records.steps;
        let mut placer = placer::Placer {
            steps,
            placements: &self.placements,
            details: &self.details,
            marks: &mut self.marks,
            rests: &mut self.rests,
            positions: &mut positions,
        };
        let mesh = &mut self.mesh;
        // How far the splits went (read after both threads are done, even after a panic).
        let split_to = AtomicUsize::new(top);
        /// Tells the splitting thread to stop when the placing thread ends early, by an
        /// error or by a panic (a user's field that panics), so that it never waits on.
        struct StopOnExit<'a>(&'a AtomicBool);
        impl Drop for StopOnExit<'_> {
            fn drop(&mut self) {
                self.0.store(true, Ordering::Release);
            }
        }
        let walked = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            rayon::join(
                || -> Result<()> {
                    let _stop = StopOnExit(&failed);
                    for r in (applied..top).rev() {
                        if !clean {
                            placer.prefetch_ahead(r);
                        }
                        let (placement, mark) = placer.placement(r, clean);
                        if let Placement::At([q0, q1]) = placement {
                            if !(q0.is_finite() && q1.is_finite()) {
                                failed.store(true, Ordering::Release);
                                let record = &steps[r];
                                return Err(Error::Overflow(format!(
                                    "splitting vertex {} from {} would put them at {q0} and {q1}",
                                    record.v0, record.v1
                                )));
                            }
                        }
                        placer.settle(r, placement, mark);
                        placed.store(r, Ordering::Release);
                    }
                    Ok(())
                },
                || -> usize {
                    let mut r = top;
                    while r > applied {
                        let next = r - 1;
                        // This thread never gets ahead of the placements: a split is made
                        // only once its record's placement is known to be good.
                        let mut spins = 0u32;
                        while placed.load(Ordering::Acquire) > next {
                            if failed.load(Ordering::Acquire)
                                && placed.load(Ordering::Acquire) > next
                            {
                                return r;
                            }
                            // Waiting long means the placing thread is not running (a busy
                            // machine): give the core back rather than spin.
                            spins += 1;
                            if spins < 1 << 12 {
                                std::hint::spin_loop();
                            } else {
                                std::thread::yield_now();
                            }
                        }
                        prefetch_splits_after(mesh, steps, next);
                        let record = &steps[next];
                        mesh.vertex_split_connectivity(record);
                        if let Some(binding) = labels.filter(|b| next < b.defined_at) {
                            let v0 = mesh.vh(record.v0);
                            // A label attribute removed by the user since it was
                            // attached has nothing left to label.
                            let _removed = labels::classify_split(mesh, binding.attribute, v0);
                        }
                        r = next;
                        split_to.store(r, Ordering::Relaxed);
                    }
                    r
                },
            )
        }));
        // Whatever happened, the mesh gets its positions back and the hierarchy the
        // position its splits reached: every record split was placed first.
        self.mesh.positions = positions;
        let split_to = split_to.into_inner();
        self.applied = split_to;
        self.consistent_from = self.consistent_from.min(split_to);
        self.stamp = Some(self.mesh.binding());
        self.tag_level();
        match walked {
            Ok((placing, _)) => placing,
            Err(panic) => std::panic::resume_unwind(panic),
        }
    }

    /// One step coarser: collapses the next record again. The survivor goes to its build
    /// time position; if an endpoint moved since the record was taken (an edit at a
    /// finer level), it goes to the same place relative to the edge's current endpoints.
    /// The record's detail coefficients are recomputed from the current positions. Drops
    /// the affine marks ([`mark_affine`](Self::mark_affine)). Returns `false` at the
    /// coarsest level.
    ///
    /// # Errors
    /// The kernel's refusal ([`Error::CollapseRefused`]) if the topology was changed
    /// behind the hierarchy's back; nothing is changed then.
    pub fn collapse_next(&mut self) -> Result<bool> {
        let r = self.applied;
        // Decided before the collapse changes the mesh's topology stamp.
        let clean = self.positions_are_clean();
        if r < self.records.len() {
            // A copy of the positions before an edit that has not taken in every split
            // since catches up now: the collapse replaces the record it would read them from.
            for k in 0..self.rests.len() {
                self.placer().sync_rest(k, r);
            }
        }
        let Some(&old) = self.records.get(r) else {
            return Ok(false);
        };
        if !self.trusts_mesh() {
            self.distrust();
        }
        // The edge must still join the record's two vertices (checked on the slot indices,
        // which may be out of range on a mesh the hierarchy cannot vouch for).
        let (i0, i1, hi) = (old.v0 as usize, old.v1 as usize, old.v0v1 as usize);
        let mesh = &self.mesh;
        let joins = mesh.halfedge_slots_.is_live_index(hi)
            && mesh.he.get(hi ^ 1).map(|rec| rec.to) == Some(old.v0)
            && mesh.he.get(hi).map(|rec| rec.to) == Some(old.v1)
            && mesh.vertex_slots_.is_live_index(i0)
            && mesh.vertex_slots_.is_live_index(i1);
        if !joins
            || (self.stamp.is_none() && !self.details.in_bounds(r, self.mesh.positions().len()))
        {
            return Err(Error::CollapseRefused {
                halfedge: if hi < mesh.he.len() {
                    mesh.hh(old.v0v1)
                } else {
                    HalfedgeId::default()
                },
                reason: crate::CollapseVeto::EdgeDeleted,
            });
        }
        let (v0, v1, h) = (mesh.vh(old.v0), mesh.vh(old.v1), mesh.hh(old.v0v1));
        if let Some(ahead) = self.records.get(r + COLLAPSE_PREFETCH_DISTANCE) {
            self.mesh.prefetch_step(ahead, true);
        }
        if let Some(ahead) = self.records.get(r + COLLAPSE_SIDES_PREFETCH_DISTANCE) {
            self.mesh.prefetch_sides(ahead);
        }
        if let Some(ahead) = self.records.get(r + COLLAPSE_LINKS_PREFETCH_DISTANCE) {
            self.mesh.prefetch_links(ahead, true);
        }
        for (step, distance) in RING_PREFETCH_DISTANCES.into_iter().enumerate() {
            if let Some(ahead) = self.records.get(r + distance) {
                self.mesh.prefetch_collapse_ring(ahead, step as u32);
            }
        }
        let p0 = self.mesh.positions[i0];
        let p1 = self.mesh.positions[i1];
        let p = self.placements.again(r, &old, p0, p1);
        if !p.is_finite() {
            return Err(Error::Overflow(format!(
                "collapsing {v0} → {v1} would put {v1} at {p} (positions {p0} and {p1})"
            )));
        }
        // While the hierarchy trusts its mesh, the topology is exactly the one the build
        // collapsed this record in (every step since was its own, and splits are exact
        // inverses), so the collapse is as legal as it was then.
        let (record, fingerprint) = if self.stamp.is_some() {
            let fingerprint = self.records.fingerprints[r];
            (
                self.mesh.recollapse_unchecked(&old, fingerprint),
                fingerprint,
            )
        } else {
            let record = self.mesh.collapse(h)?;
            (*record.step(), record.fingerprint())
        };
        if !clean {
            self.refreshes.record(r);
            let at = Collapsed {
                p0: record.p0,
                p1: record.p1,
                placed: p,
            };
            self.details.refresh(r, self.mesh.positions(), at);
        }
        self.mesh.positions[i1] = p;
        self.placements.set_placed(r, p);
        self.records.steps[r] = record;
        self.records.fingerprints[r] = fingerprint;
        self.applied += 1;
        // Marks describe motion relative to the records below the current position; a
        // record collapsed again now holds the moved positions.
        self.marks.clear();
        for rest in &mut self.rests {
            rest.ceil = rest.ceil.min(r);
        }
        self.rests.retain(|rest| rest.floor < rest.ceil);
        self.stamp = self.stamp.map(|_| self.mesh.binding());
        self.tag_level();
        Ok(true)
    }

    /// True while positions are exactly as the hierarchy's own steps left them (see
    /// `clean_positions`); false for good after the first outside edit or topology change.
    fn positions_are_clean(&mut self) -> bool {
        let clean = self.positions_unedited() && self.trusts_mesh();
        if !clean {
            self.clean_positions = None;
        }
        clean
    }

    /// One step finer: splits the last collapsed record, re-inserting `v0` (same handle)
    /// and placing both endpoints by the detail coefficients (see [`DetailMode`]): at
    /// their recorded positions when the survivor did not move, at the image of them by
    /// the survivor's affine mark when it has one, else by the local frame. Sub-mesh
    /// labels defined at a finer position are kept; otherwise `v0` is classified by the
    /// paper's Fig. 4 rule. Returns `false` at the input level.
    ///
    /// # Errors
    /// The kernel's refusal ([`Error::SplitRefused`]) if the topology was changed behind
    /// the hierarchy's back; nothing is changed then.
    pub fn split_next(&mut self) -> Result<bool> {
        if self.applied == 0 {
            return Ok(false);
        }
        let r = self.applied - 1;
        let trusted = self.trusts_mesh();
        if !trusted {
            self.distrust();
            if !self.details.in_bounds(r, self.mesh.positions().len()) {
                return Err(Error::SplitRefused(format!(
                    "a neighbour recorded for the split of vertex {} from {} is not a \
                     vertex of this mesh",
                    self.records[r].v0, self.records[r].v1
                )));
            }
        }
        let clean = self.positions_are_clean();
        let (placement, mark) = self.placer().placement(r, clean);
        prefetch_splits_after(&self.mesh, &self.records.steps, r);
        if !clean {
            self.placer().prefetch_ahead(r);
        }
        let record = self.records[r];
        // Checked before the split: nothing may change if the step cannot complete.
        if let Placement::At([q0, q1]) = placement {
            if !(q0.is_finite() && q1.is_finite()) {
                return Err(Error::Overflow(format!(
                    "splitting vertex {} from {} would put them at {q0} and {q1}",
                    record.v0, record.v1
                )));
            }
        }
        let classify = self.labels_to_classify(r)?;
        if trusted {
            self.mesh.vertex_split_unchecked(&record);
        } else {
            let fingerprint = self.records.fingerprints[r];
            let Some(public) = self.mesh.public_record(&record, fingerprint, self.origin()) else {
                return Err(Error::SplitRefused(format!(
                    "the record of vertex {} split from {} names elements this mesh does \
                     not have",
                    record.v0, record.v1
                )));
            };
            self.mesh.vertex_split(&public)?;
        }
        // The split put v0 and v1 back at p0 and p1; the placement moves them on.
        self.placer().settle(r, placement, mark);
        self.consistent_from = self.consistent_from.min(r);
        if let Some(binding) = classify {
            let v0 = self.mesh.vh(record.v0);
            // A label attribute removed by the user since it was attached has nothing
            // left to label.
            let _removed = labels::classify_split(&mut self.mesh, binding.attribute, v0);
        }
        self.applied = r;
        self.stamp = self.stamp.map(|_| self.mesh.binding());
        self.tag_level();
        Ok(true)
    }
}

impl Hierarchy {
    /// Tags the mesh with this hierarchy and its position, while the hierarchy trusts it
    /// (see [`crate::Binding`]).
    #[inline]
    fn tag_level(&mut self) {
        if self.stamp.is_some() {
            self.mesh.provenance.tag_level(self.id, self.applied);
        }
    }
}

/// # Sub-mesh labels
impl Hierarchy {
    /// Attaches sub-mesh labels (a vertex attribute of this hierarchy's mesh, see
    /// [`crate::labels`]) defined at the current position. From now on, splitting a
    /// record that was collapsed before this position classifies the re-inserted vertex
    /// with the paper's Fig. 4 rule; vertices that were live here keep their labels at
    /// every level (the attribute persists on collapsed vertices).
    ///
    /// # Errors
    /// [`Error::Stale`] when `attribute` is not an attribute of this hierarchy's mesh
    /// (nothing is attached then).
    pub fn attach_labels(&mut self, attribute: Attribute<VertexId, Label>) -> Result<()> {
        self.mesh.attribute_values(attribute)?;
        self.labels = Some(LabelBinding {
            attribute,
            defined_at: self.applied,
        });
        Ok(())
    }
    /// Tells the hierarchy that the attached labels were (re)defined at the current
    /// position. Does nothing when no labels are attached.
    pub fn labels_defined_here(&mut self) {
        if let Some(b) = &mut self.labels {
            b.defined_at = self.applied;
        }
    }
    /// The attached label attribute, if any.
    pub fn label_attribute(&self) -> Option<Attribute<VertexId, Label>> {
        self.labels.map(|b| b.attribute)
    }
    /// Makes the sub-mesh labels hold at every level: no edge of any level joins two
    /// vertices with different labels, except through [`labels::FRONTIER`] vertices.
    ///
    /// The records are replayed from the input (on a copy; the labels reach the vertices
    /// re-inserted since they were defined by the paper's Fig. 4 rule): a record whose
    /// ends carry different labels is dropped; a record whose neighbourhood such a drop
    /// may have changed is tested again where it now is (topology, flips, error bound)
    /// and made or dropped; every other record is collapsed again exactly as built, with
    /// its detail coefficients. The band along the frontier where records were dropped
    /// is simplified again, level by level, by the seed paper's rounds
    /// (collapsing only edges whose ends carry the same label), so the levels keep about
    /// their face counts (see the `replan` module). Costs well under one build: most
    /// records are only collapsed again. Then the hierarchy goes back to the level it was
    /// at (or the new coarsest, if that is finer). Edits made so far are kept (they are in
    /// the input's positions now); affine marks are dropped. Call it after labels were
    /// defined or changed at any level; several sub-meshes (labels) can live in the mesh
    /// at once. Later builds of the same mesh respect the labels too
    /// ([`HierarchyOptions::respect_labels`] is set).
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] when the mesh has no label attribute; the errors of
    /// [`go_to_level`](Self::go_to_level); [`Error::NonFiniteCoordinate`] and
    /// [`Error::Overflow`] for positions the replay cannot place. On error the hierarchy
    /// is exactly as it was.
    pub fn constrain_to_labels(&mut self) -> Result<()> {
        let attribute = self
            .labels
            .map(|b| b.attribute)
            .or_else(|| {
                self.mesh
                    .find_attribute::<VertexId, Label>(labels::LABEL_ATTRIBUTE)
            })
            .ok_or_else(|| {
                Error::InvalidArgument(format!(
                    "constrain_to_labels: the mesh has no {:?} vertex attribute",
                    labels::LABEL_ATTRIBUTE
                ))
            })?;
        let mut options = self.options.clone();
        options.respect_labels = true;
        let level = self.level_at_or_finer();
        // The replay reads the records from level 0, on a copy: a refused walk or replay
        // leaves the hierarchy exactly as it was.
        let mut walked;
        let source = if self.applied == 0 {
            &*self
        } else {
            walked = self.clone();
            walked.seek(0)?;
            &walked
        };
        let input = source.mesh.clone();
        let rebuilt = replan::respecting_labels(source, input, attribute, &options)?;
        self.replace_with(rebuilt, Some(attribute), level)
    }

    /// Changes the topology of the hierarchy's mesh the only way a hierarchy can keep:
    /// at the input. Walks to level 0 (carrying every edit), hands the input mesh to
    /// `change` (which may split edges, add or remove faces, …; its result is returned),
    /// builds the hierarchy again with the same options (so the new vertices get records
    /// of their own and every level is reachable), and goes back to the level it was at
    /// (or the new coarsest, if that is finer). Attached labels stay attached; affine
    /// marks are dropped. Costs about one build.
    ///
    /// This is how an edit that adds vertices at a coarse level (the adaptive refinement
    /// of Bendels & Klein, for example) composes with the hierarchy: the vertices are
    /// added where the carried edit stretched the input, and they survive every walk.
    ///
    /// # Errors
    /// The errors of the walks and of [`build`](Self::build); an error of `change` is
    /// passed through as [`Error::InvalidArgument`] with its message. On any error
    /// (a refused walk, `change` failing or leaving a mesh that fails [`Mesh::check`], a
    /// refused build) the hierarchy is exactly as it was: the walk is made on a copy.
    pub fn edit_input<R, E: std::fmt::Display>(
        &mut self,
        change: impl FnOnce(&mut Mesh) -> std::result::Result<R, E>,
    ) -> Result<R> {
        let level = self.level_at_or_finer();
        // The walk to the input is made on a copy: a refused walk, change or build leaves
        // the hierarchy exactly as it was (a walk down and back need not be bit-exact).
        let (mut input, spare) = if self.applied == 0 {
            // Already at the input: no walk, a copy of the mesh alone (not of the
            // records) is the input to change.
            (self.mesh.clone(), None)
        } else {
            let mut work = self.clone();
            work.seek(0)?;
            // The copy's buffers are warm: the build reuses them.
            let spare = Storage::take(&mut work);
            (work.into_mesh(), Some(spare))
        };
        let untouched = input.binding();
        let result =
            change(&mut input).map_err(|e| Error::InvalidArgument(format!("edit_input: {e}")))?;
        if !untouched.same_connectivity(&input) {
            // The change made its own topology: check it before building on it.
            input.check()?;
        }
        // Everything the build can refuse is checked here, before this hierarchy gives
        // up anything: from now on it cannot fail (its progress never asks it to stop).
        self.options.validate()?;
        check_positions(&input)?;
        // The records about to be replaced lend their memory to the new ones: one set of
        // buffers at a time, and no fresh pages to fault in (on the 1.6 M-face bench mesh
        // 32 k page faults instead of 113 k; the time saved was within this host's noise).
        let storage = spare.unwrap_or_else(|| Storage::take(self));
        let rebuilt = Hierarchy::build_validated(input, &self.options, storage, &mut |_| {
            ControlFlow::Continue(())
        })?;
        let labels = self.labels.map(|b| b.attribute);
        self.replace_with(rebuilt, labels, level)?;
        Ok(result)
    }

    /// Makes `rebuilt` (a hierarchy of this one's input, at level 0) this hierarchy: the
    /// labels `labels` attached as defined at the input, the mesh keeping this mesh's
    /// identity with a new connectivity stamp (nobody who saw the old one may trust it),
    /// at `level` or the new coarsest if that is finer. On error (a refused walk) this
    /// hierarchy is unchanged.
    fn replace_with(
        &mut self,
        mut rebuilt: Hierarchy,
        labels: Option<Attribute<VertexId, Label>>,
        level: usize,
    ) -> Result<()> {
        rebuilt.labels = labels.map(|attribute| LabelBinding {
            attribute,
            defined_at: 0,
        });
        let target = level.min(rebuilt.coarsest_level());
        let clean = rebuilt.positions_unedited();
        rebuilt.mesh.provenance.succeed(&self.mesh.provenance);
        rebuilt.stamp = Some(rebuilt.mesh.binding());
        rebuilt.clean_positions = clean.then(|| rebuilt.mesh.binding());
        rebuilt.go_to_level(target)?;
        *self = rebuilt;
        Ok(())
    }

    /// Stops propagating labels through splits.
    pub fn detach_labels(&mut self) {
        self.labels = None;
    }
}

/// The buffers of a hierarchy's records and detail coefficients, handed from a hierarchy
/// that is about to be replaced to the build that replaces it: the rebuild then holds one
/// set of buffers instead of two and faults in no fresh pages.
#[derive(Default)]
pub(crate) struct Storage {
    records: Records,
    placements: placements::Placements,
    details: Option<Details>,
}

impl Storage {
    /// Takes the buffers out of `h`, leaving it without records.
    fn take(h: &mut Hierarchy) -> Self {
        let mode = h.details.mode();
        Self {
            records: std::mem::take(&mut h.records),
            placements: std::mem::take(&mut h.placements),
            details: Some(std::mem::replace(
                &mut h.details,
                Details::with_capacity(mode, 0),
            )),
        }
    }
}

/// What a walk of a hierarchy that does not trust its mesh may change, saved to undo a
/// refused walk ([`Hierarchy::seek`]).
struct Saved {
    mesh: Mesh,
    range: std::ops::Range<usize>,
    records: Vec<Step>,
    fingerprints: Vec<u64>,
    placements: (Vec<u8>, Vec<(DVec3, f64)>),
    details: detail::SavedRange,
    marks: Marks,
    rests: Vec<Rest>,
    consistent_from: usize,
    applied: usize,
    clean_positions: Option<Binding>,
}

impl Saved {
    fn take(h: &Hierarchy, applied: usize) -> Self {
        let range = h.applied.min(applied)..h.applied.max(applied);
        Self {
            mesh: h.mesh.clone(),
            records: h.records.steps[range.clone()].to_vec(),
            fingerprints: h.records.fingerprints[range.clone()].to_vec(),
            placements: h.placements.save(range.clone()),
            details: h.details.save(range.clone()),
            range,
            marks: h.marks.clone(),
            rests: h.rests.clone(),
            consistent_from: h.consistent_from,
            applied: h.applied,
            clean_positions: h.clean_positions,
        }
    }

    fn restore(self, h: &mut Hierarchy) {
        // The mesh keeps its identity; its topology changed and changed back, so it gets
        // a new stamp (nobody who saw the walk's stamps may trust it).
        let previous = std::mem::replace(&mut h.mesh, self.mesh);
        h.mesh.provenance.succeed(&previous.provenance);
        h.records.steps[self.range.clone()].copy_from_slice(&self.records);
        h.records.fingerprints[self.range.clone()].copy_from_slice(&self.fingerprints);
        h.placements.restore(self.range.clone(), self.placements);
        h.details.restore(self.range, self.details);
        h.marks = self.marks;
        h.rests = self.rests;
        h.consistent_from = self.consistent_from;
        h.applied = self.applied;
        h.clean_positions = self.clean_positions;
        h.distrust();
    }
}

/// No affine mark on a vertex.
const UNMARKED: u32 = u32::MAX;
/// The mark of a vertex in an edit's region without an affine map of its own
/// ([`Hierarchy::mark_region`]).
const IN_REGION: u32 = u32::MAX - 1;

/// Motions (affine maps or fields) that moved vertices since the hierarchy placed them
/// ([`Hierarchy::mark_affine`], [`Hierarchy::mark_field`]) and region marks: a motion
/// index (or [`IN_REGION`]) per vertex slot, allocated on first use, and the motions.
#[derive(Clone, Debug, Default)]
struct Marks {
    of_vertex: Vec<u32>,
    maps: Vec<Motion>,
    /// Maps kept after the last [`Marks::compact`] (the next one runs when there are
    /// twice as many and 64 more).
    compacted: usize,
}

impl Marks {
    #[inline]
    fn is_empty(&self) -> bool {
        self.of_vertex.is_empty()
    }
    #[inline]
    fn of(&self, i: usize) -> u32 {
        self.of_vertex.get(i).copied().unwrap_or(UNMARKED)
    }
    #[inline]
    fn set(&mut self, i: usize, mark: u32) {
        if let Some(m) = self.of_vertex.get_mut(i) {
            *m = mark;
        }
    }
    fn clear(&mut self) {
        if !self.is_empty() {
            *self = Self::default();
        }
    }
    /// Drops the maps no vertex uses any more (an interactive drag replaces its handle's
    /// map at every step), renumbering the others; amortised over the marks made.
    fn compact(&mut self) {
        let mut renumbered = vec![UNMARKED; self.maps.len()];
        let mut kept = Vec::new();
        for m in &mut self.of_vertex {
            if *m < IN_REGION {
                let k = *m as usize;
                if renumbered[k] == UNMARKED {
                    renumbered[k] = kept.len() as u32;
                    kept.push(self.maps[k].clone());
                }
                *m = renumbered[k];
            }
        }
        self.maps = kept;
        self.compacted = self.maps.len();
    }
}

/// # Edits at a coarse level
impl Hierarchy {
    /// How splits place their vertices after an edit (see [`DetailMode`]).
    pub fn detail_mode(&self) -> DetailMode {
        self.details.mode()
    }

    /// Tells the hierarchy that `vertices` (live at the current position) were just moved
    /// by the affine map `transform` (for example a rigidly moved handle, or a rotated
    /// sub-mesh): refinement then puts every finer vertex collapsed into one of them at
    /// `transform` of its recorded position, exactly, instead of carrying it by its local
    /// frame. So a part moved rigidly at a coarse level is, at full resolution, the rigid
    /// image of its original fine vertices.
    ///
    /// Marks compose: a vertex marked with `A`, then with `B`, has moved by `B ∘ A`. A
    /// marked vertex that is not (within rounding) at its map's image of where the
    /// hierarchy left it when it is split (it was moved otherwise since) falls back to its
    /// local frame. Walking coarser drops all marks (the records collapsed again hold the
    /// moved positions). Marks need [`DetailMode::LocalFrame`].
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] in [`DetailMode::Translation`], for a map that is not
    /// finite, or for a vertex that is not live; nothing is marked then.
    pub fn mark_affine(&mut self, vertices: &[VertexId], transform: DAffine3) -> Result<()> {
        if !transform.is_finite() {
            return Err(Error::InvalidArgument(format!(
                "the affine map of mark_affine is not finite: {transform:?}"
            )));
        }
        self.mark(vertices, Motion::Affine(transform), true)
    }

    /// [`mark_affine`](Self::mark_affine), replacing the marks the vertices had instead
    /// of composing with them: for an edit that is applied again and again from the same
    /// starting positions (a handle dragged interactively), whose latest map is the whole
    /// motion since the hierarchy placed the vertices.
    ///
    /// # Errors
    /// As [`mark_affine`](Self::mark_affine).
    pub fn set_affine_mark(&mut self, vertices: &[VertexId], transform: DAffine3) -> Result<()> {
        if !transform.is_finite() {
            return Err(Error::InvalidArgument(format!(
                "the affine map of set_affine_mark is not finite: {transform:?}"
            )));
        }
        self.mark(vertices, Motion::Affine(transform), false)
    }

    /// [`mark_affine`](Self::mark_affine) for an edit that is a map of space but not an
    /// affine one (a deformation defined at every point, such as a Barr twist or taper
    /// whose strength ramps along its axis): `vertices` (live at the current position)
    /// were just moved by `field`, and refinement puts every finer vertex collapsed into
    /// one of them at `field` of its recorded position. The coarse edit then comes back
    /// at full resolution exactly as the same deformation of the input would have made
    /// it, over those vertices' clusters. A marked vertex that is not (within rounding)
    /// at `field` of where the hierarchy left it falls back to its local frame, as for
    /// affine marks; a field that gives a non-finite position makes the split that
    /// meets it fail with [`Error::Overflow`] (nothing changed by that split). Marks
    /// compose and are dropped when the hierarchy walks coarser.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] in [`DetailMode::Translation`] or for a vertex that is
    /// not live; nothing is marked then.
    pub fn mark_field(
        &mut self,
        vertices: &[VertexId],
        field: impl Fn(DVec3) -> DVec3 + Send + Sync + 'static,
    ) -> Result<()> {
        self.mark(vertices, Motion::Field(std::sync::Arc::new(field)), true)
    }

    /// [`mark_field`](Self::mark_field) with a field already shared.
    ///
    /// # Errors
    /// As [`mark_field`](Self::mark_field).
    pub fn mark_shared_field(&mut self, vertices: &[VertexId], field: Field) -> Result<()> {
        self.mark(vertices, Motion::Field(field), true)
    }

    /// [`mark_shared_field`](Self::mark_shared_field), replacing the marks the vertices
    /// had instead of composing with them (as [`set_affine_mark`](Self::set_affine_mark)).
    ///
    /// # Errors
    /// As [`mark_field`](Self::mark_field).
    pub fn set_field_mark(&mut self, vertices: &[VertexId], field: Field) -> Result<()> {
        self.mark(vertices, Motion::Field(field), false)
    }

    fn mark(&mut self, vertices: &[VertexId], motion: Motion, compose: bool) -> Result<()> {
        if self.details.mode() != DetailMode::LocalFrame {
            return Err(Error::InvalidArgument(
                "affine and field marks need DetailMode::LocalFrame (the paper's translations \
                 ignore them)"
                    .into(),
            ));
        }
        if let Some(&v) = vertices.iter().find(|&&v| !self.mesh.is_valid_vertex(v)) {
            return Err(Error::InvalidArgument(format!(
                "mark_affine: vertex {v} is not a live vertex of the hierarchy's mesh"
            )));
        }
        let slots = self.mesh.vertex_slots();
        if self.marks.of_vertex.len() < slots {
            self.marks.of_vertex.resize(slots, UNMARKED);
        }
        // One new map per map the vertices had before (or none).
        let mut composed: Vec<(u32, u32)> = Vec::new();
        for &v in vertices {
            let i = self.mesh.vertex_index(v);
            let old = match self.marks.of_vertex[i] {
                o if compose && o < IN_REGION => o,
                _ => UNMARKED,
            };
            let new = match composed.iter().find(|&&(o, _)| o == old) {
                Some(&(_, n)) => n,
                None => {
                    let map = match old {
                        UNMARKED => motion.clone(),
                        o => self.marks.maps[o as usize].then(&motion),
                    };
                    let n = self.marks.maps.len() as u32;
                    self.marks.maps.push(map);
                    composed.push((old, n));
                    n
                }
            };
            self.marks.of_vertex[i] = new;
        }
        if self.marks.maps.len() > 2 * self.marks.compacted + 64 {
            self.marks.compact();
        }
        Ok(())
    }

    /// Tells the hierarchy that `vertices` (live at the current position) are the region
    /// of an edit made at this level: refinement places the finer vertices collapsed into
    /// them by the motion of their neighbourhood even where they did not move themselves,
    /// so the edit's transition from moved to still comes back at full resolution as
    /// smooth as the edit made it (the piecewise-linear interpolation of the coarse motion
    /// over the descendants, see [`DetailMode::LocalFrame`]), instead of a step on the
    /// last fine edge before an unmoved coarse vertex. Vertices outside every region
    /// keep the default rule: a fine vertex whose ancestor did not move stays exactly
    /// where it was, so mark only what the edit may move (a sub-mesh's inside, a Lee
    /// editing area's interior, a Bendels–Klein handle and deformable region, an FFD
    /// footprint). Affinely marked vertices ([`mark_affine`](Self::mark_affine)) are in
    /// the region already; marking a vertex here keeps its affine map.
    ///
    /// Walking coarser drops the marks, as for [`mark_affine`](Self::mark_affine).
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] in [`DetailMode::Translation`] or for a vertex that is
    /// not live; nothing is marked then.
    pub fn mark_region(&mut self, vertices: &[VertexId]) -> Result<()> {
        if self.details.mode() != DetailMode::LocalFrame {
            return Err(Error::InvalidArgument(
                "region marks need DetailMode::LocalFrame (the paper's translations ignore them)"
                    .into(),
            ));
        }
        if let Some(&v) = vertices.iter().find(|&&v| !self.mesh.is_valid_vertex(v)) {
            return Err(Error::InvalidArgument(format!(
                "mark_region: vertex {v} is not a live vertex of the hierarchy's mesh"
            )));
        }
        let slots = self.mesh.vertex_slots();
        if self.marks.of_vertex.len() < slots {
            self.marks.of_vertex.resize(slots, UNMARKED);
        }
        for &v in vertices {
            let m = &mut self.marks.of_vertex[self.mesh.vertex_index(v)];
            if *m == UNMARKED {
                *m = IN_REGION;
            }
        }
        Ok(())
    }

    /// Removes every affine and region mark ([`mark_affine`](Self::mark_affine),
    /// [`mark_region`](Self::mark_region)).
    pub fn clear_marks(&mut self) {
        self.marks.clear();
    }

    /// For every vertex slot of the input mesh (indexed by [`Mesh::vertex_index`]), the
    /// index of its *ancestor* at `level`: the vertex it is collapsed into there (itself
    /// when it is live at `level`). Refinement with [`DetailMode::LocalFrame`] moves a
    /// fine vertex only when its ancestor at the edited level moved, so this map tells
    /// which fine vertices an edit's region covers.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] for a level that does not exist.
    pub fn ancestors(&self, level: usize) -> Result<Vec<u32>> {
        let end = self.check_level(level)?;
        let mut map: Vec<u32> = (0..self.mesh.vertex_slots() as u32).collect();
        for record in self.records.steps[..end].iter().rev() {
            let (i0, i1) = (record.v0 as usize, record.v1 as usize);
            if let (true, Some(&a)) = (i0 < map.len(), map.get(i1)) {
                map[i0] = a;
            }
        }
        Ok(map)
    }
}

/// # Clusters
impl Hierarchy {
    /// Every vertex the collapses down to the current position took part in, as
    /// `(index, ancestor, input position)`: its vertex index, the index of the vertex
    /// live here it is collapsed into (itself for a survivor still live), and its
    /// position in the input as the hierarchy holds it (what refining without an edit
    /// restores). Together with the live vertices that took part in no collapse (they
    /// are their own cluster, still where the input has them unless edited here), these
    /// are the *clusters* of the vertices live here: what a mark of a live vertex
    /// ([`mark_affine`](Self::mark_affine), [`mark_region`](Self::mark_region)) reaches at
    /// full resolution. Costs one pass over the records made so far.
    pub fn cluster_members(&self) -> Vec<(u32, u32, DVec3)> {
        let steps = &self.records.steps[..self.applied];
        let slots = self.mesh.vertex_slots();
        let mut first: Vec<Option<DVec3>> = vec![None; slots];
        for step in steps {
            for (i, p) in [(step.v0, step.p0), (step.v1, step.p1)] {
                if let Some(slot @ None) = first.get_mut(i as usize) {
                    *slot = Some(p);
                }
            }
        }
        let mut ancestor: Vec<u32> = (0..slots as u32).collect();
        for step in steps.iter().rev() {
            let (i0, i1) = (step.v0 as usize, step.v1 as usize);
            if let (true, Some(&a)) = (i0 < ancestor.len(), ancestor.get(i1)) {
                ancestor[i0] = a;
            }
        }
        first
            .iter()
            .enumerate()
            .filter_map(|(i, p)| p.map(|p| (i as u32, ancestor[i], p)))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What identifies every record of `h`: its edge, positions and fingerprint.
    fn record_keys(h: &Hierarchy) -> Vec<(HalfedgeId, DVec3, DVec3, u64)> {
        h.records()
            .iter()
            .map(|r| (r.v0v1, r.p0, r.p1, r.fingerprint()))
            .collect()
    }

    /// An icosphere of level 4 with smooth bumps (detail that is not radial).
    fn bumpy_icosphere() -> Mesh {
        let mut input = crate::generators::icosphere(4);
        for p in input.positions_mut() {
            *p *= 1.0 + 0.1 * (7.0 * p.x).sin() * (5.0 * p.y + 0.3).sin();
        }
        input
    }

    /// Output buffers made and mapped on another thread, adopted in the middle of a build
    /// (large enough for the QEM build to do so itself) or afterwards, hold the same
    /// records: the hierarchy refines back to its input bit for bit.
    #[test]
    fn adopted_prefaulted_buffers_keep_every_record() {
        let input = crate::generators::icosphere(6);
        let options = HierarchyOptions::qem().with_target_faces(500);
        let mut h = Hierarchy::build(input.clone(), &options).unwrap();
        assert!(h.n_records() > 4 * PREFAULT_RECORDS);
        let records = h.n_records();
        let bytes = h.record_bytes();
        let before = record_keys(&h);
        // Adopt buffers by hand (as large as the records, and larger).
        for extra in [0, 1000] {
            let sizes = (records + extra, records);
            let details = h.details.prefaulted_sizes(records);
            h.adopt_prefaulted(Prefaulted {
                steps: prefaulted(sizes),
                fingerprints: prefaulted(sizes),
                rules: prefaulted(sizes),
                stored: prefaulted(sizes),
                details: details.make(),
            });
        }
        assert_eq!(h.n_records(), records);
        assert!(h.record_bytes() >= bytes);
        let after = record_keys(&h);
        assert_eq!(after, before);
        h.refine_to(0).unwrap();
        h.mesh().check().unwrap();
        let bits = |m: &Mesh| -> Vec<[u64; 3]> {
            m.positions()
                .iter()
                .map(|p| p.to_array().map(f64::to_bits))
                .collect()
        };
        assert_eq!(bits(h.mesh()), bits(&input));
        // And a build that adopted them at its own pace gives the same records.
        let again = Hierarchy::build(input, &options).unwrap();
        let records_again = record_keys(&again);
        assert_eq!(records_again, before);
    }

    #[test]
    fn a_field_mark_places_every_fine_vertex_of_its_clusters_at_the_field_of_its_input_position() {
        // A twist whose angle ramps along z (not affine), then a translation: the fine
        // vertices of the marked cap are exactly the composed deformation of the input,
        // the rest did not move; a mark that does not fit falls back to the local frame.
        let input = bumpy_icosphere();
        let twist = |p: DVec3| {
            let angle = 1.5 * (p.z - 0.2).clamp(0.0, 1.0);
            glam::DQuat::from_rotation_z(angle) * p
        };
        let shift = DVec3::new(0.05, -0.02, 0.1);
        for options in [HierarchyOptions::rounds(), HierarchyOptions::qem()] {
            let mut h = Hierarchy::build(input.clone(), &options.with_target_faces(100)).unwrap();
            let level = 2;
            h.go_to_level(level).unwrap();
            let ancestors = h.ancestors(level).unwrap();
            let cap: Vec<VertexId> = h
                .mesh()
                .vertices()
                .filter(|&v| h.mesh().position(v).z > 0.1)
                .collect();
            let mut in_cap = vec![false; h.mesh().vertex_slots()];
            for &v in &cap {
                in_cap[h.mesh().vertex_index(v)] = true;
                let p = h.mesh().position(v);
                h.mesh_mut().set_position(v, twist(p) + shift);
            }
            h.mark_field(&cap, twist).unwrap();
            h.mark_affine(&cap, DAffine3::from_translation(shift))
                .unwrap();
            h.go_to_level(0).unwrap();
            h.mesh().check().unwrap();
            for v in input.vertices() {
                let i = input.vertex_index(v);
                let (p, q) = (input.position(v), h.mesh().position(v));
                if in_cap[ancestors[i] as usize] {
                    assert!(
                        q.distance(twist(p) + shift) < 1e-12,
                        "{v}: {q} against {}",
                        twist(p) + shift
                    );
                } else {
                    assert_eq!(q, p, "{v} outside the cap moved");
                }
            }
        }
        // Refused in translation mode, nothing marked.
        let options = HierarchyOptions::rounds().with_detail_mode(DetailMode::Translation);
        let mut h = Hierarchy::build(input.clone(), &options.with_target_faces(100)).unwrap();
        h.go_to_level(1).unwrap();
        let v = h.mesh().vertices().next().unwrap();
        assert!(h.mark_field(&[v], twist).is_err());
        assert!(h.marks.is_empty());
    }

    #[test]
    fn cluster_members_are_the_input_positions_of_each_live_vertex_cluster() {
        // At every level of both methods: each member is at its input position bit for bit
        // and has the ancestor `ancestors` gives; every vertex that is not a member is live
        // there, its own ancestor, and still at its input position.
        let input = bumpy_icosphere();
        for options in [HierarchyOptions::rounds(), HierarchyOptions::qem()] {
            let mut h = Hierarchy::build(input.clone(), &options.with_target_faces(100)).unwrap();
            for level in 0..h.n_levels() {
                h.go_to_level(level).unwrap();
                let ancestors = h.ancestors(level).unwrap();
                let members = h.cluster_members();
                let mut member = vec![false; input.vertex_slots()];
                for &(i, a, p) in &members {
                    let i = i as usize;
                    member[i] = true;
                    assert_eq!(a, ancestors[i], "level {level}");
                    assert_eq!(
                        p.to_array().map(f64::to_bits),
                        input.positions()[i].to_array().map(f64::to_bits)
                    );
                }
                for v in input.vertices() {
                    let i = input.vertex_index(v);
                    if !member[i] {
                        assert_eq!(ancestors[i] as usize, i);
                        assert!(h.mesh().is_valid_vertex(v));
                        assert_eq!(h.mesh().position(v), input.position(v));
                    }
                }
                assert_eq!(!members.is_empty(), level > 0);
            }
        }
    }

    #[test]
    fn the_public_records_fit_their_own_mesh_and_no_other() {
        // The hierarchy keeps compact records; the public ones it makes on demand split
        // like the kernel's: on a clone of its mesh the last record splits and gives back
        // its vertex where it was, on another hierarchy's mesh (same input) it is refused.
        let options = HierarchyOptions::rounds().with_target_faces(60);
        let h = Hierarchy::build(crate::generators::icosphere(3), &options).unwrap();
        let other = Hierarchy::build(crate::generators::icosphere(3), &options).unwrap();
        let records = h.records();
        assert_eq!(records.len(), h.n_records());
        let last = records.last().unwrap();
        let mut mesh = h.mesh().clone();
        mesh.vertex_split(last).unwrap();
        mesh.check().unwrap();
        assert_eq!(mesh.position(last.v0), last.p0);
        assert!(mesh.vertex_split(last).is_err(), "split twice");
        let mut foreign = other.mesh().clone();
        let e = foreign.vertex_split(last).unwrap_err();
        assert!(e.to_string().contains("another mesh"), "{e}");
    }

    #[test]
    fn replacing_a_mark_again_and_again_keeps_the_maps_bounded() {
        // An interactive drag: the handle's map is replaced at every step; maps no
        // vertex uses are dropped, and the last one still lands exactly.
        let mesh = crate::generators::icosphere(3);
        let input = mesh.clone();
        let mut h = Hierarchy::build(mesh, &HierarchyOptions::rounds()).unwrap();
        h.go_to_level(2).unwrap();
        let handle: Vec<VertexId> = h
            .mesh()
            .vertices()
            .filter(|&v| h.mesh().position(v).x > 0.5)
            .collect();
        let before: Vec<DVec3> = handle.iter().map(|&v| h.mesh().position(v)).collect();
        let mut t = DAffine3::IDENTITY;
        for step in 1..=1000 {
            t = DAffine3::from_translation(DVec3::new(0.0, 0.0, 1e-4 * step as f64));
            for (&v, &p) in handle.iter().zip(&before) {
                h.mesh_mut().set_position(v, t.transform_point3(p));
            }
            h.set_affine_mark(&handle, t).unwrap();
            assert!(h.marks.maps.len() <= 67, "{} maps", h.marks.maps.len());
        }
        let ancestors = h.ancestors(2).unwrap();
        let marked: Vec<bool> = {
            let mut m = vec![false; input.vertex_slots()];
            for &v in &handle {
                m[h.mesh().vertex_index(v)] = true;
            }
            m
        };
        h.refine_to(0).unwrap();
        for v in input.vertices() {
            let i = input.vertex_index(v);
            if marked[ancestors[i] as usize] {
                let target = t.transform_point3(input.position(v));
                assert!(h.mesh().position(v).distance(target) < 1e-12);
            }
        }
    }
}
