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

/// State of a slot: two bits in [`Slots`].
const VACANT: u64 = 0;
const LIVE: u64 = 1;
const TOMBSTONE: u64 = 2;
/// Slots per state word.
const PER_WORD: usize = 32;

/// State and generation of every slot of one element kind. The state — vacant (never
/// used, or freed by garbage collection), live, or a tombstone (removed by a collapse,
/// revivable by a split) — is packed two bits a slot, so the states of a million-face
/// mesh take a few hundred kilobytes and stay in cache while collapses and splits flip
/// them. Generations (how often a slot was reused) live apart and are read only once a
/// freed slot has been reused.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct Slots {
    states: Vec<u64>,
    generations: Vec<u32>,
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
            states: Vec::with_capacity(n.div_ceil(PER_WORD)),
            generations: Vec::with_capacity(n),
            ..Self::default()
        }
    }
    /// `n` live slots of generation 0.
    pub(crate) fn live(n: usize) -> Self {
        let mut states = vec![0x5555_5555_5555_5555u64; n.div_ceil(PER_WORD)];
        if n % PER_WORD != 0 {
            if let Some(last) = states.last_mut() {
                *last &= (1u64 << (2 * (n % PER_WORD))) - 1;
            }
        }
        Self {
            states,
            generations: vec![0; n],
            ..Self::default()
        }
    }
    #[inline]
    fn state(&self, i: usize) -> u64 {
        (self.states[i / PER_WORD] >> (2 * (i % PER_WORD))) & 3
    }
    #[inline]
    fn set_state(&mut self, i: usize, state: u64) {
        let word = &mut self.states[i / PER_WORD];
        let shift = 2 * (i % PER_WORD);
        *word = (*word & !(3 << shift)) | (state << shift);
    }
    /// Prefetches the state word of slot `i` (see [`crate::prefetch`]).
    #[inline(always)]
    pub(crate) fn prefetch_state(&self, i: usize) {
        crate::prefetch::prefetch(&self.states, i / PER_WORD);
    }
    /// Generation of slot `i`.
    #[inline]
    fn generation_of(&self, i: usize) -> u32 {
        if self.reused {
            self.generations[i]
        } else {
            0
        }
    }
    /// The key of slot `i` (its current generation).
    #[inline]
    pub(crate) fn key<K: Key>(&self, i: u32) -> K {
        key(i, self.generation_of(i as usize))
    }
    #[inline]
    fn state_of<K: Key>(&self, k: K) -> Option<u64> {
        let i = slot(k);
        (i < self.generations.len() && self.generation_of(i) == generation(k))
            .then(|| self.state(i))
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
        i < self.generations.len() && self.state(i) == LIVE
    }
    /// Marks slot `i` a tombstone (it was live).
    #[inline]
    pub(crate) fn bury(&mut self, i: usize) {
        self.set_state(i, TOMBSTONE);
    }
    /// Makes tombstone `i` live again.
    #[inline]
    pub(crate) fn revive(&mut self, i: usize) {
        self.set_state(i, LIVE);
    }
    /// Appends a live slot of generation 0.
    fn push_live(&mut self) -> u32 {
        let i = self.generations.len();
        if i % PER_WORD == 0 {
            self.states.push(0);
        }
        self.generations.push(0);
        self.set_state(i, LIVE);
        i as u32
    }
    /// A slot for a new element: `(index, true)` for a reused vacant slot (next
    /// generation), `(index, false)` for a new slot at the end (the caller pushes its
    /// arrays).
    pub(crate) fn allocate(&mut self) -> (u32, bool) {
        if let Some(i) = self.free.pop() {
            self.reused = true;
            self.set_state(i as usize, LIVE);
            (i, true)
        } else {
            (self.push_live(), false)
        }
    }
    /// Two consecutive slots `(i, i + 1)`, `i` even, for the halfedges of a new edge; the
    /// free list of halfedges holds even indices only (edges are freed whole).
    pub(crate) fn allocate_pair(&mut self) -> (u32, bool) {
        if let Some(i) = self.free.pop() {
            self.reused = true;
            self.set_state(i as usize, LIVE);
            self.set_state(i as usize + 1, LIVE);
            (i, true)
        } else {
            let i = self.push_live();
            self.push_live();
            (i, false)
        }
    }
    /// Frees every tombstone for good (vacant, next generation) and returns their indices.
    pub(crate) fn free_tombstones(&mut self) -> Vec<u32> {
        let mut freed = Vec::new();
        for i in 0..self.generations.len() {
            if self.state(i) == TOMBSTONE {
                self.set_state(i, VACANT);
                self.generations[i] += 1;
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
        (0..self.generations.len() as u32).filter(|&i| self.state(i as usize) == LIVE)
    }
    /// Number of live slots.
    pub(crate) fn live_count(&self) -> usize {
        self.states
            .iter()
            .map(|&w| {
                // Live is 0b01: the low bit set and the high bit clear.
                (w & !(w >> 1) & 0x5555_5555_5555_5555).count_ones() as usize
            })
            .sum()
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
