//! The collapse records a hierarchy keeps, and the buffers a rebuild borrows.

use super::buffers::adopt;
use super::detail::Details;
use super::placements;
use super::Hierarchy;
use crate::binding::Binding;
use crate::collapse::Step;

/// The collapse records of a hierarchy: the compact records the walks use, and apart
/// (cold) what only a checked split compares: each record's fingerprint, and once for all
/// records the mesh instance they were made on.
#[derive(Clone, Debug, Default)]
pub(crate) struct Records {
    pub(super) steps: Vec<Step>,
    pub(super) fingerprints: Vec<u64>,
    /// The mesh's [`Binding`] after the hierarchy's last step while it
    /// trusted its mesh: every record was made on that mesh instance (or one it was
    /// cloned from) at or before that change count, which is what
    /// `Mesh::is_own_history` needs to vouch for a record's indices.
    pub(super) origin: Option<Binding>,
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
    pub(super) fn push(&mut self, step: Step, fingerprint: u64) {
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
    pub(super) fn adopt(&mut self, steps: Vec<Step>, fingerprints: Vec<u64>) {
        adopt(&mut self.steps, steps);
        adopt(&mut self.fingerprints, fingerprints);
    }
    /// Gives back unused capacity.
    pub(crate) fn shrink_to_fit(&mut self) {
        self.steps.shrink_to_fit();
        self.fingerprints.shrink_to_fit();
    }
    /// Heap bytes.
    pub(super) fn heap_bytes(&self) -> usize {
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

/// The buffers of a hierarchy's records and detail coefficients, handed from a hierarchy
/// that is about to be replaced to the build that replaces it: the rebuild then holds one
/// set of buffers instead of two and faults in no fresh pages.
#[derive(Default)]
pub(crate) struct Storage {
    pub(super) records: Records,
    pub(super) placements: placements::Placements,
    pub(super) details: Option<Details>,
}

impl Storage {
    /// Takes the buffers out of `h`, leaving it without records.
    pub(super) fn take(h: &mut Hierarchy) -> Self {
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
