//! The progressive hierarchy of the seed paper ("Interactive Editing of Multiresolution
//! Meshes", section 3): a sequence of edge collapses recorded level by level, with
//! detail coefficients, that can be walked coarser and finer at will
//! while the user edits positions (and sub-mesh labels) at any level.
//!
//! - **Building** ([`Hierarchy::build`]) simplifies the mesh with one of two methods
//!   ([`Method`]): the paper's *rounds* (every unlocked edge whose star is nearly planar
//!   collapses to its midpoint, then the edges around the survivor are locked until the
//!   round ends; a round is a level, module `rounds`) or a *QEM* priority decimation
//!   (Garland–Heckbert, module [`qem`]) whose levels are cut at fixed face-count ratios so
//!   that they are comparable with rounds. Both share the legality layer of module
//!   legality layer (OpenMesh's topological rules, no normal flips, no degenerate faces,
//!   boundary vertices never leave the boundary). The build stops at a target face
//!   count, a level count or an error bound ([`HierarchyOptions`]). The mesh is left at
//!   the coarsest level. [`Hierarchy::build_with_progress`] reports progress, and
//!   [`Hierarchy::build_cancellable`] lets the report stop the build.
//! - **Speed**: walking the records is bound by memory latency (each step touches a few
//!   elements scattered over arrays larger than the caches), so every step prefetches
//!   what the record a few steps ahead will touch (`crate::prefetch`); while the
//!   hierarchy trusts its mesh (its [`crate::Binding`]), collapsing a record again
//!   skips the legality test the build already made, and splitting one skips its checks.
//! - **Walking**: [`coarsen_to`](Hierarchy::coarsen_to) / [`refine_to`](Hierarchy::refine_to)
//!   / [`go_to_level`](Hierarchy::go_to_level) level by level, or
//!   [`collapse_next`](Hierarchy::collapse_next) / [`split_next`](Hierarchy::split_next)
//!   split by split. Level 0 is the input; higher levels are coarser.
//! - **Detail coefficients** ([`DetailMode`]): every split re-inserts
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
//! - **Files**: [`Hierarchy::save`] and [`Hierarchy::load`] keep a hierarchy in a `.mrh`
//!   file, everything it holds included, to walk and edit it another day (module
//!   [`file`](mod@file)).
//!
//! ```
//! use halfedge::generators;
//! use halfedge::hierarchy::{Hierarchy, HierarchyOptions};
//! let mesh = generators::icosphere(3);
//! let faces = mesh.n_faces();
//! let mut h = Hierarchy::build(mesh, &HierarchyOptions::rounds().with_target_faces(100)).unwrap();
//! assert!(h.mesh().n_faces() <= 200);
//! h.refine_to(0).unwrap();
//! assert_eq!(h.mesh().n_faces(), faces);
//! ```

mod ahead;
mod bookmark;
mod buffers;
mod build;
mod clusters;
mod detail;
pub mod file;
mod heap;
mod legality;
mod marks;
mod motion;
mod options;
mod outcome;
mod placements;
mod placer;
pub mod qem;
mod records;
mod replan;
mod rests;
mod rounds;
mod submesh_labels;
mod unfold;
mod walk;

use crate::binding::Binding;
use crate::collapse::CollapseRecord;
use crate::error::{Error, Result};
use crate::mesh::Mesh;

pub use bookmark::LevelBookmark;
pub use detail::DetailMode;
use detail::Details;
pub use motion::Field;
pub use options::{BuildProgress, HierarchyOptions, Method, SurvivorPlacement};
pub use outcome::{BuildOutcome, Refusals, Relaxation, StopReason};

use marks::Marks;
use records::Records;
use rests::{Rest, MAX_RESTS};
use submesh_labels::LabelBinding;

/// [`Error::NonFiniteCoordinate`] for the first live vertex with a NaN or infinite
/// coordinate: the build would spread it over the coarse levels.
pub(crate) fn check_positions(mesh: &Mesh) -> Result<()> {
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

/// A new hierarchy number.
pub(super) fn next_hierarchy_id() -> u64 {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
    NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
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
    /// The options the hierarchy was built with (kept in its file).
    pub fn options(&self) -> &HierarchyOptions {
        &self.options
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
}

#[cfg(test)]
mod tests;
