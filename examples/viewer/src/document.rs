//! The edited mesh, its multiresolution hierarchy when it has one, and the undo / redo
//! history.
//!
//! The document holds *one* mesh: a plain [`Mesh`], or the mesh of a
//! [`Hierarchy`] (after the *Multiresolution* tool built one,
//! [`Document::set_hierarchy`]); [`Document::mesh`] is that mesh either way, so every tool
//! edits the level shown, and [`Document::go_to_level`] moves the hierarchy (its mesh
//! *is* the document's mesh: nothing is copied between two meshes). Per-vertex data of
//! the mesh, such as the sub-mesh labels (the [`halfedge::labels::LABEL_ATTRIBUTE`]
//! attribute), live in the mesh and ride along through the levels.
//!
//! Every change goes through an *edit*: [`Document::begin_edit`] stores what is needed to
//! go back (the positions for a geometric edit — on a hierarchy with its marks, as a
//! bookmark — the whole mesh once the connectivity changes, the level and positions for
//! a level change) and [`Document::end_edit`] closes
//! it, so that one gesture (a drag, a slider drag, a button press) is one undo step
//! however many frames it spans. Asking for [`Document::positions_mut`] or
//! [`Document::mesh_mut`] outside an edit opens one, so no change can escape the history.
//! A positions-only edit that turns out to change the connectivity is upgraded on the fly
//! (the snapshot becomes the old mesh: exact, since the connectivity had not changed yet).
//! A connectivity change made by a tool on a hierarchy's mesh leaves a plain mesh (the
//! hierarchy could not walk it); undo brings the hierarchy back. A change that the
//! hierarchy can take (new vertices added at its input, `halfedge::hierarchy::Hierarchy::edit_input`,
//! as the Bendels–Klein refinement does through
//! `edit::bendels_klein::BlendSession::refine_in_hierarchy`) goes through
//! [`Document::edit_hierarchy`] instead: the document keeps the hierarchy at its level,
//! and undo gives back the hierarchy as it was.
//!
//! Revisions (`geometry`, `topology`, `labels`) tell the renderer and the panels what to
//! refresh; the picking structure (the library's `halfedge::bvh::Bvh`) keeps itself
//! current from the mesh.

use std::path::PathBuf;

use glam::DVec3;
use halfedge::hierarchy::{Hierarchy, LevelBookmark};
use halfedge::labels::Label;
use halfedge::labels::LABEL_ATTRIBUTE;
use halfedge::{BuildReport, Mesh, VertexId};
use multires::recipe::{HierarchySpec, Step};

use crate::recipe_log::{RecipeLog, RecordId};

/// A mesh file read for the viewer: the mesh, how it was built, and how many vertices
/// were welded onto others at the same position (a triangle soup or a mesh cut along
/// seams is welded into its surface, `Mesh::welded_seams`; 0 when nothing was).
///
/// # Errors
/// The reader's error, as text naming the file.
pub fn read_mesh(path: &std::path::Path) -> Result<(Mesh, BuildReport, usize), String> {
    let (mesh, report) = halfedge::io::read(path).map_err(|e| e.to_string())?;
    Ok(match mesh.welded_seams().map_err(|e| e.to_string())? {
        Some((welded, weld)) => (welded, weld.build, weld.merged_vertices),
        None => (mesh, report, 0),
    })
}

/// What the document holds: a plain mesh, or a hierarchy and its mesh.
enum Content {
    Plain(Box<Mesh>),
    Levels(Box<Hierarchy>),
}

impl Content {
    fn mesh(&self) -> &Mesh {
        match self {
            Content::Plain(m) => m,
            Content::Levels(h) => h.mesh(),
        }
    }

    /// The mesh for changes of positions or attributes.
    fn mesh_for_values(&mut self) -> &mut Mesh {
        match self {
            Content::Plain(m) => m,
            Content::Levels(h) => h.mesh_mut(),
        }
    }

    /// Approximate memory held, bytes.
    fn bytes(&self) -> usize {
        // Positions + three slot maps + key arrays: about 200 bytes per vertex.
        let mesh = 200 * self.mesh().vertex_slots().max(1);
        match self {
            Content::Plain(_) => mesh,
            Content::Levels(h) => mesh + h.record_bytes(),
        }
    }
}

/// What an undo step restores.
enum Snapshot {
    /// Vertex positions (indexed by `vertex_index`) over unchanged connectivity.
    Positions(Vec<DVec3>),
    /// The whole content: a mesh, or a hierarchy (before a build, a connectivity change).
    Content(Box<Content>),
    /// A position of the hierarchy (records collapsed), the positions there and its
    /// bookkeeping: going back is exact ([`Hierarchy::return_to`]).
    Level(Box<LevelBookmark>),
}

