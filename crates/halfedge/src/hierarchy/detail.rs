//! Centroid detail coefficients (the seed paper "Interactive Editing of Multiresolution
//! Meshes", section 3, Fig. 1; DESIGN.md §2).
//!
//! Before `v0 → v1` collapses, each endpoint `v ∈ {v0, v1}` gets the centroid `C_i` of its
//! one-ring *without the other endpoint* (the vertices of the star of faces around `v`).
//! When the record is split again, `C_f` is the centroid of the same neighbours at their
//! current positions, and both `v0` and `v1` take their recorded pre-collapse position
//! plus `C_f − C_i`, each with its own centroids. The translation carries any edit made at
//! a coarser level to the re-inserted vertices.
//!
//! Reach of an edit: a re-inserted vertex near the border of an edited part has moved and
//! unmoved neighbours and takes a blend of their motion; as a split's neighbours may be
//! vertices re-inserted just before in the same round, the blend spreads over a few
//! coarse edge lengths, decaying by about a factor 10 per coarse edge (see the tests in
//! `tests/hierarchy.rs`). Well inside an edited part the fine mesh moves with it; well
//! outside nothing moves.
//!
//! Exactness: `C_i` and `C_f` are computed by the same function over the same neighbour
//! list in the same order, so with no edit they agree bit for bit; a zero translation is
//! then not even added (adding `+0.0` would turn a `-0.0` coordinate into `+0.0`), and
//! refinement restores the input positions exactly.
//!
//! Storage is flat: one `Vec<u32>` of neighbour vertex indices for all records, with two
//! lists per record (`v0`'s, then `v1`'s) delimited by one offset array, and the two
//! recorded centroids per record.

use glam::DVec3;

/// The detail coefficients of every record of a hierarchy, indexed by record number.
#[derive(Clone, Debug, Default)]
pub(crate) struct Details {
    /// Neighbour vertex indices of all records, `v0`'s list then `v1`'s list per record.
    neighbours: Vec<u32>,
    /// `offsets[2 r]..offsets[2 r + 1]` is `v0`'s list of record `r`,
    /// `offsets[2 r + 1]..offsets[2 r + 2]` is `v1`'s; starts with 0.
    offsets: Vec<u32>,
    /// `[C_i(v0), C_i(v1)]` per record.
    centroids: Vec<[DVec3; 2]>,
}

/// Centroid of the positions of the listed vertices, summed in list order (the order is
/// what makes `C_f == C_i` bit for bit when nothing moved). Zero for an empty list.
#[inline]
pub(crate) fn centroid(positions: &[DVec3], list: &[u32]) -> DVec3 {
    if list.is_empty() {
        return DVec3::ZERO;
    }
    let mut sum = DVec3::ZERO;
    for &i in list {
        sum += positions[i as usize];
    }
    sum / list.len() as f64
}

/// `p + d`, except that components where `d` is zero are left untouched (bit for bit,
/// signed zeros included).
#[inline]
pub(crate) fn translate_exact(p: DVec3, d: DVec3) -> DVec3 {
    DVec3::new(
        if d.x != 0.0 { p.x + d.x } else { p.x },
        if d.y != 0.0 { p.y + d.y } else { p.y },
        if d.z != 0.0 { p.z + d.z } else { p.z },
    )
}

impl Details {
    /// Room for about `records` records.
    pub(crate) fn with_capacity(records: usize) -> Self {
        let mut offsets = Vec::with_capacity(2 * records + 1);
        offsets.push(0);
        Self {
            neighbours: Vec::with_capacity(12 * records),
            offsets,
            centroids: Vec::with_capacity(records),
        }
    }

