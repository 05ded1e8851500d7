//! Element handles: versioned `slotmap` keys.
//!
//! A handle is a slot index and a version. A handle stays valid until its element is
//! removed for good (by [`Mesh::garbage_collection`](crate::Mesh::garbage_collection));
//! a slot freed there gets a new version when it is reused, so a stale handle is
//! detected by the validity queries and never silently aliases another element.
//! Every accessor that takes a handle (`position`, `next`, `to_vertex`, `triangle`, the
//! circulators, attribute reads, …) checks it in release builds as in debug ones and
//! panics with "stale … handle" rather than read the element now in its slot; use
//! [`Mesh::is_valid_vertex`](crate::Mesh::is_valid_vertex) (or `ensure_vertex`, …) on a
//! handle you did not just get from the mesh. The check is one compare on a mesh that
//! never collected garbage, a state-bit read after.
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
    KeyData::from_ffi((version << 32) | u64::from(index.wrapping_add(1))).into()
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
/// them. Generations (how often a slot was freed) live apart and are allocated only when
/// garbage collection first frees a slot: a mesh that never collected garbage (every mesh
/// just read or built, and every hierarchy) has none, and neither have its clones.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct Slots {
    states: Vec<u64>,
    /// Number of slots.
    len: usize,
    /// Generation per slot; empty while every generation is 0 (no slot freed yet).
    generations: Vec<u32>,
    /// Vacant slots, reused last-freed first.
    free: Vec<u32>,
}