impl Snapshot {
    /// Approximate memory held, bytes.
    fn bytes(&self) -> usize {
        match self {
            Snapshot::Positions(p) => p.len() * std::mem::size_of::<DVec3>(),
            Snapshot::Level(bookmark) => bookmark.heap_bytes(),
            Snapshot::Content(c) => c.bytes(),
        }
    }
}

/// One step of the history: its label and the state before (undo) or after (redo) it,
/// with the recipe log as it was then.
struct Entry {
    label: String,
    snapshot: Snapshot,
    log: RecipeLog,
}

/// What the open edit stores.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum EditKind {
    Positions,
    Topology,
    Level,
}

/// Counters bumped by every change, for caches to compare against.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Revision {
    /// Bumped when positions change (also on connectivity changes).
    pub geometry: u64,
    /// Bumped when the connectivity (or the whole mesh) changes.
    pub topology: u64,
    /// Bumped when the sub-mesh labels are changed ([`Document::edit_labels`]).
    pub labels: u64,
}

/// Why the document refused a level change.
#[derive(Debug, thiserror::Error)]
pub enum DocumentError {
    /// The document holds no hierarchy.
    #[error("no hierarchy: build one first")]
    NoHierarchy,
    /// The hierarchy refused the walk.
    #[error(transparent)]
    Hierarchy(#[from] halfedge::Error),
}

/// Puts `h` back to the positions and marks of `bookmark` (taken at the same level when
/// a position edit began); when it cannot, the positions only, without marks.
fn back_before_edit(h: &mut Hierarchy, bookmark: &LevelBookmark) {
    if h.return_to(bookmark).is_err() {
        h.mesh_mut()
            .positions_mut()
            .copy_from_slice(bookmark.positions());
        h.clear_marks();
    }
}

/// Largest memory the undo stack may hold before the oldest steps are dropped.
const HISTORY_BYTES: usize = 1 << 30;
/// Most undo steps kept.
const HISTORY_STEPS: usize = 200;

/// The mesh being edited (plain or in a hierarchy), where it came from, and its history.
pub struct Document {
    content: Content,
    source: Option<PathBuf>,
    build_report: Option<BuildReport>,
    undo: Vec<Entry>,
    redo: Vec<Entry>,
    open_edit: Option<(String, EditKind)>,
    revision: Revision,
    /// The edits as recipe steps (see [`crate::recipe_log`]).
    log: RecipeLog,
    /// The last id given to a log entry.
    log_ids: u64,
}

impl Document {
    /// A document on `mesh`, with an empty history.
    pub fn new(mesh: Mesh, source: Option<PathBuf>, build_report: Option<BuildReport>) -> Self {
        Self {
            content: Content::Plain(Box::new(mesh)),
            source,
            build_report,
            undo: Vec::new(),
            redo: Vec::new(),
            open_edit: None,
            revision: Revision::default(),
            log: RecipeLog::default(),
            log_ids: 0,
        }
    }

    /// Replaces the mesh by a freshly loaded one and clears the history.
    pub fn replace(&mut self, mesh: Mesh, source: Option<PathBuf>, report: Option<BuildReport>) {
        let revision = self.revision;
        *self = Self::new(mesh, source, report);
        self.revision = Revision {
            geometry: revision.geometry + 1,
            topology: revision.topology + 1,
            labels: revision.labels + 1,
        };
    }

    /// The mesh (the hierarchy's, at its current level, when there is a hierarchy).
    pub fn mesh(&self) -> &Mesh {
        self.content.mesh()
    }

    /// The hierarchy whose mesh the document shows, if any.
    pub fn hierarchy(&self) -> Option<&Hierarchy> {
        match &self.content {
            Content::Plain(_) => None,
            Content::Levels(h) => Some(h),
        }
    }

    /// The file the mesh was read from, if any.
    pub fn source(&self) -> Option<&PathBuf> {
        self.source.as_ref()
    }

    /// What the builder had to repair when the mesh was read, if it was read from a file.
    pub fn build_report(&self) -> Option<&BuildReport> {
        self.build_report.as_ref()
    }

    /// Current revision counters.
    pub fn revision(&self) -> Revision {
        self.revision
    }

    /// Opens an edit named `label` unless one is open: stores the positions so that the
    /// edit can be undone. Closing is [`end_edit`](Self::end_edit).
    pub fn begin_edit(&mut self, label: &str) {
        if self.open_edit.is_some() {
            return;
        }
        // On a hierarchy, a bookmark: the positions and the hierarchy's marks, so that
        // undo and redo give back the marks of the edits they keep (refinement then
        // places the finer levels as those edits meant).
        let snapshot = match &self.content {
            Content::Levels(h) => Snapshot::Level(Box::new(h.bookmark())),
            Content::Plain(m) => Snapshot::Positions(m.positions().to_vec()),
        };
        self.log.flush(&mut self.log_ids);
        self.push_undo(Entry {
            label: label.to_owned(),
            snapshot,
            log: self.log.clone(),
        });
        self.log.begin_change(label, &mut self.log_ids);
        self.redo.clear();
        self.open_edit = Some((label.to_owned(), EditKind::Positions));
    }

