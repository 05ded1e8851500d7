//! The priority queue of the QEM decimation: a min-heap of packed `u64` keys
//! `(cost as f32 bits) << 32 | edge`.
//!
//! Costs are non-negative, so their `f32` bit patterns order like the costs, and ties go to
//! the smaller edge index (deterministic). Staleness is tracked by the caller (see
//! [`super::qem`]).
//!
//! The heap is 4-ary rather than binary: four 8-byte children share a cache line, so a
//! pop touches half as many lines of a heap of millions of entries.

/// A 4-ary min-heap of `u64` keys.
#[derive(Clone, Debug, Default)]
pub(crate) struct MinHeap {
    keys: Vec<u64>,
}

const ARITY: usize = 4;

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
    /// A heap made of `keys` in linear time.
    pub(crate) fn from_vec(keys: Vec<u64>) -> Self {
        let mut heap = Self { keys };
        let n = heap.keys.len();
        if n > 1 {
            for i in (0..=(n - 2) / ARITY).rev() {
                heap.sift_down(i);
            }
        }
        heap
    }

    /// Adds a key.
    #[inline]
    pub(crate) fn push(&mut self, key: u64) {
        self.keys.push(key);
        let mut i = self.keys.len() - 1;
        while i > 0 {
            let parent = (i - 1) / ARITY;
            if self.keys[parent] <= key {
                break;
            }
            self.keys[i] = self.keys[parent];
            i = parent;
        }
        self.keys[i] = key;
    }

    /// The smallest key.
    #[inline]
    pub(crate) fn peek(&self) -> Option<u64> {
        self.keys.first().copied()
    }

    /// Removes and returns the smallest key.
    #[inline]
    pub(crate) fn pop(&mut self) -> Option<u64> {
        let last = self.keys.pop()?;
        if self.keys.is_empty() {
            return Some(last);
        }
        let top = std::mem::replace(&mut self.keys[0], last);
        self.sift_down(0);
        Some(top)
    }

    #[inline]
    fn sift_down(&mut self, mut i: usize) {
        let n = self.keys.len();
        let key = self.keys[i];
        loop {
            let first = ARITY * i + 1;
            if first >= n {
                break;
            }
            let end = (first + ARITY).min(n);
            let mut best = first;
            let mut best_key = self.keys[first];
            for c in first + 1..end {
                let k = self.keys[c];
                if k < best_key {
                    best = c;
                    best_key = k;
                }
            }
            if best_key >= key {
                break;
            }
            self.keys[i] = best_key;
            i = best;
        }
        self.keys[i] = key;
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
}
