//! The priority queue of the QEM decimation: packed `u64` keys
//! `(cost as f32 bits) << 32 | edge`.
//!
//! Costs are non-negative, so their `f32` bit patterns order like the costs, and ties go to
//! the smaller edge index (deterministic). Staleness is tracked by the caller (see
//! [`super::qem`]).
//!
//! The queue is a *radix heap* (Ahuja, Mehlhorn, Orlin & Tarjan 1990, "Faster Algorithms
//! for the Shortest Path Problem"): key `k` waits in bucket `b` = the position of the
//! highest bit in which `k` differs from the last key taken out, so a bucket holds keys
//! sharing all bits above `b` with it. Taking out scans the lowest non-empty bucket once
//! for its minimum and spreads its keys over lower buckets; every key moves down at most
//! 64 times, in sequential passes over short vectors. A binary heap of millions of
//! entries instead pays a cache miss per level on every pop, which was most of the QEM
//! decimation's queue time. Radix heaps need keys that never go below the last one taken
//! out; the decimation's keys mostly grow (a stale edge's cost only rises), and the few
//! that do not (an edge that comes back after being parked) wait in a small binary heap
//! of *overdue* keys, which is served first. So the queue pops exactly the order of an
//! ordinary binary heap.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// A min-priority queue of `u64` keys (a radix heap with a heap of overdue keys; see
/// the [module docs](self)).
#[derive(Clone, Debug, Default)]
pub(crate) struct MinHeap {
    /// The last key moved to `overdue` by a refill (0 at first): every key in the buckets
    /// is above it.
    last: u64,
    /// Keys not above `last`, served first, smallest first.
    overdue: BinaryHeap<Reverse<u64>>,
    /// `buckets[b - 1]` holds the keys whose highest bit differing from `last` is bit
    /// `b - 1` (`b` in `1..=64`).
    buckets: Vec<Vec<u64>>,
    /// Bit `b - 1` set when `buckets[b - 1]` is not empty.
    occupied: u64,
}

/// Packs a non-negative cost and an edge index into a heap key.
#[inline]
pub(crate) fn pack(cost: f64, edge: u32) -> u64 {
    (u64::from(cost_bits(cost)) << 32) | u64::from(edge)
}

/// The `f32` bit pattern of a cost clamped to `[0, f32::MAX]` (NaN counts as the largest).
#[inline]
pub(crate) fn cost_bits(cost: f64) -> u32 {
    let c = if cost.is_nan() {
        f32::MAX
    } else {
        (cost.max(0.0) as f32).min(f32::MAX)
    };
    c.to_bits()
}

/// `(cost bits, edge)` of a key.
#[inline]
pub(crate) fn unpack(key: u64) -> (u32, u32) {
    ((key >> 32) as u32, key as u32)
}

impl MinHeap {
    /// A queue holding `keys`.
    pub(crate) fn from_vec(keys: Vec<u64>) -> Self {
        let mut heap = Self {
            buckets: vec![Vec::new(); 64],
            ..Self::default()
        };
        // Buckets sized exactly (no regrowth, no copies), then filled.
        let mut counts = [0usize; 64];
        for &k in &keys {
            if k > 0 {
                counts[63 - k.leading_zeros() as usize] += 1;
            }
        }
        for (bucket, &n) in heap.buckets.iter_mut().zip(&counts) {
            bucket.reserve_exact(n);
        }
        for k in keys {
            heap.push(k);
        }
        heap
    }

    /// Adds a key.
    #[inline]
    pub(crate) fn push(&mut self, key: u64) {
        if key <= self.last {
            self.overdue.push(Reverse(key));
        } else {
            let b = 63 - (key ^ self.last).leading_zeros() as usize;
            self.buckets[b].push(key);
            self.occupied |= 1 << b;
        }
    }