    /// Opens an edit that may change the connectivity: stores the whole mesh (a
    /// hierarchy moves into the history, the document keeps a plain copy of its mesh).
    pub fn begin_topology_edit(&mut self, label: &str) {
        match self.open_edit.as_ref().map(|(_, k)| *k) {
            None => {
                let before = self.take_content_for_topology();
                self.log.flush(&mut self.log_ids);
                self.push_undo(Entry {
                    label: label.to_owned(),
                    snapshot: Snapshot::Content(Box::new(before)),
                    log: self.log.clone(),
                });
                self.log.begin_change(label, &mut self.log_ids);
                self.redo.clear();
                self.open_edit = Some((label.to_owned(), EditKind::Topology));
            }
            Some(EditKind::Level) => {
                // The level step stays a step of its own.
                self.open_edit = None;
                self.begin_topology_edit(label);
            }
            Some(EditKind::Positions) => self.upgrade_open_edit(),
            Some(EditKind::Topology) => {}
        }
    }

    /// The content as it is now, for the history, leaving a plain mesh in its place:
    /// a copy of a plain mesh, or the hierarchy itself (its mesh copied).
    fn take_content_for_topology(&mut self) -> Content {
        match &self.content {
            Content::Plain(m) => Content::Plain(m.clone()),
            Content::Levels(h) => {
                let plain = Content::Plain(Box::new(h.mesh().clone()));
                std::mem::replace(&mut self.content, plain)
            }
        }
    }

    /// The label of the open edit, if any.
    pub fn open_edit(&self) -> Option<&str> {
        self.open_edit.as_ref().map(|(l, _)| l.as_str())
    }

    /// Closes the open edit (if any): the next change starts a new undo step.
    pub fn end_edit(&mut self) {
        self.open_edit = None;
    }

    /// Mutable positions (indexed by `vertex_index`); opens an edit named "edit" if none
    /// is open. Bumps the geometry revision.
    pub fn positions_mut(&mut self) -> &mut [DVec3] {
        if self.open_edit.is_none() {
            self.begin_edit("edit");
        }
        self.revision.geometry += 1;
        self.content.mesh_for_values().positions_mut()
    }

    /// The mesh, mutably, for edits that may change the connectivity; opens (or upgrades)
    /// an edit. Bumps both revisions. A hierarchy goes into the history (see the module
    /// docs).
    pub fn mesh_mut(&mut self) -> &mut Mesh {
        self.begin_topology_edit("edit");
        self.revision.geometry += 1;
        self.revision.topology += 1;
        self.content.mesh_for_values()
    }

    /// Changes the sub-mesh labels (or other attributes) of the mesh with `change`, which
    /// must change neither positions nor connectivity. Not an undo step. When the document
    /// holds a hierarchy and the mesh has a label attribute afterwards, the hierarchy
    /// carries the labels through its levels from here (the paper's Fig. 4 rule); when the
    /// attribute is gone, it stops.
    pub fn edit_labels<R>(&mut self, change: impl FnOnce(&mut Mesh) -> R) -> R {
        let result = change(self.content.mesh_for_values());
        if let Content::Levels(h) = &mut self.content {
            match h.mesh().find_attribute::<VertexId, Label>(LABEL_ATTRIBUTE) {
                Some(attribute) => h.attach_labels(attribute).unwrap(),
                None => h.detach_labels(),
            }
        }
        self.revision.labels += 1;
        result
    }

    /// Makes `hierarchy` (built from the document's mesh, at any level) the document's
    /// content, as one undo step named `label`: undo gives the plain mesh back.
    pub fn set_hierarchy(&mut self, hierarchy: Hierarchy, label: &str) {
        self.end_edit();
        let before = std::mem::replace(&mut self.content, Content::Levels(Box::new(hierarchy)));
        self.log.flush(&mut self.log_ids);
        self.push_undo(Entry {
            label: label.to_owned(),
            snapshot: Snapshot::Content(Box::new(before)),
            log: self.log.clone(),
        });
        self.log.built(&mut self.log_ids);
        self.redo.clear();
        self.bump_all();
    }

