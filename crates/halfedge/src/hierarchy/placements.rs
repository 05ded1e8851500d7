//! Where each record's collapse put its survivor, and its parameter along the edge.
//!
//! The seed paper's rounds put the survivor at one of two places the record's own
//! endpoints give, bit for bit: `v1`'s position (on a boundary) or the edge's midpoint
//! `0.5 (p0 + p1)`. Those records keep one byte saying which (the placement is computed
//! again from the record when needed, in the same floating-point operations); any other
//! placement (QEM's optimal positions, a placement moved by a collapse made again after an
//! edit) keeps its position and parameter, 32 bytes, in a second array indexed by record
//! that is allocated as far as such records go.

use glam::DVec3;

use crate::collapse::Step;

/// The survivor stayed at `v1` (`t = 0`).
const AT_V1: u8 = 0;
/// The survivor went to the edge's midpoint `0.5 (p0 + p1)` (`t = 0.5`).
const MIDPOINT: u8 = 1;
/// The placement is kept in [`Placements::stored`].
const STORED: u8 = 2;

/// The placements of a hierarchy's records (see the module docs).
#[derive(Clone, Debug, Default)]
pub(crate) struct Placements {
    rules: Vec<u8>,
    stored: Vec<(DVec3, f64)>,
}

impl Placements {
    /// The rule that makes `p` from `step`'s endpoints with parameter `t`, if any.
    #[inline]
    fn rule_of(step: &Step, p: DVec3, t: f64) -> u8 {
        if t == 0.0 && p.to_array().map(f64::to_bits) == step.p1.to_array().map(f64::to_bits) {
            AT_V1
        } else if t == 0.5
            && p.to_array().map(f64::to_bits)
                == (0.5 * (step.p0 + step.p1)).to_array().map(f64::to_bits)
        {
            MIDPOINT
        } else {
            STORED
        }
    }

    /// Appends the placement of the record `step` just made: the survivor went to `p`,
    /// parameter `t` along the edge from `v1` to `v0`.
    #[inline]
    pub(crate) fn push(&mut self, step: &Step, p: DVec3, t: f64) {
        let rule = Self::rule_of(step, p, t);
        let r = self.rules.len();
        self.rules.push(rule);
        if rule == STORED {
            self.store(r, p, t);
        }
    }

    /// Appends a copy of record `r` of `from` (same endpoints).
    #[inline]
    pub(crate) fn push_copy(&mut self, from: &Placements, r: usize) {
        let rule = from.rules[r];
        let at = self.rules.len();
        self.rules.push(rule);
        if rule == STORED {
            let (p, t) = from.stored[r];
            self.store(at, p, t);
        }
    }

    /// Keeps `(p, t)` for record `r` in the stored array, which grows to reach it.
    fn store(&mut self, r: usize, p: DVec3, t: f64) {
        if self.stored.len() <= r {
            self.stored.resize(r + 1, (DVec3::ZERO, 0.0));
        }
        self.stored[r] = (p, t);
    }

    /// Where record `r` (whose compact record is `step`) put its survivor.
    #[inline]
    pub(crate) fn placed(&self, r: usize, step: &Step) -> DVec3 {
        match self.rules[r] {
            AT_V1 => step.p1,
            MIDPOINT => 0.5 * (step.p0 + step.p1),
            _ => self.stored[r].0,
        }
    }

    /// Where collapsing record `r` (whose compact record is `step`) again puts the
    /// survivor when its endpoints are now at `p0` and `p1`: its build-time position when
    /// they have not moved; else the same place relative to them (the rule's place, or
    /// the same parameter along the edge plus the same offset from it).
    #[inline]
    pub(crate) fn again(&self, r: usize, step: &Step, p0: DVec3, p1: DVec3) -> DVec3 {
        match self.rules[r] {
            AT_V1 => p1,
            MIDPOINT => 0.5 * (p0 + p1),
            _ => {
                let (placed, t) = self.stored[r];
                if p0 == step.p0 && p1 == step.p1 {
                    placed
                } else {
                    let residual = placed - (step.p1 + t * (step.p0 - step.p1));
                    p1 + t * (p0 - p1) + residual
                }
            }
        }
    }

    /// The parameter of record `r`'s placement along its edge, from `v1` to `v0`.
    #[inline]
    pub(crate) fn parameter(&self, r: usize) -> f64 {
        match self.rules[r] {
            AT_V1 => 0.0,
            MIDPOINT => 0.5,
            _ => self.stored[r].1,
        }
    }

    /// Record `r` was collapsed again and its survivor put at `p` (by
    /// [`again`](Self::again)): a stored placement keeps the new position.
    #[inline]
    pub(crate) fn set_placed(&mut self, r: usize, p: DVec3) {
        if self.rules[r] == STORED {
            self.stored[r].0 = p;
        }
    }

    /// Prefetches what [`placed`](Self::placed) reads for record `r`.
    #[inline]
    pub(crate) fn prefetch(&self, r: usize) {
        crate::prefetch::prefetch(&self.rules, r);
        crate::prefetch::prefetch(&self.stored, r);
    }

    /// The rules and the stored placements as they are kept (for the hierarchy file).
    pub(crate) fn raw_parts(&self) -> (&[u8], &[(DVec3, f64)]) {
        (&self.rules, &self.stored)
    }