    /// Makes sure the smallest key is in `overdue` unless the queue is empty.
    #[inline]
    fn refill(&mut self) {
        if !self.overdue.is_empty() || self.occupied == 0 {
            return;
        }
        let b = self.occupied.trailing_zeros() as usize;
        self.occupied &= !(1 << b);
        let mut keys = std::mem::take(&mut self.buckets[b]);
        let min = keys.iter().copied().min().unwrap_or(u64::MAX);
        self.last = min;
        for &k in &keys {
            if k == min {
                self.overdue.push(Reverse(k));
            } else {
                // Below bit `b` now: a lower bucket.
                let c = 63 - (k ^ min).leading_zeros() as usize;
                self.buckets[c].push(k);
                self.occupied |= 1 << c;
            }
        }
        // Keep the emptied vector's memory for the keys that will fall into bucket `b`.
        keys.clear();
        self.buckets[b] = keys;
    }

    /// The smallest key (the tests compare it; [`Queue::peek`] is what the decimation
    /// uses).
    #[cfg(test)]
    fn peek(&mut self) -> Option<u64> {
        self.refill();
        self.overdue.peek().map(|k| k.0)
    }

    /// Removes and returns the smallest key.
    #[inline]
    pub(crate) fn pop(&mut self) -> Option<u64> {
        self.refill();
        self.overdue.pop().map(|k| k.0)
    }
}

/// A [`MinHeap`] with its next few keys taken out in order, so that the caller knows
/// which edges come next and can prefetch what they will touch (see
/// [`crate::prefetch`]). Every key in `ahead` is at most every key in the heap; a key
/// pushed below the last of `ahead` is inserted there in order (and `ahead`'s largest
/// goes back into the heap), so pops come in exactly the heap's order.
#[derive(Clone, Debug)]
pub(crate) struct Queue {
    heap: MinHeap,
    /// The smallest keys, ascending, at most `depth` of them.
    ahead: std::collections::VecDeque<u64>,
    depth: usize,
}

impl Queue {
    /// A queue holding `keys` that keeps its next `depth` keys (at least 1) in order.
    pub(crate) fn new(keys: Vec<u64>, depth: usize) -> Self {
        let depth = depth.max(1);
        Self {
            heap: MinHeap::from_vec(keys),
            ahead: std::collections::VecDeque::with_capacity(depth + 1),
            depth,
        }
    }

    /// Takes keys out of the heap until `ahead` holds `depth` (or the heap is empty),
    /// dropping those that `keep` refuses.
    #[inline]
    fn fill(&mut self, keep: &impl Fn(u64) -> bool) {
        while self.ahead.len() < self.depth {
            match self.heap.pop() {
                Some(k) if keep(k) => self.ahead.push_back(k),
                Some(_) => {}
                None => break,
            }
        }
    }

    /// Adds a key.
    #[inline]
    pub(crate) fn push(&mut self, key: u64) {
        match self.ahead.back() {
            Some(&last) if key < last => {
                let at = self.ahead.partition_point(|&k| k < key);
                self.ahead.insert(at, key);
                if self.ahead.len() > self.depth {
                    if let Some(k) = self.ahead.pop_back() {
                        self.heap.push(k);
                    }
                }
            }
            _ => self.heap.push(key),
        }
    }

    /// The smallest key that `keep` accepts. Keys it refuses on their way out of the
    /// heap are dropped for good: `keep` must refuse a key forever once it has (the
    /// decimation drops the keys of dead edges, which never come back).
    #[inline]
    pub(crate) fn peek(&mut self, keep: impl Fn(u64) -> bool) -> Option<u64> {
        self.fill(&keep);
        self.ahead.front().copied()
    }

    /// Removes and returns the smallest key that `keep` accepts (see [`peek`](Self::peek)).
    #[inline]
    pub(crate) fn pop(&mut self, keep: impl Fn(u64) -> bool) -> Option<u64> {
        self.fill(&keep);
        let key = self.ahead.pop_front();
        self.fill(&keep);
        key
    }