    /// Changes the hierarchy with `change` as one undo step named `label` (closing the
    /// open edit first), for changes the hierarchy keeps through its levels (new
    /// vertices at its input: `Hierarchy::edit_input`). `change` works on a copy and
    /// returns its result and whether to keep the change: when it fails or says not to
    /// keep, the document is exactly as it was and no step is recorded; otherwise the copy
    /// becomes the document's hierarchy and the hierarchy as it was goes into the
    /// history, so that undo restores it exactly (mesh, level, records).
    ///
    /// # Errors
    /// [`DocumentError::NoHierarchy`] (converted into `E`) when the document holds a
    /// plain mesh; the error of `change`.
    pub fn edit_hierarchy<R, E: From<DocumentError>>(
        &mut self,
        label: &str,
        change: impl FnOnce(&mut Hierarchy) -> Result<(R, bool), E>,
    ) -> Result<R, E> {
        let Content::Levels(h) = &self.content else {
            return Err(DocumentError::NoHierarchy.into());
        };
        let mut work = h.clone();
        self.end_edit();
        let (result, keep) = change(&mut work)?;
        if keep {
            let before = std::mem::replace(&mut self.content, Content::Levels(work));
            self.log.flush(&mut self.log_ids);
            self.push_undo(Entry {
                label: label.to_owned(),
                snapshot: Snapshot::Content(Box::new(before)),
                log: self.log.clone(),
            });
            self.log.begin_change(label, &mut self.log_ids);
            self.redo.clear();
            self.bump_all();
        }
        Ok(result)
    }

    /// Lets `mark` tell the hierarchy how the open position edit moved its mesh (affine
    /// and region marks, `Hierarchy::set_affine_mark` / `mark_region`), so that refining
    /// it places the finer levels as the edit meant: a handle lands exactly, a region's
    /// motion is interpolated over its fine vertices. Not an undo step of its own: the
    /// marks belong to the positions the edit wrote, and undo or redo of a position step
    /// gives back the marks the hierarchy had with the positions it restores (the step
    /// stores a [`LevelBookmark`]: the positions and the marks), so the edits kept keep
    /// their marks and an undone edit's are gone. Does nothing and returns `Ok(None)` when
    /// the document holds a plain mesh.
    ///
    /// # Errors
    /// The error of `mark`.
    pub fn mark_hierarchy<R, E>(
        &mut self,
        mark: impl FnOnce(&mut Hierarchy) -> Result<R, E>,
    ) -> Result<Option<R>, E> {
        match &mut self.content {
            Content::Levels(h) => mark(h).map(Some),
            Content::Plain(_) => Ok(None),
        }
    }

    /// Moves the hierarchy to `level` (coarser or finer, with its detail coefficients),
    /// as an undo step named `label`; level changes in one open edit (a slider drag) are
    /// one step. The step stores the level and the positions left, not the mesh.
    ///
    /// # Errors
    /// [`DocumentError::NoHierarchy`]; the hierarchy's refusal (a level that does not
    /// exist), the document then unchanged.
    pub fn go_to_level(&mut self, level: usize, label: &str) -> Result<(), DocumentError> {
        let Content::Levels(h) = &mut self.content else {
            return Err(DocumentError::NoHierarchy);
        };
        if h.current_level() == Some(level) {
            return Ok(());
        }
        let open_level = matches!(self.open_edit, Some((_, EditKind::Level)));
        let before = (!open_level).then(|| Snapshot::Level(Box::new(h.bookmark())));
        h.go_to_level(level)?;
        if let Some(snapshot) = before {
            self.log.flush(&mut self.log_ids);
            self.push_undo(Entry {
                label: label.to_owned(),
                snapshot,
                log: self.log.clone(),
            });
            self.redo.clear();
            self.open_edit = Some((label.to_owned(), EditKind::Level));
        }
        self.bump_all();
        Ok(())
    }

    fn bump_all(&mut self) {
        self.revision.geometry += 1;
        self.revision.topology += 1;
        self.revision.labels += 1;
    }

    /// Turns the open positions-only edit into a whole-mesh one.
    fn upgrade_open_edit(&mut self) {
        let Some((_, kind)) = &mut self.open_edit else {
            return;
        };
        if *kind != EditKind::Positions {
            return;
        }
        *kind = EditKind::Topology;
        let Some(entry) = self.undo.last_mut() else {
            return;
        };
        let snapshot = std::mem::replace(&mut entry.snapshot, Snapshot::Positions(Vec::new()));
        let mut before = self.take_content_for_topology();
        match (&snapshot, &mut before) {
            (Snapshot::Positions(p), before) => {
                before.mesh_for_values().positions_mut().copy_from_slice(p);
            }
            (Snapshot::Level(bookmark), Content::Levels(h)) => back_before_edit(h, bookmark),
            _ => {}
        }
        if let Some(entry) = self.undo.last_mut() {
            entry.snapshot = Snapshot::Content(Box::new(before));
        }
    }

