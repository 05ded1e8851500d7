//! The edited mesh and its undo / redo history.
//!
//! Every change goes through an *edit*: [`Document::begin_edit`] stores what is needed to
//! go back (the positions for a geometric edit, the whole mesh once the connectivity
//! changes) and [`Document::end_edit`] closes it, so that one gesture (a drag, a slider
//! drag, a button press) is one undo step however many frames it spans. Asking for
//! [`Document::positions_mut`] or [`Document::mesh_mut`] outside an edit opens one, so no
//! change can escape the history. A positions-only edit that turns out to change the
//! connectivity is upgraded on the fly (the snapshot becomes the old mesh: exact, since
//! the connectivity had not changed yet).
//!
//! Revisions (`geometry`, `topology`) tell the renderer what to refresh; the picking
//! structure (the library's `halfedge::bvh::Bvh`) keeps itself current from the mesh.

use std::path::PathBuf;

use glam::DVec3;
use halfedge::{BuildReport, Mesh};

/// What an undo step restores.
#[derive(Clone)]
pub enum Snapshot {
    /// Vertex positions (indexed by `vertex_index`) over unchanged connectivity.
    Positions(Vec<DVec3>),
    /// The whole mesh.
    Mesh(Box<Mesh>),
}

impl Snapshot {
    /// Approximate memory held, bytes.
    pub fn bytes(&self) -> usize {
        match self {
            Snapshot::Positions(p) => p.len() * std::mem::size_of::<DVec3>(),
            // Positions + three slot maps + key arrays: about 200 bytes per vertex.
            Snapshot::Mesh(m) => 200 * m.vertex_slots().max(1),
        }
    }
}

/// One step of the history: its label and the state before (undo) or after (redo) it.
#[derive(Clone)]
struct Entry {
    label: String,
    snapshot: Snapshot,
}

/// Counters bumped by every change, for caches to compare against.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Revision {
    /// Bumped when positions change (also on connectivity changes).
    pub geometry: u64,
    /// Bumped when the connectivity (or the whole mesh) changes.
    pub topology: u64,
}

/// Largest memory the undo stack may hold before the oldest steps are dropped.
const HISTORY_BYTES: usize = 1 << 30;
/// Most undo steps kept.
const HISTORY_STEPS: usize = 200;

/// The mesh being edited, where it came from, and its history.
pub struct Document {
    mesh: Mesh,
    source: Option<PathBuf>,
    build_report: Option<BuildReport>,
    undo: Vec<Entry>,
    redo: Vec<Entry>,
    open_edit: Option<(String, bool)>,
    revision: Revision,
}

impl Document {
    /// A document on `mesh`, with an empty history.
    pub fn new(mesh: Mesh, source: Option<PathBuf>, build_report: Option<BuildReport>) -> Self {
        Self {
            mesh,
            source,
            build_report,
            undo: Vec::new(),
            redo: Vec::new(),
            open_edit: None,
            revision: Revision::default(),
        }
    }

    /// Replaces the mesh by a freshly loaded one and clears the history.
    pub fn replace(&mut self, mesh: Mesh, source: Option<PathBuf>, report: Option<BuildReport>) {
        let revision = self.revision;
        *self = Self::new(mesh, source, report);
        self.revision = Revision {
            geometry: revision.geometry + 1,
            topology: revision.topology + 1,
        };
    }

    /// The mesh.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
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
        self.push_undo(Entry {
            label: label.to_owned(),
            snapshot: Snapshot::Positions(self.mesh.positions().to_vec()),
        });
        self.redo.clear();
        self.open_edit = Some((label.to_owned(), false));
    }

    /// Opens an edit that may change the connectivity: stores the whole mesh.
    pub fn begin_topology_edit(&mut self, label: &str) {
        if self.open_edit.is_none() {
            self.push_undo(Entry {
                label: label.to_owned(),
                snapshot: Snapshot::Mesh(Box::new(self.mesh.clone())),
            });
            self.redo.clear();
            self.open_edit = Some((label.to_owned(), true));
        } else {
            self.upgrade_open_edit();
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
        self.mesh.positions_mut()
    }

    /// The mesh, mutably, for edits that may change the connectivity; opens (or upgrades)
    /// an edit. Bumps both revisions.
    pub fn mesh_mut(&mut self) -> &mut Mesh {
        self.begin_topology_edit("edit");
        self.revision.geometry += 1;
        self.revision.topology += 1;
        &mut self.mesh
    }

    /// Turns the open positions-only edit into a whole-mesh one.
    fn upgrade_open_edit(&mut self) {
        let Some((_, topology)) = &mut self.open_edit else {
            return;
        };
        if *topology {
            return;
        }
        *topology = true;
        let entry = self
            .undo
            .last_mut()
            .expect("an open edit has an undo entry");
        if let Snapshot::Positions(p) = &entry.snapshot {
            let mut before = self.mesh.clone();
            before.positions_mut().copy_from_slice(p);
            entry.snapshot = Snapshot::Mesh(Box::new(before));
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
    fn swap_in(&mut self, entry: Entry) -> Entry {
        let snapshot = match entry.snapshot {
            Snapshot::Positions(mut p) => {
                if p.len() == self.mesh.positions().len() {
                    self.mesh.positions_mut().swap_with_slice(&mut p);
                    self.revision.geometry += 1;
                    Snapshot::Positions(p)
                } else {
                    // Cannot happen with LIFO steps (connectivity changes store the mesh);
                    // keep the state rather than corrupt it.
                    Snapshot::Positions(p)
                }
            }
            Snapshot::Mesh(mut m) => {
                std::mem::swap(&mut *m, &mut self.mesh);
                self.revision.geometry += 1;
                self.revision.topology += 1;
                Snapshot::Mesh(m)
            }
        };
        Entry {
            label: entry.label,
            snapshot,
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

    /// Number of redo steps available.
    pub fn redo_len(&self) -> usize {
        self.redo.len()
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
}
