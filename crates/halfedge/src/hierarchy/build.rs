//! Building a hierarchy: the entry points, the records a build writes, and the output
//! buffers made ahead on another thread.

use std::ops::ControlFlow;

use glam::DVec3;

use super::buffers::{prefaulted, PREFAULT_RECORDS};
use super::detail::{self, Collapsed, Details};
use super::marks::Marks;
use super::options::{report, BuildProgress, HierarchyOptions, Method};
use super::records::Storage;
use super::{bookmark, outcome, qem, rounds};
use super::{check_positions, next_hierarchy_id, Hierarchy};
use crate::collapse::Step;
use crate::error::Result;
use crate::handle::{HalfedgeId, VertexId};
use crate::labels::{self, Label};
use crate::mesh::Mesh;

/// # Building
impl Hierarchy {
    /// Builds the hierarchy of `mesh` with `options` (see [`HierarchyOptions`] and the
    /// [module docs](crate::hierarchy)); the mesh is left at the coarsest level.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`](crate::Error::InvalidArgument) for options out of range,
    /// [`Error::NonFiniteCoordinate`](crate::Error::NonFiniteCoordinate) for a vertex position that is NaN or infinite.
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
    /// [`Error::Cancelled`](crate::Error::Cancelled) (the mesh, moved in, is dropped). Reports come at the end of
    /// every level and every 65,536 collapses, so a build stops within a fraction of a
    /// second of being asked to — what an interactive application needs for a Cancel
    /// button.
    ///
    /// # Errors
    /// As [`build`](Self::build), and [`Error::Cancelled`](crate::Error::Cancelled).
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
    pub(super) fn build_validated(
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
        report(h.built_levels(), h.mesh.n_faces(), faces, progress)?;
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
    pub(super) steps: Vec<Step>,
    pub(super) fingerprints: Vec<u64>,
    pub(super) rules: Vec<u8>,
    pub(super) stored: Vec<(DVec3, f64)>,
    pub(super) details: detail::DetailBuffers,
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