    fn push_undo(&mut self, entry: Entry) {
        self.undo.push(entry);
        let mut bytes: usize = self.undo.iter().map(|e| e.snapshot.bytes()).sum();
        while self.undo.len() > 1 && (bytes > HISTORY_BYTES || self.undo.len() > HISTORY_STEPS) {
            bytes -= self.undo.remove(0).snapshot.bytes();
        }
    }

    /// Swaps the current state with `entry`'s snapshot and returns the inverse entry.
    fn swap_in(&mut self, mut entry: Entry) -> Entry {
        std::mem::swap(&mut entry.log, &mut self.log);
        let log = entry.log;
        let snapshot = match entry.snapshot {
            Snapshot::Positions(mut p) => {
                // The hierarchy's marks describe the motion of the positions being
                // swapped out.
                if let Content::Levels(h) = &mut self.content {
                    h.clear_marks();
                }
                let positions = self.content.mesh_for_values().positions_mut();
                if p.len() == positions.len() {
                    positions.swap_with_slice(&mut p);
                    self.revision.geometry += 1;
                }
                // Otherwise (cannot happen with LIFO steps: connectivity changes store
                // the mesh) keep the state rather than corrupt it.
                Snapshot::Positions(p)
            }
            Snapshot::Content(mut c) => {
                std::mem::swap(&mut *c, &mut self.content);
                self.bump_all();
                Snapshot::Content(c)
            }
            Snapshot::Level(bookmark) => match &mut self.content {
                Content::Levels(h) => {
                    let now = Snapshot::Level(Box::new(h.bookmark()));
                    let same_level = h.applied() == bookmark.applied();
                    // Back to a position the hierarchy has been at, exactly; when the
                    // bookmark no longer fits (cannot happen with LIFO steps), a walk
                    // there with the positions put back.
                    let back = h.return_to(&bookmark).is_ok() || {
                        let walked = h.seek(bookmark.applied()).is_ok();
                        if walked {
                            let target = h.mesh_mut().positions_mut();
                            if target.len() == bookmark.positions().len() {
                                target.copy_from_slice(bookmark.positions());
                            }
                        }
                        walked
                    };
                    if back {
                        if same_level {
                            // Positions and marks only (a position edit's undo).
                            self.revision.geometry += 1;
                        } else {
                            self.bump_all();
                        }
                        now
                    } else {
                        Snapshot::Level(bookmark)
                    }
                }
                // Cannot happen with LIFO steps (the hierarchy is restored first).
                Content::Plain(_) => Snapshot::Level(bookmark),
            },
        };
        Entry {
            label: entry.label,
            snapshot,
            log,
        }
    }

    /// Undoes the last step; returns its label, `None` when there is nothing to undo.
    pub fn undo(&mut self) -> Option<String> {
        self.end_edit();
        let entry = self.undo.pop()?;
        let inverse = self.swap_in(entry);
        let label = inverse.label.clone();
        self.redo.push(inverse);
        Some(label)
    }

    /// Redoes the last undone step; returns its label.
    pub fn redo(&mut self) -> Option<String> {
        self.end_edit();
        let entry = self.redo.pop()?;
        let inverse = self.swap_in(entry);
        let label = inverse.label.clone();
        self.undo.push(inverse);
        Some(label)
    }

    /// Labels of the undo steps, oldest first.
    pub fn undo_labels(&self) -> impl Iterator<Item = &str> {
        self.undo.iter().map(|e| e.label.as_str())
    }

    /// Labels of the redo steps, next first.
    pub fn redo_labels(&self) -> impl Iterator<Item = &str> {
        self.redo.iter().rev().map(|e| e.label.as_str())
    }

    /// Number of undo steps available.
    pub fn undo_len(&self) -> usize {
        self.undo.len()
    }

    /// Approximate memory held by the undo steps, bytes.
    pub fn undo_bytes(&self) -> usize {
        self.undo.iter().map(|e| e.snapshot.bytes()).sum()
    }

    /// Number of redo steps available.
    pub fn redo_len(&self) -> usize {
        self.redo.len()
    }

    /// The edits as recipe steps (see [`crate::recipe_log`]).
    pub fn recipe_log(&self) -> &RecipeLog {
        &self.log
    }

    /// Records the step of the change just made (`Err`: what it was, when it has no
    /// recipe step), replacing the entry `replacing` names when it is the last one (the
    /// same edit changed again, see [`RecipeLog`]). Returns the entry's id.
    pub fn record_step(
        &mut self,
        replacing: Option<RecordId>,
        step: Result<Step, String>,
    ) -> RecordId {
        self.log.record(replacing, step, &mut self.log_ids)
    }

    /// Sets the options of the hierarchy build the log starts from (`None`: options the
    /// recipe's `[hierarchy]` table cannot express).
    pub fn set_recipe_hierarchy(&mut self, spec: Option<HierarchySpec>) {
        self.log.set_built_spec(spec);
    }