impl Slots {
    /// Room for `n` slots.
    pub(crate) fn with_capacity(n: usize) -> Self {
        Self {
            states: Vec::with_capacity(n.div_ceil(PER_WORD)),
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
            len: n,
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
        // The same test as `collected` (live slots that were never freed are at
        // generation 0 in both branches): the accessors' checks and the keys the
        // iterators make then share one flag, which the compiler keeps in a register.
        if self.collected() {
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
        (i < self.len && self.generation_of(i) == generation(k)).then(|| self.state(i))
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
    /// True once garbage collection freed a slot: only then can a handle of this mesh
    /// name a vacant slot or an older generation. Before, every slot below the length is
    /// live or a tombstone, so the accessors' checks need only the bounds check their
    /// indexing makes anyway.
    #[inline(always)]
    pub(crate) fn collected(&self) -> bool {
        !self.generations.is_empty()
    }
    /// The handle check of a mesh that collected garbage (see
    /// [`collected`](Self::collected)): panics unless `k` is of its slot's current
    /// generation (a live element or a tombstone of this mesh). The test is inline and only the panic is out of line and never
    /// returns: a call that could return would make a caller's loop (a `for` over a
    /// circulator reading positions) keep its sums in memory across it.
    ///
    /// Only the generation is compared: freeing a slot moves it to the next generation,
    /// so a handle that names a vacant slot is always of an older one.
    #[inline]
    pub(crate) fn check_collected<K: Key + std::fmt::Display>(&self, k: K, kind: &str) {
        if self.generations.get(slot(k)) != Some(&generation(k)) {
            stale_handle(k, kind);
        }
    }
    /// True when `k` names a live element or a tombstone.
    #[inline]
    pub(crate) fn contains<K: Key>(&self, k: K) -> bool {
        matches!(self.state_of(k), Some(LIVE | TOMBSTONE))
    }
    /// True when slot `i` is live.
    #[inline]
    pub(crate) fn is_live_index(&self, i: usize) -> bool {
        i < self.len && self.state(i) == LIVE
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
        let i = self.len;
        if i % PER_WORD == 0 {
            self.states.push(0);
        }
        if !self.generations.is_empty() {
            self.generations.push(0);
        }
        self.len += 1;
        self.set_state(i, LIVE);
        i as u32
    }
    /// A slot for a new element: `(index, true)` for a reused vacant slot (next
    /// generation), `(index, false)` for a new slot at the end (the caller pushes its
    /// arrays).
    pub(crate) fn allocate(&mut self) -> (u32, bool) {
        if let Some(i) = self.free.pop() {
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
        for i in 0..self.len {
            if self.state(i) == TOMBSTONE {
                if self.generations.is_empty() {
                    self.generations = vec![0; self.len];
                }
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
    pub(crate) fn live_indices(&self) -> LiveIndices<'_> {
        LiveIndices::new(&self.states, ALL_SLOTS)
    }
    /// Indices of the live even slots, in order (one halfedge per edge).
    #[inline]
    pub(crate) fn live_even_indices(&self) -> LiveIndices<'_> {
        LiveIndices::new(&self.states, EVEN_SLOTS)
    }
    /// Runs `f(i, &mut out[i])` for every live slot `i`, in parallel, a state word's 32
    /// slots at a time (so a word is tested once, not every slot); entries of other slots
    /// are left alone. `out` may be shorter than the slots (the rest is not visited).
    pub(crate) fn par_for_each_live<T: Send>(
        &self,
        out: &mut [T],
        f: impl Fn(usize, &mut T) + Sync,
    ) {
        use rayon::prelude::*;
        out.par_chunks_mut(PER_WORD)
            .zip(self.states.par_iter())
            .enumerate()
            .for_each(|(k, (chunk, &word))| {
                let base = k * PER_WORD;
                let live = live_bits(word);
                if live == ALL_SLOTS {
                    for (j, x) in chunk.iter_mut().enumerate() {
                        f(base + j, x);
                    }
                } else {
                    for (j, x) in chunk.iter_mut().enumerate() {
                        if live >> (2 * j) & 1 != 0 {
                            f(base + j, x);
                        }
                    }
                }
            });
    }
    /// The table as it is stored: the packed states, the number of slots, the
    /// generations (empty while no slot was freed) and the free list (for the hierarchy
    /// file, `crate::hierarchy::file`).
    pub(crate) fn raw_parts(&self) -> (&[u64], usize, &[u32], &[u32]) {
        (&self.states, self.len, &self.generations, &self.free)
    }
    /// A table from [`raw_parts`](Self::raw_parts) read back from a file, checked: as
    /// many state words as `len` needs, no state bits past `len`, no unknown state,
    /// generations for every slot or none, every free slot vacant, in range, listed once
    /// and (with `pairs`, for halfedges) even with a vacant partner. Says what is wrong
    /// otherwise.
    pub(crate) fn from_raw_parts(
        states: Vec<u64>,
        len: usize,
        generations: Vec<u32>,
        free: Vec<u32>,
        pairs: bool,
    ) -> Result<Self, String> {
        if states.len() != len.div_ceil(PER_WORD) {
            return Err(format!(
                "{} state words for {len} slots (expected {})",
                states.len(),
                len.div_ceil(PER_WORD)
            ));
        }
        if let Some(k) = states.iter().position(|&w| (w & (w >> 1) & ALL_SLOTS) != 0) {
            return Err(format!("state word {k} holds an unknown slot state"));
        }
        if len % PER_WORD != 0 {
            let last = states.last().copied().unwrap_or(0);
            if last >> (2 * (len % PER_WORD)) != 0 {
                return Err(format!("state bits set past the last of {len} slots"));
            }
        }
        if !generations.is_empty() && generations.len() != len {
            return Err(format!("{} generations for {len} slots", generations.len()));
        }
        if generations.is_empty() {
            // No slot was ever freed: every slot is live or a tombstone (what the
            // accessors' checks rely on, see `collected`).
            for (k, &w) in states.iter().enumerate() {
                let in_word = (len - k * PER_WORD).min(PER_WORD);
                let mask = if in_word == PER_WORD {
                    ALL_SLOTS
                } else {
                    ALL_SLOTS & ((1u64 << (2 * in_word)) - 1)
                };
                if (w | (w >> 1)) & mask != mask {
                    return Err(format!(
                        "a slot of state word {k} is vacant, but no slot was ever freed"
                    ));
                }
            }
        }
        let slots = Self {
            states,
            len,
            generations,
            free: Vec::new(),
        };
        let mut listed = vec![false; if free.is_empty() { 0 } else { len }];
        for &i in &free {
            let i = i as usize;
            if i >= len || slots.state(i) != VACANT || listed[i] {
                return Err(format!(
                    "free slot {i} is out of range, not vacant or listed twice"
                ));
            }
            if pairs && (i % 2 != 0 || i + 1 >= len || slots.state(i + 1) != VACANT) {
                return Err(format!(
                    "free halfedge slot {i} does not start a vacant pair"
                ));
            }
            listed[i] = true;
        }
        Ok(Self { free, ..slots })
    }
    /// Number of slots.
    #[inline]
    pub(crate) fn len(&self) -> usize {
        self.len
    }
    /// Number of live slots.
    pub(crate) fn live_count(&self) -> usize {
        self.states
            .iter()
            .map(|&w| live_bits(w).count_ones() as usize)
            .sum()
    }
}

/// The low bit of every slot's two state bits: a word's slots that are live are the set
/// bits of `live_bits(word) & ALL_SLOTS`.
const ALL_SLOTS: u64 = 0x5555_5555_5555_5555;
/// The low state bit of the even slots only.
const EVEN_SLOTS: u64 = 0x1111_1111_1111_1111;

/// Live slots of a state word: bit `2 k` set when slot `k` of the word is live (state
/// `0b01`: low bit set, high bit clear).
#[inline(always)]
fn live_bits(word: u64) -> u64 {
    word & !(word >> 1) & ALL_SLOTS
}

/// Iterator over the live slot indices of a [`Slots`], in order: it reads the packed
/// states a word (32 slots) at a time and picks the live ones with `trailing_zeros`, so a
/// slot costs a few register operations and no bounds check; `fold` (hence `for_each`,
/// `sum`, …) runs a word whose slots are all live as a plain counted loop.
#[derive(Clone, Debug)]
pub(crate) struct LiveIndices<'a> {
    words: std::slice::Iter<'a, u64>,
    /// Slot index of bit 0 of the current word (wraps to 0 on the first word).
    base: u32,
    /// Live slots of the current word not returned yet (bit `2 k` for slot `base + k`).
    mask: u64,
    /// The slots asked for: [`ALL_SLOTS`] or [`EVEN_SLOTS`].
    select: u64,
}

impl<'a> LiveIndices<'a> {
    #[inline]
    fn new(states: &'a [u64], select: u64) -> Self {
        Self {
            words: states.iter(),
            base: 0u32.wrapping_sub(PER_WORD as u32),
            mask: 0,
            select,
        }
    }
}

impl Iterator for LiveIndices<'_> {
    type Item = u32;
    #[inline]
    fn next(&mut self) -> Option<u32> {
        while self.mask == 0 {
            let word = *self.words.next()?;
            self.base = self.base.wrapping_add(PER_WORD as u32);
            self.mask = live_bits(word) & self.select;
        }
        let bit = self.mask.trailing_zeros();
        self.mask &= self.mask - 1;
        Some(self.base + bit / 2)
    }
    #[inline]
    fn size_hint(&self) -> (usize, Option<usize>) {
        let here = self.mask.count_ones() as usize;
        let per_word = (self.select.count_ones() as usize).min(PER_WORD);
        (here, Some(here + self.words.len() * per_word))
    }
    #[inline]
    fn fold<B, F: FnMut(B, u32) -> B>(self, init: B, mut f: F) -> B {
        // One call of `f` in the whole loop: the caller's closure is then inlined into it
        // (with a call per element in several fast paths, a large closure — a
        // circulator with its checks — is compiled out of line and called per element).
        let mut acc = init;
        let mut mask = self.mask;
        let mut base = self.base;
        let mut words = self.words;
        loop {
            while mask != 0 {
                acc = f(acc, base + mask.trailing_zeros() / 2);
                mask &= mask - 1;
            }
            let Some(&word) = words.next() else {
                return acc;
            };
            base = base.wrapping_add(PER_WORD as u32);
            mask = live_bits(word) & self.select;
        }
    }
}

/// Dense slot index of a key: the position of its element in per-element arrays
/// (positions, attributes): the key's index minus one (index 0 is the null key, whose
/// slot is out of every range).
///
/// The subtraction is done in `u32`, undoing [`key`]'s `+ 1` in the same width, so that
/// the compiler folds `slot(key(i, g))` to `i` (one instruction less per step of a
/// circulator that yields handles the caller turns back into indices).
#[inline]
pub(crate) fn slot<K: Key>(key: K) -> usize {
    (key.data().as_ffi() as u32).wrapping_sub(1) as usize
}

/// The panic of [`Slots::check_collected`], out of line and never returning.
#[cold]
#[inline(never)]
fn stale_handle<K: std::fmt::Display>(k: K, kind: &str) -> ! {
    panic!(
        "stale {kind} handle {k}: not an element of this mesh (removed by garbage collection, \
         or from another mesh)"
    );
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

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Slots whose states are runs of `(state, length)` (0 vacant, 1 live, 2 tombstone).
    fn slots_from_runs(runs: &[(u64, usize)]) -> (Slots, Vec<u64>) {
        let states: Vec<u64> = runs
            .iter()
            .flat_map(|&(s, n)| std::iter::repeat_n(s, n))
            .collect();
        let mut slots = Slots::default();
        for (i, &s) in states.iter().enumerate() {
            slots.push_live();
            slots.set_state(i, s);
        }
        (slots, states)
    }

    /// The iterator's items through `next` only, and through `fold` after `k` `next`s.
    fn by_next_and_fold(it: LiveIndices<'_>, k: usize) -> (Vec<u32>, Vec<u32>) {
        let by_next: Vec<u32> = it.clone().by_ref().collect::<Vec<_>>();
        let mut it = it;
        let mut mixed: Vec<u32> = it.by_ref().take(k).collect();
        mixed = it.fold(mixed, |mut v, i| {
            v.push(i);
            v
        });
        (by_next, mixed)
    }

    proptest! {
        /// Live (and live even) indices, by `next`, by `fold` (whole words of live slots
        /// take the counted loop) and by both mixed, are those a slot-by-slot scan finds;
        /// `size_hint` brackets the count; `par_for_each_live` visits exactly them.
        #[test]
        fn live_indices_are_the_live_slots(
            runs in prop::collection::vec((0u64..3, 0usize..80), 0..8),
            k in 0usize..100,
        ) {
            let (slots, states) = slots_from_runs(&runs);
            let live: Vec<u32> = (0..states.len() as u32)
                .filter(|&i| states[i as usize] == LIVE)
                .collect();
            let even: Vec<u32> = live.iter().copied().filter(|i| i % 2 == 0).collect();
            let (by_next, mixed) = by_next_and_fold(slots.live_indices(), k);
            prop_assert_eq!(&by_next, &live);
            prop_assert_eq!(&mixed, &live);
            let (lo, hi) = slots.live_indices().size_hint();
            prop_assert!(lo <= live.len() && live.len() <= hi.unwrap());
            let (by_next, mixed) = by_next_and_fold(slots.live_even_indices(), k);
            prop_assert_eq!(&by_next, &even);
            prop_assert_eq!(&mixed, &even);
            prop_assert_eq!(slots.live_count(), live.len());
            let mut seen = vec![u32::MAX; states.len()];
            slots.par_for_each_live(&mut seen, |i, x| *x = i as u32);
            let visited: Vec<u32> = seen.into_iter().filter(|&i| i != u32::MAX).collect();
            prop_assert_eq!(visited, live);
        }
    }

    /// `slot` undoes `key` for every index, and the null key's slot is beyond every array.
    #[test]
    fn slot_undoes_key() {
        for i in [0, 1, 31, 32, 1 << 20, u32::MAX - 2] {
            for g in [0, 1, 7] {
                assert_eq!(slot(key::<crate::handle::VertexId>(i, g)), i as usize);
                assert_eq!(generation(key::<crate::handle::VertexId>(i, g)), g);
            }
        }
        assert!(slot(crate::handle::VertexId::default()) >= (u32::MAX - 1) as usize);
    }

    /// Generations are allocated only when garbage collection first frees a slot (a
    /// clone of fresh slots has none), then kept in step with new slots; a reused slot
    /// hands out a new key and its old key is stale.
    #[test]
    fn generations_exist_once_a_slot_was_freed() {
        use crate::handle::VertexId;
        let mut s = Slots::live(70);
        assert!(s.generations.is_empty() && s.clone().generations.is_empty());
        let old: VertexId = s.key(5);
        s.bury(5);
        s.bury(40);
        assert!(s.is_tombstone(old) && s.generations.is_empty());
        let freed = s.free_tombstones();
        assert_eq!(freed, [5, 40]);
        assert_eq!(s.generations.len(), 70);
        assert!(!s.contains(old));
        s.push_free(freed.into_iter().rev());
        assert_eq!(s.allocate(), (5, true));
        let new: VertexId = s.key(5);
        assert!(new != old && s.is_live(new) && !s.is_live(old));
        assert_eq!(generation(new), 1);
        assert_eq!(s.allocate(), (40, true));
        assert_eq!(s.allocate(), (70, false));
        assert_eq!(s.generations.len(), 71);
        assert!(s.is_live(s.key::<VertexId>(70)));
        assert_eq!(s.live_count(), 71);
    }
}