    /// Appends the record of the next collapse: the neighbours of `v0` (without `v1`) and
    /// of `v1` (without `v0`) given as vertex indices by the two iterators, and computes
    /// their centroids from `positions`.
    pub(crate) fn push(
        &mut self,
        positions: &[DVec3],
        v0_neighbours: impl Iterator<Item = u32>,
        v1_neighbours: impl Iterator<Item = u32>,
    ) {
        let start0 = self.neighbours.len();
        self.neighbours.extend(v0_neighbours);
        let start1 = self.neighbours.len();
        self.neighbours.extend(v1_neighbours);
        let end = self.neighbours.len();
        self.offsets.push(start1 as u32);
        self.offsets.push(end as u32);
        let c0 = centroid(positions, &self.neighbours[start0..start1]);
        let c1 = centroid(positions, &self.neighbours[start1..end]);
        self.centroids.push([c0, c1]);
    }

    /// The neighbour lists of record `r`: `(v0's, v1's)`.
    #[inline]
    pub(crate) fn lists(&self, r: usize) -> (&[u32], &[u32]) {
        let a = self.offsets[2 * r] as usize;
        let b = self.offsets[2 * r + 1] as usize;
        let c = self.offsets[2 * r + 2] as usize;
        (&self.neighbours[a..b], &self.neighbours[b..c])
    }

    /// True when every neighbour of record `r` is an index into `positions` of length
    /// `len`: always so on the hierarchy's own mesh, checked before using a mesh the
    /// hierarchy cannot vouch for.
    pub(crate) fn in_bounds(&self, r: usize, len: usize) -> bool {
        self.all_neighbours(r).iter().all(|&i| (i as usize) < len)
    }

    /// Both neighbour lists of record `r`, one after the other.
    #[inline]
    fn all_neighbours(&self, r: usize) -> &[u32] {
        &self.neighbours[self.offsets[2 * r] as usize..self.offsets[2 * r + 2] as usize]
    }

    /// Recomputes `C_i` of record `r` from the current positions (when the record is
    /// collapsed again after an edit at a finer level).
    pub(crate) fn refresh(&mut self, r: usize, positions: &[DVec3]) {
        let (l0, l1) = self.lists(r);
        let c = [centroid(positions, l0), centroid(positions, l1)];
        self.centroids[r] = c;
    }

    /// The translations `C_f − C_i` of `v0` and `v1` for splitting record `r` now.
    #[inline]
    pub(crate) fn translations(&self, r: usize, positions: &[DVec3]) -> [DVec3; 2] {
        let (l0, l1) = self.lists(r);
        let [c0, c1] = self.centroids[r];
        [centroid(positions, l0) - c0, centroid(positions, l1) - c1]
    }

    /// Prefetches the current positions of record `r`'s neighbours, which
    /// [`translations`](Self::translations) will read (see [`crate::prefetch`]).
    #[inline]
    pub(crate) fn prefetch(&self, r: usize, positions: &[DVec3]) {
        for &i in self.all_neighbours(r) {
            crate::prefetch::prefetch(positions, i as usize);
        }
    }

    /// Bytes used (for reports).
    pub(crate) fn heap_bytes(&self) -> usize {
        self.neighbours.capacity() * 4
            + self.offsets.capacity() * 4
            + self.centroids.capacity() * std::mem::size_of::<[DVec3; 2]>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_translation_keeps_signed_zero() {
        let p = DVec3::new(-0.0, 1.0, -2.5);
        let q = translate_exact(p, DVec3::ZERO);
        assert_eq!(
            q.to_array().map(f64::to_bits),
            p.to_array().map(f64::to_bits)
        );
        let q = translate_exact(p, DVec3::new(0.0, 1.0, 0.0));
        assert_eq!(q.y, 2.0);
        assert_eq!(q.x.to_bits(), (-0.0f64).to_bits());
    }

    #[test]
    fn centroid_is_order_deterministic() {
        let positions = vec![
            DVec3::new(0.1, 0.2, 0.3),
            DVec3::new(1e16, -3.0, 0.7),
            DVec3::new(-1e16, 5.0, 0.1),
        ];
        let mut d = Details::with_capacity(1);
        d.push(&positions, [0u32, 1, 2].into_iter(), [2u32].into_iter());
        assert_eq!(d.translations(0, &positions), [DVec3::ZERO; 2]);
        let (a, b) = d.lists(0);
        assert_eq!((a, b), (&[0u32, 1, 2][..], &[2u32][..]));
    }
}