    /// The level a step made now is made at: `Ok(None)` on a plain mesh, `Ok(Some(l))`
    /// at level `l` of the hierarchy.
    ///
    /// # Errors
    /// A message when the hierarchy is between levels.
    pub fn recipe_level(&self) -> Result<Option<usize>, String> {
        match &self.content {
            Content::Plain(_) => Ok(None),
            Content::Levels(h) => h
                .current_level()
                .map(Some)
                .ok_or_else(|| "the hierarchy is between two levels".to_owned()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use halfedge::generators;

    fn doc() -> Document {
        Document::new(generators::icosphere(1), None, None)
    }

    #[test]
    fn a_soup_file_is_read_as_its_surface() {
        let sphere = generators::icosphere(2);
        let (corners, faces) = generators::triangle_soup(&sphere);
        let (soup, _) = Mesh::from_arrays(&corners, &faces).unwrap();
        let path = std::env::temp_dir().join(format!("viewer-soup-{}.ply", std::process::id()));
        halfedge::io::write(&path, &soup).unwrap();
        let (mesh, report, welded) = read_mesh(&path).unwrap();
        std::fs::remove_file(&path).ok();
        assert_eq!(welded, corners.len() - sphere.n_vertices());
        assert_eq!(
            (mesh.n_vertices(), mesh.n_faces()),
            (sphere.n_vertices(), sphere.n_faces())
        );
        let topology = mesh.topology_report();
        assert_eq!((topology.components, topology.boundary_loops), (1, 0));
        assert_eq!(report.duplicated_vertices, 0);
        // A mesh with nothing to weld is read as it is.
        let path = std::env::temp_dir().join(format!("viewer-sphere-{}.ply", std::process::id()));
        halfedge::io::write(&path, &sphere).unwrap();
        let (mesh, _, welded) = read_mesh(&path).unwrap();
        std::fs::remove_file(&path).ok();
        assert_eq!((welded, mesh.to_arrays()), (0, sphere.to_arrays()));
    }

    #[test]
    fn one_gesture_is_one_step_and_undo_redo_restore_exactly() {
        let mut d = doc();
        let before = d.mesh().positions().to_vec();
        d.begin_edit("pull");
        for k in 0..5 {
            d.positions_mut()[3] += DVec3::splat(0.1 * k as f64);
        }
        d.end_edit();
        let after = d.mesh().positions().to_vec();
        assert_ne!(before, after);
        assert_eq!(d.undo_len(), 1);
        assert_eq!(d.undo().as_deref(), Some("pull"));
        assert_eq!(d.mesh().positions(), &before[..]);
        assert_eq!(d.redo().as_deref(), Some("pull"));
        assert_eq!(d.mesh().positions(), &after[..]);
        assert!(d.redo().is_none());
    }

    #[test]
    fn a_new_edit_clears_redo_and_implicit_edits_are_recorded() {
        let mut d = doc();
        d.positions_mut()[0] = DVec3::ZERO;
        d.end_edit();
        d.positions_mut()[1] = DVec3::ZERO;
        d.end_edit();
        assert_eq!(d.undo_len(), 2);
        d.undo();
        assert_eq!(d.redo_len(), 1);
        d.begin_edit("other");
        assert_eq!(d.redo_len(), 0);
        assert_eq!(d.undo_labels().collect::<Vec<_>>(), ["edit", "other"]);
    }

    #[test]
    fn topology_edits_store_the_mesh_and_upgrade_keeps_the_old_positions() {
        let mut d = doc();
        let original = d.mesh().positions().to_vec();
        let faces = d.mesh().n_faces();
        d.begin_edit("pull then refine");
        d.positions_mut()[0] = DVec3::splat(7.0);
        let refined = generators::subdivide(d.mesh());
        *d.mesh_mut() = refined;
        d.end_edit();
        assert_eq!(d.mesh().n_faces(), 4 * faces);
        let topo = d.revision().topology;
        d.undo();
        assert!(d.revision().topology > topo);
        assert_eq!(d.mesh().n_faces(), faces);
        assert_eq!(d.mesh().positions(), &original[..]);
        d.mesh().check().unwrap();
        d.redo();
        assert_eq!(d.mesh().n_faces(), 4 * faces);
        assert_eq!(d.mesh().positions()[0], DVec3::splat(7.0));
    }

    #[test]
    fn revisions_track_changes() {
        let mut d = doc();
        let r0 = d.revision();
        d.positions_mut();
        let r1 = d.revision();
        assert!(r1.geometry > r0.geometry && r1.topology == r0.topology);
        d.replace(generators::icosphere(0), None, None);
        let r2 = d.revision();
        assert!(r2.geometry > r1.geometry && r2.topology > r1.topology);
        assert_eq!(d.undo_len(), 0);
    }

    fn hierarchy_doc() -> (Document, Mesh) {
        let input = generators::icosphere(3);
        let h = Hierarchy::build(
            input.clone(),
            &halfedge::hierarchy::HierarchyOptions::rounds().with_target_faces(100),
        )
        .unwrap();
        let mut d = Document::new(input.clone(), None, None);
        let mut h = h;
        h.go_to_level(0).unwrap();
        d.set_hierarchy(h, "build");
        (d, input)
    }

    #[test]
    fn a_slider_drag_over_levels_is_one_step_that_stores_positions_not_meshes() {
        let (mut d, input) = hierarchy_doc();
        assert!(std::ptr::eq(d.mesh(), d.hierarchy().unwrap().mesh()));
        let coarsest = d.hierarchy().unwrap().coarsest_level();
        assert!(coarsest >= 2);
        let before = d.undo_bytes();
        for level in 1..=coarsest {
            d.go_to_level(level, "levels").unwrap();
        }
        d.end_edit();
        assert_eq!(d.undo_labels().collect::<Vec<_>>(), ["build", "levels"]);
        // The step holds the positions of the level left, no copy of the mesh.
        let step = d.undo_bytes() - before;
        assert_eq!(step, input.vertex_slots() * std::mem::size_of::<DVec3>());
        assert_eq!(
            d.mesh().n_faces(),
            d.hierarchy().unwrap().level_face_counts()[coarsest]
        );
        assert_eq!(d.undo().as_deref(), Some("levels"));
        assert_eq!(d.hierarchy().unwrap().current_level(), Some(0));
        assert_eq!(d.mesh().positions(), input.positions());
        assert_eq!(d.redo().as_deref(), Some("levels"));
        assert_eq!(d.hierarchy().unwrap().current_level(), Some(coarsest));
        assert!(matches!(
            d.go_to_level(coarsest + 1, "x"),
            Err(DocumentError::Hierarchy(_))
        ));
        assert_eq!(d.hierarchy().unwrap().current_level(), Some(coarsest));
        let mut plain = doc();
        assert!(matches!(
            plain.go_to_level(1, "x"),
            Err(DocumentError::NoHierarchy)
        ));
    }

    #[test]
    fn an_edit_at_a_coarse_level_undoes_exactly_through_the_levels() {
        let (mut d, input) = hierarchy_doc();
        d.go_to_level(2, "coarsen").unwrap();
        d.end_edit();
        let coarse = d.mesh().positions().to_vec();
        for p in d.positions_mut() {
            *p += DVec3::X;
        }
        d.end_edit();
        d.go_to_level(0, "refine").unwrap();
        d.end_edit();
        let moved = d.mesh().positions().to_vec();
        assert_ne!(moved, input.positions());
        d.undo();
        assert_eq!(d.hierarchy().unwrap().current_level(), Some(2));
        assert_eq!(d.mesh().positions()[0], coarse[0] + DVec3::X);
        d.undo();
        assert_eq!(d.mesh().positions(), &coarse[..]);
        d.undo();
        assert_eq!(d.mesh().positions(), input.positions());
        // And forward again.
        d.redo();
        d.redo();
        d.redo();
        assert_eq!(d.mesh().positions(), &moved[..]);
    }

    #[test]
    fn a_coarse_edit_undone_after_a_walk_to_the_input_refines_to_the_input_again() {
        // Edit at level 2, refine to the input, undo both, refine again: the input, bit
        // for bit (the undone walk must not collapse the edited fine mesh into the
        // records); redoing the walk after the undo gives the first refinement.
        let (mut d, input) = hierarchy_doc();
        d.go_to_level(2, "coarsen").unwrap();
        d.end_edit();
        let moved: Vec<VertexId> = d
            .mesh()
            .vertices()
            .filter(|&v| d.mesh().position(v).x > 0.3)
            .collect();
        {
            let h = match &mut d.content {
                Content::Levels(h) => h,
                Content::Plain(_) => unreachable!(),
            };
            h.mark_region(&moved).unwrap();
        }
        for &v in &moved {
            let (p, i) = (d.mesh().position(v), d.mesh().vertex_index(v));
            d.positions_mut()[i] = p + DVec3::Z * (0.2 * p.x);
        }
        d.end_edit();
        d.go_to_level(0, "refine").unwrap();
        d.end_edit();
        let refined = d.mesh().positions().to_vec();
        assert_ne!(refined, input.positions());
        d.undo();
        d.redo();
        assert_eq!(d.mesh().positions(), &refined[..], "the walk redone");
        d.undo();
        d.undo();
        assert_eq!(d.hierarchy().unwrap().current_level(), Some(2));
        d.go_to_level(0, "refine again").unwrap();
        d.end_edit();
        assert_eq!(d.mesh().positions(), input.positions());
    }

    #[test]
    fn a_connectivity_change_leaves_a_plain_mesh_and_undo_brings_the_hierarchy_back() {
        let (mut d, _) = hierarchy_doc();
        d.go_to_level(1, "coarsen").unwrap();
        d.end_edit();
        let faces = d.mesh().n_faces();
        let refined = generators::subdivide(d.mesh());
        *d.mesh_mut() = refined;
        d.end_edit();
        assert!(d.hierarchy().is_none());
        assert_eq!(d.mesh().n_faces(), 4 * faces);
        d.undo();
        assert_eq!(d.hierarchy().unwrap().current_level(), Some(1));
        assert!(std::ptr::eq(d.mesh(), d.hierarchy().unwrap().mesh()));
        assert_eq!(d.mesh().n_faces(), faces);
        d.go_to_level(0, "refine").unwrap();
        d.mesh().check().unwrap();
    }

    #[test]
    fn a_hierarchy_edit_keeps_the_hierarchy_and_undo_restores_it_exactly() {
        let (mut d, input) = hierarchy_doc();
        d.go_to_level(2, "coarsen").unwrap();
        d.end_edit();
        let before = d.mesh().positions().to_vec();
        let (vertices, steps) = (d.mesh().n_vertices(), d.undo_len());
        // Refused or not kept: nothing changes, no step.
        let r: Result<(), DocumentError> = d.edit_hierarchy("fail", |h| {
            h.mesh_mut().positions_mut()[0] = DVec3::splat(9.0);
            Err(DocumentError::NoHierarchy)
        });
        assert!(r.is_err());
        let kept = d.edit_hierarchy("skip", |h| {
            h.mesh_mut().positions_mut()[0] = DVec3::splat(9.0);
            Ok::<_, DocumentError>((7, false))
        });
        assert_eq!(kept.unwrap(), 7);
        assert_eq!(d.undo_len(), steps);
        assert_eq!(d.mesh().positions(), &before[..]);
        // A change at the input: split one edge there.
        let topology = d.revision().topology;
        d.edit_hierarchy("split", |h| {
            h.edit_input(|m| {
                let e = m.edges().next().unwrap();
                let p = 0.5 * (m.position(m.from_vertex(e)) + m.position(m.to_vertex(e)));
                m.split_edge(e, p).map(|_| ())
            })?;
            Ok::<_, DocumentError>(((), true))
        })
        .unwrap();
        assert!(d.revision().topology > topology);
        let h = d.hierarchy().expect("the hierarchy stays");
        assert_eq!(h.current_level(), Some(2));
        assert!(std::ptr::eq(d.mesh(), h.mesh()));
        assert_eq!(d.undo_labels().last(), Some("split"));
        d.go_to_level(0, "refine").unwrap();
        assert_eq!(d.mesh().n_vertices(), input.n_vertices() + 1);
        d.undo();
        d.undo();
        assert_eq!(d.hierarchy().unwrap().current_level(), Some(2));
        assert_eq!(d.mesh().n_vertices(), vertices);
        assert_eq!(d.mesh().positions(), &before[..]);
        d.redo();
        d.go_to_level(0, "refine").unwrap();
        assert_eq!(d.mesh().n_vertices(), input.n_vertices() + 1);
        // A plain mesh has no hierarchy to edit.
        let mut plain = doc();
        let r = plain.edit_hierarchy("x", |_| Ok::<_, DocumentError>(((), true)));
        assert!(matches!(r, Err(DocumentError::NoHierarchy)));
    }

    #[test]
    fn labels_are_the_meshs_attribute_and_the_hierarchy_carries_them() {
        let (mut d, _) = hierarchy_doc();
        let r = d.revision().labels;
        let frontier = d.mesh().frontier_from_plane(DVec3::ZERO, DVec3::X).unwrap();
        d.edit_labels(|m| m.label_sides(&frontier, 1, 0).map(|_| ()))
            .unwrap();
        assert!(d.revision().labels > r);
        assert_eq!(d.undo_len(), 1, "labels are not an undo step");
        assert!(d.hierarchy().unwrap().label_attribute().is_some());
        d.go_to_level(2, "coarsen").unwrap();
        let a = d
            .mesh()
            .find_attribute::<VertexId, Label>(LABEL_ATTRIBUTE)
            .unwrap();
        let values = d.mesh().attribute_values(a).unwrap();
        assert!(d
            .mesh()
            .vertices()
            .all(|v| values[d.mesh().vertex_index(v)] <= 1
                || values[d.mesh().vertex_index(v)] == halfedge::labels::FRONTIER));
        d.edit_labels(|m| m.remove_attribute(a).unwrap());
        assert!(d.hierarchy().unwrap().label_attribute().is_none());
    }
}
