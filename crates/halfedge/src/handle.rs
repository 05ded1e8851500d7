//! Element handles: versioned `slotmap` keys.
//!
//! A handle is a slot index and a version. A handle stays valid until its element is
//! removed for good (by [`Mesh::garbage_collection`](crate::Mesh::garbage_collection));
//! a slot freed there gets a new version when it is reused, so a stale handle is
//! detected by the validity queries and never silently aliases another element.
//! Collapsed elements are kept as tombstones so that a vertex split revives the very
//! handles the collapse removed.
//!
//! The kernel stores connectivity in flat `u32` arrays (see [`crate::Mesh`]); the
//! [`Slots`] table keeps each slot's version and state next to them.

use slotmap::{new_key_type, Key, KeyData};

new_key_type! {
    /// Handle of a vertex.
    pub struct VertexId;
    /// Handle of a halfedge (one side of an edge, oriented from `from_vertex` to `to_vertex`).
    pub struct HalfedgeId;
    /// Handle of a (triangle) face.
    pub struct FaceId;
}

/// Key of slot `index` with generation `generation` (version `2 g + 1`, odd as `slotmap`
/// wants it; key index `index + 1`, since index 0 is `slotmap`'s null key).
#[inline]
pub(crate) fn key<K: Key>(index: u32, generation: u32) -> K {
    let version = u64::from(generation) * 2 + 1;
    KeyData::from_ffi((version << 32) | (u64::from(index) + 1)).into()
}

/// Generation of a key (see [`key`]).
#[inline]
pub(crate) fn generation<K: Key>(k: K) -> u32 {
    ((k.data().as_ffi() >> 32) as u32) >> 1
}

/// "No element" in the connectivity arrays.
pub(crate) const NONE: u32 = u32::MAX;

/// State of a slot, in the low two bits of its [`Slots`] entry.
const VACANT: u32 = 0;
const LIVE: u32 = 1;
const TOMBSTONE: u32 = 2;

/// Generation and state of every slot of one element kind: `generation << 2 | state`,
/// where the state is vacant (freed by garbage collection, or never used), live or a
/// tombstone (removed by a collapse, revivable by a split).
#[derive(Clone, Debug, Default)]
pub(crate) struct Slots {
    meta: Vec<u32>,
    /// Vacant slots, reused last-freed first.
    free: Vec<u32>,
    /// True once a freed slot has been reused: only then can a live slot have a
    /// generation other than 0, and handles need their generation looked up.
    reused: bool,
}

impl Slots {
    /// Room for `n` slots.
    pub(crate) fn with_capacity(n: usize) -> Self {
        Self {
            meta: Vec::with_capacity(n),
            ..Self::default()
        }
    }
    /// `n` live slots of generation 0.
    pub(crate) fn live(n: usize) -> Self {
        Self {
            meta: vec![LIVE; n],
            ..Self::default()
        }
    }
    /// The key of slot `i` (its current generation).
    #[inline]
    pub(crate) fn key<K: Key>(&self, i: u32) -> K {
        if self.reused {
            key(i, self.meta[i as usize] >> 2)
        } else {
            key(i, 0)
        }
    }
    #[inline]
    fn state_of<K: Key>(&self, k: K) -> Option<u32> {
        let m = *self.meta.get(slot(k))?;
        (m >> 2 == generation(k)).then_some(m & 3)
    }
    /// True when `k` names a live element.
    #[inline]
    pub(crate) fn is_live<K: Key>(&self, k: K) -> bool {
        self.state_of(k) == Some(LIVE)
    }
    /// True when `k` names a tombstone.
    #[inline]
    pub(crate) fn is_tombstone<K: Key>(&self, k: K) -> bool {
        self.state_of(k) == Some(TOMBSTONE)
    }
    /// True when `k` names a live element or a tombstone.
    #[inline]
    pub(crate) fn contains<K: Key>(&self, k: K) -> bool {
        matches!(self.state_of(k), Some(LIVE | TOMBSTONE))
    }
    /// True when slot `i` is live.
    #[inline]
    pub(crate) fn is_live_index(&self, i: usize) -> bool {
        self.meta.get(i).is_some_and(|m| m & 3 == LIVE)
    }
    /// Marks slot `i` a tombstone (it was live).
    #[inline]
    pub(crate) fn bury(&mut self, i: usize) {
        self.meta[i] = (self.meta[i] & !3) | TOMBSTONE;
    }
    /// Makes tombstone `i` live again.
    #[inline]
    pub(crate) fn revive(&mut self, i: usize) {
        self.meta[i] = (self.meta[i] & !3) | LIVE;
    }
    /// A slot for a new element: `(index, true)` for a reused vacant slot (next
    /// generation), `(index, false)` for a new slot at the end (the caller pushes its
    /// arrays).
    pub(crate) fn allocate(&mut self) -> (u32, bool) {
        if let Some(i) = self.free.pop() {
            self.reused = true;
            self.meta[i as usize] = (self.meta[i as usize] & !3) | LIVE;
            (i, true)
        } else {
            self.meta.push(LIVE);
            ((self.meta.len() - 1) as u32, false)
        }
    }
    /// Two consecutive slots `(i, i + 1)`, `i` even, for the halfedges of a new edge; the
    /// free list of halfedges holds even indices only (edges are freed whole).
    pub(crate) fn allocate_pair(&mut self) -> (u32, bool) {
        if let Some(i) = self.free.pop() {
            self.reused = true;
            for j in [i as usize, i as usize + 1] {
                self.meta[j] = (self.meta[j] & !3) | LIVE;
            }
            (i, true)
        } else {
            self.meta.push(LIVE);
            self.meta.push(LIVE);
            ((self.meta.len() - 2) as u32, false)
        }
    }
    /// Frees every tombstone for good (vacant, next generation) and returns their indices.
    pub(crate) fn free_tombstones(&mut self) -> Vec<u32> {
        let mut freed = Vec::new();
        for (i, m) in self.meta.iter_mut().enumerate() {
            if *m & 3 == TOMBSTONE {
                *m = ((*m >> 2) + 1) << 2 | VACANT;
                freed.push(i as u32);
            }
        }
        freed
    }
    /// Adds slots to the free list (after [`free_tombstones`](Self::free_tombstones)).
    pub(crate) fn push_free(&mut self, slots: impl IntoIterator<Item = u32>) {
        self.free.extend(slots);
    }
    /// Indices of the live slots, in order.
    #[inline]
    pub(crate) fn live_indices(&self) -> impl Iterator<Item = u32> + Clone + '_ {
        self.meta
            .iter()
            .enumerate()
            .filter(|(_, m)| *m & 3 == LIVE)
            .map(|(i, _)| i as u32)
    }
    /// Number of live slots.
    pub(crate) fn live_count(&self) -> usize {
        self.meta.iter().filter(|m| *m & 3 == LIVE).count()
    }
}

/// Dense slot index of a key: the position of its element in per-element arrays
/// (positions, attributes): the key's index minus one (index 0 is the null key, whose
/// slot is out of every range).
#[inline]
pub(crate) fn slot<K: Key>(key: K) -> usize {
    ((key.data().as_ffi() & 0xffff_ffff) as usize).wrapping_sub(1)
}

impl std::fmt::Display for VertexId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "v{}", slot(*self))
    }
}
impl std::fmt::Display for HalfedgeId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "h{}", slot(*self))
    }
}
impl std::fmt::Display for FaceId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "f{}", slot(*self))
    }
}
