//! What the user tells a hierarchy about an edit at a coarse level: affine maps, fields
//! and regions, kept per vertex for refinement.

use glam::{DAffine3, DVec3};

use super::detail::DetailMode;
use super::motion::{Field, Motion};
use super::Hierarchy;
use crate::error::{Error, Result};
use crate::handle::VertexId;

/// No affine mark on a vertex.
pub(super) const UNMARKED: u32 = u32::MAX;
/// The mark of a vertex in an edit's region without an affine map of its own
/// ([`Hierarchy::mark_region`]).
pub(super) const IN_REGION: u32 = u32::MAX - 1;

/// Motions (affine maps or fields) that moved vertices since the hierarchy placed them
/// ([`Hierarchy::mark_affine`], [`Hierarchy::mark_field`]) and region marks: a motion
/// index (or [`IN_REGION`]) per vertex slot, allocated on first use, and the motions.
#[derive(Clone, Debug, Default)]
pub(super) struct Marks {
    pub(super) of_vertex: Vec<u32>,
    pub(super) maps: Vec<Motion>,
    /// Maps kept after the last [`Marks::compact`] (the next one runs when there are
    /// twice as many and 64 more).
    compacted: usize,
}

impl Marks {
    #[inline]
    pub(super) fn is_empty(&self) -> bool {
        self.of_vertex.is_empty()
    }
    #[inline]
    pub(super) fn of(&self, i: usize) -> u32 {
        self.of_vertex.get(i).copied().unwrap_or(UNMARKED)
    }
    #[inline]
    pub(super) fn set(&mut self, i: usize, mark: u32) {
        if let Some(m) = self.of_vertex.get_mut(i) {
            *m = mark;
        }
    }
    pub(super) fn clear(&mut self) {
        if !self.is_empty() {
            *self = Self::default();
        }
    }
    /// The maps kept after the last compaction (for the hierarchy file).
    pub(super) fn compacted(&self) -> usize {
        self.compacted
    }
    /// Marks read back from a file, checked: every vertex's mark is none, the region, or
    /// one of `maps`. Says what is wrong otherwise.
    pub(super) fn from_raw_parts(
        of_vertex: Vec<u32>,
        maps: Vec<Motion>,
        compacted: usize,
    ) -> Result<Self, String> {
        if let Some(i) = of_vertex
            .iter()
            .position(|&m| m < IN_REGION && m as usize >= maps.len())
        {
            return Err(format!(
                "vertex slot {i} is marked with map {} of {}",
                of_vertex[i],
                maps.len()
            ));
        }
        Ok(Self {
            of_vertex,
            maps,
            compacted,
        })
    }
    /// Drops the maps no vertex uses any more (an interactive drag replaces its handle's
    /// map at every step), renumbering the others; amortised over the marks made.
    pub(super) fn compact(&mut self) {
        let mut renumbered = vec![UNMARKED; self.maps.len()];
        let mut kept = Vec::new();
        for m in &mut self.of_vertex {
            if *m < IN_REGION {
                let k = *m as usize;
                if renumbered[k] == UNMARKED {
                    renumbered[k] = kept.len() as u32;
                    kept.push(self.maps[k].clone());
                }
                *m = renumbered[k];
            }
        }
        self.maps = kept;
        self.compacted = self.maps.len();
    }
}

/// # Edits at a coarse level
impl Hierarchy {
    /// How splits place their vertices after an edit (see [`DetailMode`]).
    pub fn detail_mode(&self) -> DetailMode {
        self.details.mode()
    }

