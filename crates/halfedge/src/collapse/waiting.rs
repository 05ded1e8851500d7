//! The collapses made through [`Mesh::collapse`] whose records still wait for their split.
//!
//! A record names one collapse event, and only that one: once its collapse was undone and
//! the same edge collapsed again, the old record is refused (the new one is the record of
//! `v0`'s removal). And splits of these records undo their collapses in reverse order:
//! splitting a record while a later collapse is still waiting could strand the later
//! record (its neighbourhood is no longer what its collapse left), so it is refused with
//! the record to split first. Collapses made by a hierarchy's own steps are not kept here
//! (a hierarchy splits its records in order by construction).
//!
//! The map holds one small entry per waiting public collapse (nothing for a hierarchy's
//! millions of records), is copied by a clone (records made before the clone belong to
//! both meshes' histories), and is emptied by garbage collection (whose freed records are
//! refused anyway).

use std::collections::HashMap;

use crate::mesh::Mesh;

/// One waiting collapse: the record's instance and change count (what names the event)
/// and its vertices (for messages).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Waiting {
    pub(crate) instance: u64,
    pub(crate) count: u64,
    pub(crate) v1: u32,
}

/// The waiting collapses of a mesh, by the slot of their removed vertex `v0`.
#[derive(Clone, Debug, Default)]
pub(crate) struct WaitingCollapses {
    by_v0: HashMap<u32, Waiting>,
}

impl WaitingCollapses {
    /// Records the collapse that removed `v0`.
    pub(crate) fn insert(&mut self, v0: u32, waiting: Waiting) {
        self.by_v0.insert(v0, waiting);
    }

    /// The waiting collapse that removed `v0`, if any.
    pub(crate) fn get(&self, v0: u32) -> Option<&Waiting> {
        self.by_v0.get(&v0)
    }

    /// Forgets the collapse of `v0` (its vertex was split back in).
    #[inline]
    pub(crate) fn remove(&mut self, v0: u32) {
        if !self.by_v0.is_empty() {
            self.by_v0.remove(&v0);
        }
    }

    /// Forgets every waiting collapse (garbage collection freed their elements).
    pub(crate) fn clear(&mut self) {
        self.by_v0.clear();
    }

    /// The latest waiting collapse made after change count `count`, other than the one
    /// of `v0`: the record to split before one made at `count`.
    pub(crate) fn latest_after(&self, count: u64, v0: u32) -> Option<(u32, Waiting)> {
        self.by_v0
            .iter()
            .filter(|&(&w0, w)| w0 != v0 && w.count > count)
            .max_by_key(|&(&w0, w)| (w.count, w0))
            .map(|(&w0, &w)| (w0, w))
    }
}

impl Mesh {
    /// Why the split of the record of `v0`, made at (`instance`, `count`), would not undo
    /// the collapse event it names or would strand a later record (see the
    /// [module docs](self)), or `None`.
    pub(crate) fn split_event_conflict(
        &self,
        v0: u32,
        instance: u64,
        count: u64,
        tracked: bool,
    ) -> Option<String> {
        match self.waiting.get(v0) {
            Some(w) if (w.instance, w.count) != (instance, count) => {
                return Some(
                    "the record names an earlier collapse of this edge, undone since: the edge \
                     was collapsed again and the newer record is the one to split"
                        .to_owned(),
                );
            }
            None if tracked => {
                return Some("v0 was split back in since: the record was already split".to_owned());
            }
            _ => {}
        }
        let (w0, w) = self.waiting.latest_after(count, v0)?;
        Some(format!(
            "a later collapse still waits for its split ({} → {}): splits undo collapses in \
             reverse order, and splitting this record first could strand that one; split it \
             first",
            self.vh(w0),
            self.vh(w.v1)
        ))
    }
}
