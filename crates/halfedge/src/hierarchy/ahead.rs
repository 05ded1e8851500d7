//! How far ahead the walks prefetch what a split or a collapse will touch (see
//! [`crate::prefetch`]): distances tuned on large meshes, shared by the walks, the
//! placer and the re-planning.

use crate::collapse::Step;
use crate::mesh::Mesh;

/// How many splits ahead [`Hierarchy::split_next`] prefetches the memory of the record it
/// will split (see [`crate::prefetch`]): first the collapsed edge, the positions and the
/// vertex halfedges the record names, then the halfedges and faces the collapsed edge's
/// tombstones name, then the links the removed edges' tombstones name.
pub(super) const SPLIT_PREFETCH_DISTANCE: usize = 16;
pub(super) const SIDES_PREFETCH_DISTANCE: usize = 11;
pub(super) const LINKS_PREFETCH_DISTANCE: usize = 6;
/// How many splits ahead [`Hierarchy::split_next`] prefetches the positions a record's
/// detail coefficients read.
pub(super) const DETAIL_PREFETCH_DISTANCE: usize = 5;
/// As [`SPLIT_PREFETCH_DISTANCE`] and [`SIDES_PREFETCH_DISTANCE`], for
/// [`Hierarchy::collapse_next`].
pub(super) const COLLAPSE_PREFETCH_DISTANCE: usize = 16;
pub(super) const COLLAPSE_SIDES_PREFETCH_DISTANCE: usize = 11;
pub(super) const COLLAPSE_LINKS_PREFETCH_DISTANCE: usize = 7;
/// How many splits ahead [`Hierarchy::split_next`] prefetches the record's neighbour list
/// and coefficients (which the prefetch of the neighbours' positions reads, later).
pub(super) const LIST_PREFETCH_DISTANCE: usize = 20;
/// How many splits ahead [`Hierarchy::split_next`] prefetches the first, second and third
/// halfedge of the walk around `v1` of the record it will split.
pub(super) const MOVED_PREFETCH_DISTANCES: [usize; 3] = [6, 4, 2];
/// Prefetches the connectivity the splits a few records below `r` will touch (see
/// [`SPLIT_PREFETCH_DISTANCE`]): their edges, vertices and positions, then the halfedges
/// and faces their tombstones name, then the links, and the walk around `v1`, which is a
/// chain of loads, one more link of it per stage.
#[inline]
pub(super) fn prefetch_splits_after(mesh: &Mesh, steps: &[Step], r: usize) {
    if let Some(ahead) = r.checked_sub(SPLIT_PREFETCH_DISTANCE) {
        mesh.prefetch_step(&steps[ahead], false);
    }
    if let Some(ahead) = r.checked_sub(SIDES_PREFETCH_DISTANCE) {
        mesh.prefetch_sides(&steps[ahead]);
    }
    if let Some(ahead) = r.checked_sub(LINKS_PREFETCH_DISTANCE) {
        mesh.prefetch_links(&steps[ahead], false);
    }
    for (step, distance) in MOVED_PREFETCH_DISTANCES.into_iter().enumerate() {
        if let Some(ahead) = r.checked_sub(distance) {
            mesh.prefetch_moved(&steps[ahead], step as u32);
        }
    }
}

/// Refinements after an edit of at least this many splits place on one thread and split
/// on another ([`Hierarchy::split_beside`]); shorter ones are not worth the hand-off.
pub(super) const SPLIT_BESIDE_MIN: usize = 4096;
/// How many collapses ahead [`Hierarchy::collapse_next`] prefetches the first, second, …
/// halfedge of the walk around `v0` (the whole ring: one more than the split's walk and
/// the removed edges).
pub(super) const RING_PREFETCH_DISTANCES: [usize; 6] = [7, 6, 5, 4, 3, 2];