    /// Tells the hierarchy that `vertices` (live at the current position) were just moved
    /// by the affine map `transform` (for example a rigidly moved handle, or a rotated
    /// sub-mesh): refinement then puts every finer vertex collapsed into one of them at
    /// `transform` of its recorded position, exactly, instead of carrying it by its local
    /// frame. So a part moved rigidly at a coarse level is, at full resolution, the rigid
    /// image of its original fine vertices.
    ///
    /// Marks compose: a vertex marked with `A`, then with `B`, has moved by `B ∘ A`. A
    /// marked vertex that is not (within rounding) at its map's image of where the
    /// hierarchy left it when it is split (it was moved otherwise since) falls back to its
    /// local frame. Walking coarser drops all marks (the records collapsed again hold the
    /// moved positions). Marks need [`DetailMode::LocalFrame`].
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] in [`DetailMode::Translation`], for a map that is not
    /// finite, or for a vertex that is not live; nothing is marked then.
    pub fn mark_affine(&mut self, vertices: &[VertexId], transform: DAffine3) -> Result<()> {
        if !transform.is_finite() {
            return Err(Error::InvalidArgument(format!(
                "the affine map of mark_affine is not finite: {transform:?}"
            )));
        }
        self.mark(vertices, Motion::Affine(transform), true)
    }

    /// [`mark_affine`](Self::mark_affine), replacing the marks the vertices had instead
    /// of composing with them: for an edit that is applied again and again from the same
    /// starting positions (a handle dragged interactively), whose latest map is the whole
    /// motion since the hierarchy placed the vertices.
    ///
    /// # Errors
    /// As [`mark_affine`](Self::mark_affine).
    pub fn set_affine_mark(&mut self, vertices: &[VertexId], transform: DAffine3) -> Result<()> {
        if !transform.is_finite() {
            return Err(Error::InvalidArgument(format!(
                "the affine map of set_affine_mark is not finite: {transform:?}"
            )));
        }
        self.mark(vertices, Motion::Affine(transform), false)
    }

    /// [`mark_affine`](Self::mark_affine) for an edit that is a map of space but not an
    /// affine one (a deformation defined at every point, such as a Barr twist or taper
    /// whose strength ramps along its axis): `vertices` (live at the current position)
    /// were just moved by `field`, and refinement puts every finer vertex collapsed into
    /// one of them at `field` of its recorded position. The coarse edit then comes back
    /// at full resolution exactly as the same deformation of the input would have made
    /// it, over those vertices' clusters. A marked vertex that is not (within rounding)
    /// at `field` of where the hierarchy left it falls back to its local frame, as for
    /// affine marks; a field that gives a non-finite position makes the split that
    /// meets it fail with [`Error::Overflow`] (nothing changed by that split). Marks
    /// compose and are dropped when the hierarchy walks coarser.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] in [`DetailMode::Translation`] or for a vertex that is
    /// not live; nothing is marked then.
    pub fn mark_field(
        &mut self,
        vertices: &[VertexId],
        field: impl Fn(DVec3) -> DVec3 + Send + Sync + 'static,
    ) -> Result<()> {
        self.mark(vertices, Motion::Field(std::sync::Arc::new(field)), true)
    }

    /// [`mark_field`](Self::mark_field) with a field already shared.
    ///
    /// # Errors
    /// As [`mark_field`](Self::mark_field).
    pub fn mark_shared_field(&mut self, vertices: &[VertexId], field: Field) -> Result<()> {
        self.mark(vertices, Motion::Field(field), true)
    }

    /// [`mark_shared_field`](Self::mark_shared_field), replacing the marks the vertices
    /// had instead of composing with them (as [`set_affine_mark`](Self::set_affine_mark)).
    ///
    /// # Errors
    /// As [`mark_field`](Self::mark_field).
    pub fn set_field_mark(&mut self, vertices: &[VertexId], field: Field) -> Result<()> {
        self.mark(vertices, Motion::Field(field), false)
    }

    pub(super) fn mark(
        &mut self,
        vertices: &[VertexId],
        motion: Motion,
        compose: bool,
    ) -> Result<()> {
        if self.details.mode() != DetailMode::LocalFrame {
            return Err(Error::InvalidArgument(
                "affine and field marks need DetailMode::LocalFrame (the paper's translations \
                 ignore them)"
                    .into(),
            ));
        }
        if let Some(&v) = vertices.iter().find(|&&v| !self.mesh.is_valid_vertex(v)) {
            return Err(Error::InvalidArgument(format!(
                "mark_affine: vertex {v} is not a live vertex of the hierarchy's mesh"
            )));
        }
        let slots = self.mesh.vertex_slots();
        if self.marks.of_vertex.len() < slots {
            self.marks.of_vertex.resize(slots, UNMARKED);
        }
        // One new map per map the vertices had before (or none).
        let mut composed: Vec<(u32, u32)> = Vec::new();
        for &v in vertices {
            let i = self.mesh.vertex_index(v);
            let old = match self.marks.of_vertex[i] {
                o if compose && o < IN_REGION => o,
                _ => UNMARKED,
            };
            let new = match composed.iter().find(|&&(o, _)| o == old) {
                Some(&(_, n)) => n,
                None => {
                    let map = match old {
                        UNMARKED => motion.clone(),
                        o => self.marks.maps[o as usize].then(&motion),
                    };
                    let n = self.marks.maps.len() as u32;
                    self.marks.maps.push(map);
                    composed.push((old, n));
                    n
                }
            };
            self.marks.of_vertex[i] = new;
        }
        if self.marks.maps.len() > 2 * self.marks.compacted + 64 {
            self.marks.compact();
        }
        Ok(())
    }

    /// Tells the hierarchy that `vertices` (live at the current position) are the region
    /// of an edit made at this level: refinement places the finer vertices collapsed into
    /// them by the motion of their neighbourhood even where they did not move themselves,
    /// so the edit's transition from moved to still comes back at full resolution as
    /// smooth as the edit made it (the piecewise-linear interpolation of the coarse motion
    /// over the descendants, see [`DetailMode::LocalFrame`]), instead of a step on the
    /// last fine edge before an unmoved coarse vertex. Vertices outside every region
    /// keep the default rule: a fine vertex whose ancestor did not move stays exactly
    /// where it was, so mark only what the edit may move (a sub-mesh's inside, a Lee
    /// editing area's interior, a Bendels–Klein handle and deformable region, an FFD
    /// footprint). Affinely marked vertices ([`mark_affine`](Self::mark_affine)) are in
    /// the region already; marking a vertex here keeps its affine map.
    ///
    /// Walking coarser drops the marks, as for [`mark_affine`](Self::mark_affine).
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] in [`DetailMode::Translation`] or for a vertex that is
    /// not live; nothing is marked then.
    pub fn mark_region(&mut self, vertices: &[VertexId]) -> Result<()> {
        if self.details.mode() != DetailMode::LocalFrame {
            return Err(Error::InvalidArgument(
                "region marks need DetailMode::LocalFrame (the paper's translations ignore them)"
                    .into(),
            ));
        }
        if let Some(&v) = vertices.iter().find(|&&v| !self.mesh.is_valid_vertex(v)) {
            return Err(Error::InvalidArgument(format!(
                "mark_region: vertex {v} is not a live vertex of the hierarchy's mesh"
            )));
        }
        let slots = self.mesh.vertex_slots();
        if self.marks.of_vertex.len() < slots {
            self.marks.of_vertex.resize(slots, UNMARKED);
        }
        for &v in vertices {
            let m = &mut self.marks.of_vertex[self.mesh.vertex_index(v)];
            if *m == UNMARKED {
                *m = IN_REGION;
            }
        }
        Ok(())
    }

    /// Removes every affine and region mark ([`mark_affine`](Self::mark_affine),
    /// [`mark_region`](Self::mark_region)).
    pub fn clear_marks(&mut self) {
        self.marks.clear();
    }
}
