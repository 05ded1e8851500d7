//! Which fine vertices a coarse vertex stands for: ancestors and cluster members.

use glam::DVec3;

use super::Hierarchy;
use crate::error::Result;

impl Hierarchy {
    /// For every vertex slot of the input mesh (indexed by [`Mesh::vertex_index`](crate::Mesh::vertex_index)), the
    /// index of its *ancestor* at `level`: the vertex it is collapsed into there (itself
    /// when it is live at `level`). Refinement with [`DetailMode::LocalFrame`](crate::hierarchy::DetailMode::LocalFrame) moves a
    /// fine vertex only when its ancestor at the edited level moved, so this map tells
    /// which fine vertices an edit's region covers.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`](crate::Error::InvalidArgument) for a level that does not exist.
    pub fn ancestors(&self, level: usize) -> Result<Vec<u32>> {
        let end = self.check_level(level)?;
        Ok(self.ancestors_through(0..end))
    }

    /// For every vertex slot, the vertex it is collapsed into by the records `records`
    /// (itself when none of them removes it): [`ancestors`](Self::ancestors) over a range
    /// of records (out-of-range ends are clamped).
    pub(super) fn ancestors_through(&self, records: std::ops::Range<usize>) -> Vec<u32> {
        let end = records.end.min(self.records.len());
        let mut map: Vec<u32> = (0..self.mesh.vertex_slots() as u32).collect();
        for record in self.records.steps[records.start.min(end)..end].iter().rev() {
            let (i0, i1) = (record.v0 as usize, record.v1 as usize);
            if let (true, Some(&a)) = (i0 < map.len(), map.get(i1)) {
                map[i0] = a;
            }
        }
        map
    }
}

/// # Clusters
impl Hierarchy {
    /// Every vertex the collapses down to the current position took part in, as
    /// `(index, ancestor, input position)`: its vertex index, the index of the vertex
    /// live here it is collapsed into (itself for a survivor still live), and its
    /// position in the input as the hierarchy holds it (what refining without an edit
    /// restores). Together with the live vertices that took part in no collapse (they
    /// are their own cluster, still where the input has them unless edited here), these
    /// are the *clusters* of the vertices live here: what a mark of a live vertex
    /// ([`mark_affine`](Self::mark_affine), [`mark_region`](Self::mark_region)) reaches at
    /// full resolution. Costs one pass over the records made so far.
    pub fn cluster_members(&self) -> Vec<(u32, u32, DVec3)> {
        let steps = &self.records.steps[..self.applied];
        let slots = self.mesh.vertex_slots();
        let mut first: Vec<Option<DVec3>> = vec![None; slots];
        for step in steps {
            for (i, p) in [(step.v0, step.p0), (step.v1, step.p1)] {
                if let Some(slot @ None) = first.get_mut(i as usize) {
                    *slot = Some(p);
                }
            }
        }
        let mut ancestor: Vec<u32> = (0..slots as u32).collect();
        for step in steps.iter().rev() {
            let (i0, i1) = (step.v0 as usize, step.v1 as usize);
            if let (true, Some(&a)) = (i0 < ancestor.len(), ancestor.get(i1)) {
                ancestor[i0] = a;
            }
        }
        first
            .iter()
            .enumerate()
            .filter_map(|(i, p)| p.map(|p| (i as u32, ancestor[i], p)))
            .collect()
    }
}