    /// Placements from [`raw_parts`](Self::raw_parts) read back from a file for
    /// `records` records, checked: one known rule per record, and a stored placement for
    /// every record whose rule says so. Says what is wrong otherwise.
    pub(crate) fn from_raw_parts(
        rules: Vec<u8>,
        stored: Vec<(DVec3, f64)>,
        records: usize,
    ) -> Result<Self, String> {
        if rules.len() != records {
            return Err(format!("{} rules for {records} records", rules.len()));
        }
        if stored.len() > records {
            return Err(format!(
                "{} stored placements for {records} records",
                stored.len()
            ));
        }
        if let Some(r) = rules.iter().position(|&rule| rule > STORED) {
            return Err(format!("record {r} has the unknown rule {}", rules[r]));
        }
        if let Some(r) = rules.iter().rposition(|&rule| rule == STORED) {
            if r >= stored.len() {
                return Err(format!(
                    "record {r} has a stored placement, but only {} are stored",
                    stored.len()
                ));
            }
        }
        Ok(Self { rules, stored })
    }

    /// Empties the placements, keeping their memory, with room for `n` rules and, when
    /// `stored`, `n` stored placements.
    pub(crate) fn recycle(&mut self, n: usize, stored: bool) {
        self.rules.clear();
        self.rules.reserve(n);
        self.stored.clear();
        if stored {
            self.stored.reserve(n);
        }
    }

    /// Gives back unused capacity.
    pub(crate) fn shrink_to_fit(&mut self) {
        self.rules.shrink_to_fit();
        self.stored.shrink_to_fit();
    }

    /// Heap bytes.
    pub(crate) fn heap_bytes(&self) -> usize {
        self.rules.capacity() + self.stored.capacity() * std::mem::size_of::<(DVec3, f64)>()
    }

    /// Capacities of the two arrays (rules, stored).
    pub(crate) fn capacities(&self) -> (usize, usize) {
        (self.rules.capacity(), self.stored.capacity())
    }

    /// Moves the placements into `rules` and `stored` (see [`super::build::Prefaulted`]).
    pub(crate) fn adopt(&mut self, rules: Vec<u8>, stored: Vec<(DVec3, f64)>) {
        super::buffers::adopt(&mut self.rules, rules);
        super::buffers::adopt(&mut self.stored, stored);
    }

    /// The placements of the records in `range`, to [`restore`](Self::restore) them.
    pub(crate) fn save(&self, range: std::ops::Range<usize>) -> (Vec<u8>, Vec<(DVec3, f64)>) {
        let stored = self
            .stored
            .get(range.start.min(self.stored.len())..range.end.min(self.stored.len()))
            .map(<[_]>::to_vec)
            .unwrap_or_default();
        (self.rules[range].to_vec(), stored)
    }

    /// Puts back what [`save`](Self::save) saved for `range`.
    pub(crate) fn restore(
        &mut self,
        range: std::ops::Range<usize>,
        (rules, stored): (Vec<u8>, Vec<(DVec3, f64)>),
    ) {
        self.rules[range.clone()].copy_from_slice(&rules);
        let start = range.start.min(self.stored.len());
        self.stored[start..start + stored.len()].copy_from_slice(&stored);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generators;

    /// Real records of a few collapses of an icosphere, with their endpoints.
    fn steps() -> Vec<Step> {
        let mut mesh = generators::icosphere(2);
        let mut out = Vec::new();
        for _ in 0..3 {
            let h = mesh
                .halfedges()
                .find(|&h| mesh.is_collapse_ok(h).is_ok())
                .unwrap();
            let (step, _) = mesh.collapse_unchecked(h);
            out.push(step);
        }
        out
    }

    #[test]
    fn rules_give_the_placements_back_bit_for_bit_and_others_are_stored() {
        let s = steps();
        let bits = |p: DVec3| p.to_array().map(f64::to_bits);
        let mid = 0.5 * (s[1].p0 + s[1].p1);
        let odd = s[2].p1 + 0.3 * (s[2].p0 - s[2].p1) + DVec3::splat(1e-3);
        let mut placements = Placements::default();
        placements.push(&s[0], s[0].p1, 0.0);
        placements.push(&s[1], mid, 0.5);
        placements.push(&s[2], odd, 0.3);
        // Two rules and one stored placement: rounds records cost one byte.
        assert_eq!(placements.rules, [AT_V1, MIDPOINT, STORED]);
        assert_eq!(placements.stored.len(), 3);
        assert_eq!(bits(placements.placed(0, &s[0])), bits(s[0].p1));
        assert_eq!(bits(placements.placed(1, &s[1])), bits(mid));
        assert_eq!(bits(placements.placed(2, &s[2])), bits(odd));
        assert_eq!([0, 1, 2].map(|r| placements.parameter(r)), [0.0, 0.5, 0.3]);
        // Collapsed again from the same endpoints: the same place; from moved ones, the
        // rule's place or the same offset along the edge.
        for (r, step) in s.iter().enumerate() {
            let again = placements.again(r, step, step.p0, step.p1);
            assert_eq!(bits(again), bits(placements.placed(r, step)));
        }
        let shift = DVec3::new(0.1, -0.2, 0.3);
        let moved = |r: usize| placements.again(r, &s[r], s[r].p0 + shift, s[r].p1 + shift);
        assert_eq!(bits(moved(0)), bits(s[0].p1 + shift));
        assert_eq!(
            bits(moved(1)),
            bits(0.5 * (s[1].p0 + shift + s[1].p1 + shift))
        );
        assert!((moved(2) - (odd + shift)).length() < 1e-12);
        // A stored placement takes a new position; a rule's does not need to.
        let saved = placements.save(0..3);
        placements.set_placed(2, DVec3::ONE);
        assert_eq!(placements.placed(2, &s[2]), DVec3::ONE);
        placements.restore(0..3, saved);
        assert_eq!(bits(placements.placed(2, &s[2])), bits(odd));
        // Copies keep the rule, or the stored placement.
        let mut copy = Placements::default();
        for r in 0..3 {
            copy.push_copy(&placements, r);
        }
        assert_eq!(copy.rules, placements.rules);
        assert_eq!(bits(copy.placed(2, &s[2])), bits(odd));
    }
}