    /// The key that [`pop`](Self::pop) will return after `i` more pops, unless keys are
    /// pushed or refused meanwhile (`i < depth`).
    #[inline]
    pub(crate) fn upcoming(&self, i: usize) -> Option<u64> {
        self.ahead.get(i).copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pops_in_order() {
        let costs = [3.5, 0.0, 1e-30, 7.0, 1e-30, 2.0, f64::NAN, 1e30, 0.5];
        let keys: Vec<u64> = costs
            .iter()
            .enumerate()
            .map(|(i, &c)| pack(c, i as u32))
            .collect();
        let mut heap = MinHeap::from_vec(keys[..4].to_vec());
        for &k in &keys[4..] {
            heap.push(k);
        }
        let mut out = Vec::new();
        while let Some(k) = heap.pop() {
            out.push(unpack(k).1);
        }
        assert_eq!(out, vec![1, 2, 4, 8, 5, 0, 3, 7, 6]);
    }

    proptest::proptest! {
        /// Any sequence of pushes (below, at and above the last key taken out: overdue
        /// keys included) and pops gives what a binary heap gives, `peek` included.
        #[test]
        fn pops_what_a_binary_heap_pops(
            initial in proptest::collection::vec(0u64..1 << 40, 0..200),
            ops in proptest::collection::vec((0u8..3, 0u64..1 << 40, 0u32..64), 0..400),
        ) {
            let mut heap = MinHeap::from_vec(initial.clone());
            let mut reference: BinaryHeap<Reverse<u64>> = initial.into_iter().map(Reverse).collect();
            for (op, key, shift) in ops {
                match op {
                    0 => {
                        proptest::prop_assert_eq!(heap.pop(), reference.pop().map(|k| k.0));
                    }
                    1 => {
                        // Near the current minimum: often below the last key taken out.
                        let near = reference.peek().map_or(key, |k| k.0 ^ (key >> shift));
                        heap.push(near);
                        reference.push(Reverse(near));
                    }
                    _ => {
                        heap.push(key);
                        reference.push(Reverse(key));
                    }
                }
                proptest::prop_assert_eq!(heap.peek(), reference.peek().map(|k| k.0));
            }
            while let Some(k) = reference.pop() {
                proptest::prop_assert_eq!(heap.pop(), Some(k.0));
            }
            proptest::prop_assert_eq!(heap.pop(), None);
        }
    }

    proptest::proptest! {
        /// The queue pops what a binary heap pops whatever is pushed meanwhile, and its
        /// upcoming keys are the heap's next ones.
        #[test]
        fn queue_pops_what_a_binary_heap_pops(
            initial in proptest::collection::vec(0u64..1 << 20, 0..100),
            ops in proptest::collection::vec((0u8..2, 0u64..1 << 20), 0..300),
            depth in 1usize..10,
        ) {
            let mut queue = Queue::new(initial.clone(), depth);
            let all = |_: u64| true;
            let mut reference: BinaryHeap<Reverse<u64>> = initial.into_iter().map(Reverse).collect();
            for (op, key) in ops {
                if op == 0 {
                    proptest::prop_assert_eq!(queue.pop(all), reference.pop().map(|k| k.0));
                    let mut next = reference.clone();
                    for i in 0..depth {
                        proptest::prop_assert_eq!(queue.upcoming(i), next.pop().map(|k| k.0));
                    }
                } else {
                    queue.push(key);
                    reference.push(Reverse(key));
                }
                proptest::prop_assert_eq!(queue.peek(all), reference.peek().map(|k| k.0));
            }
            while let Some(k) = reference.pop() {
                proptest::prop_assert_eq!(queue.pop(all), Some(k.0));
            }
            proptest::prop_assert_eq!(queue.pop(all), None);
        }
    }

    proptest::proptest! {
        /// Keys refused by `keep` (here: multiples of 3) are never returned, the others
        /// come in order.
        #[test]
        fn queue_drops_refused_keys(
            keys in proptest::collection::vec(0u64..1 << 20, 0..200),
            depth in 1usize..10,
        ) {
            let keep = |k: u64| k % 3 != 0;
            let mut queue = Queue::new(keys.clone(), depth);
            let mut expected: Vec<u64> = keys.into_iter().filter(|&k| keep(k)).collect();
            expected.sort_unstable();
            let mut out = Vec::new();
            while let Some(k) = queue.pop(keep) {
                out.push(k);
            }
            proptest::prop_assert_eq!(out, expected);
        }
    }
}
