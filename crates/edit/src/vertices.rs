//! Vertex selections and position snapshots shared by the deformers of *Interactive
//! editing of multiresolution meshes* §4 (sub-mesh edits, Barr's deformations, Taubin
//! smoothing, FFD: [`crate::deform`]), and the finiteness check every family makes
//! before it writes positions.
//!
//! A deformer works on the whole mesh or on a set of vertices, given either as a mask
//! indexed by [`Mesh::vertex_index`] or as a list of handles. [`Snapshot`] keeps the
//! positions of a vertex set so that any edit can be undone bit for bit.

use glam::DVec3;
use halfedge::{Mesh, VertexData, VertexId};
use rayon::prelude::*;

use halfedge::{Error, Stale};

/// The vertices a deformer acts on.
///
/// Paper: *Interactive editing of multiresolution meshes* §4 (the deformers act on a vertex
/// set).
#[derive(Clone, Copy, Debug, Default)]
pub enum Vertices<'a> {
    /// Every live vertex of the mesh.
    #[default]
    All,
    /// The live vertices whose entry is `true`: per-vertex data of the mesh acted on
    /// (a [`halfedge::selection::Selection::mask`], or [`VertexData::new`] over a `Vec<bool>`);
    /// data made for another mesh is refused as stale ([`halfedge::Stale`]).
    Mask(&'a VertexData<bool>),
    /// The listed vertices (duplicates are ignored).
    List(&'a [VertexId]),
}

/// A validated selection: the sorted slot indices of the selected live vertices, or all
/// slots when every slot is a live vertex and everything is selected.
#[derive(Clone, Debug)]
pub(crate) enum Resolved {
    /// Every slot `0..slots` is a live, selected vertex.
    Dense(usize),
    /// Sorted, distinct slot indices of selected live vertices.
    Sparse(Vec<u32>),
}

impl Resolved {
    /// Number of selected vertices.
    pub(crate) fn len(&self) -> usize {
        match self {
            Resolved::Dense(n) => *n,
            Resolved::Sparse(v) => v.len(),
        }
    }
    /// The selected slot indices as a list.
    pub(crate) fn to_indices(&self) -> Vec<u32> {
        match self {
            Resolved::Dense(n) => (0..*n as u32).collect(),
            Resolved::Sparse(v) => v.clone(),
        }
    }
}

/// True when every vertex slot of `mesh` holds a live vertex (no tombstones or free
/// slots), so per-slot arrays need no liveness test.
pub(crate) fn all_slots_live(mesh: &Mesh) -> bool {
    mesh.n_vertices() == mesh.vertex_slots()
}

/// A per-slot liveness mask.
pub(crate) fn live_mask(mesh: &Mesh) -> Vec<bool> {
    let mut live = vec![false; mesh.vertex_slots()];
    for v in mesh.vertices() {
        live[mesh.vertex_index(v)] = true;
    }
    live
}

impl Vertices<'_> {
    /// Checks the selection against `mesh` and returns it as slot indices.
    ///
    /// # Errors
    /// [`Error::Stale`] for a mask of another mesh (or of this one before a change of
    /// connectivity), [`Error::InvalidHandle`] for a listed vertex that is not live.
    pub(crate) fn resolve(&self, mesh: &Mesh) -> Result<Resolved, Error> {
        let slots = mesh.vertex_slots();
        match *self {
            Vertices::All => {
                if all_slots_live(mesh) {
                    Ok(Resolved::Dense(slots))
                } else {
                    Ok(Resolved::Sparse(
                        mesh.vertices()
                            .map(|v| mesh.vertex_index(v) as u32)
                            .collect(),
                    ))
                }
            }
            Vertices::Mask(mask) => {
                // A mask that fits the mesh has one entry per vertex slot.
                mask.check(mesh)?;
                if all_slots_live(mesh) && mask.iter().all(|&b| b) {
                    return Ok(Resolved::Dense(slots));
                }
                let live = live_mask(mesh);
                Ok(Resolved::Sparse(
                    (0..slots)
                        .filter(|&i| mask[i] && live[i])
                        .map(|i| i as u32)
                        .collect(),
                ))
            }
            Vertices::List(list) => {
                let mut indices = Vec::with_capacity(list.len());
                for &v in list {
                    mesh.ensure_vertex(v)?;
                    indices.push(mesh.vertex_index(v) as u32);
                }
                indices.sort_unstable();
                indices.dedup();
                Ok(Resolved::Sparse(indices))
            }
        }
    }
}

/// The positions of a set of vertices, kept to undo an edit exactly (*Interactive
/// editing of multiresolution meshes* §4.3: "a geometric transformation can be undone";
/// restoring stored positions is exact where an inverse transform is exact only to
/// rounding).
#[derive(Clone, Debug, Default)]
pub struct Snapshot {
    /// The mesh the positions were taken from (`None` for the empty default snapshot,
    /// which restores nothing on any mesh).
    binding: Option<halfedge::Binding>,
    indices: Vec<u32>,
    positions: Vec<DVec3>,
}

impl Snapshot {
    /// Records the current positions of `vertices`.
    ///
    /// # Errors
    /// As the vertex set is checked: [`Error::Stale`] for a mask of another mesh,
    /// [`Error::InvalidHandle`] for a listed vertex that is not live.
    pub fn take(mesh: &Mesh, vertices: Vertices<'_>) -> Result<Self, Error> {
        let resolved = vertices.resolve(mesh)?;
        Ok(Self::of_indices(mesh, resolved.to_indices()))
    }

    /// Records the positions of the given slot indices (sorted, distinct, live).
    pub(crate) fn of_indices(mesh: &Mesh, indices: Vec<u32>) -> Self {
        let all = mesh.positions();
        let positions = indices.par_iter().map(|&i| all[i as usize]).collect();
        Self {
            binding: Some(mesh.binding()),
            indices,
            positions,
        }
    }

    /// Number of vertices recorded.
    pub fn len(&self) -> usize {
        self.indices.len()
    }

    /// True when no vertex is recorded.
    pub fn is_empty(&self) -> bool {
        self.indices.is_empty()
    }

    /// The recorded vertices' [`vertex_index`](Mesh::vertex_index)es, ascending.
    pub fn indices(&self) -> &[u32] {
        &self.indices
    }

    /// The recorded positions, in the order of [`indices`](Self::indices).
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// Puts the recorded positions back, bit for bit.
    ///
    /// # Errors
    /// [`Stale`], changing nothing, for another mesh than the one the snapshot was taken
    /// on, or that mesh at another hierarchy level or with other connectivity.
    pub fn restore(&self, mesh: &mut Mesh) -> Result<(), Stale> {
        if let Some(binding) = &self.binding {
            binding.check(mesh, "the snapshot")?;
        }
        let positions = mesh.positions_mut();
        for (&i, &p) in self.indices.iter().zip(&self.positions) {
            positions[i as usize] = p;
        }
        Ok(())
    }
}

/// Writes `new[k]` to slot `indices[k]` of `positions`, in parallel when the write set
/// is large (through a per-slot inverse map, so that every slot is written by one task).
pub(crate) fn scatter(positions: &mut [DVec3], indices: &[u32], new: &[DVec3]) {
    debug_assert_eq!(indices.len(), new.len());
    if indices.len() * 8 < positions.len() || indices.len() < 50_000 {
        for (&i, &p) in indices.iter().zip(new) {
            positions[i as usize] = p;
        }
        return;
    }
    let mut row = vec![u32::MAX; positions.len()];
    for (k, &i) in indices.iter().enumerate() {
        row[i as usize] = k as u32;
    }
    positions
        .par_iter_mut()
        .zip(row.par_iter())
        .for_each(|(p, &k)| {
            if k != u32::MAX {
                *p = new[k as usize];
            }
        });
}

/// The first of the new positions `new` (of the vertices with the given slot indices, or
/// of slots `0..` when `indices` is empty) that is not finite, as `(slot, position)`: the
/// check an edit makes before it writes, so that no NaN or infinity ever reaches the mesh
/// through an `Ok`.
pub(crate) fn first_non_finite(indices: &[u32], new: &[DVec3]) -> Option<(usize, DVec3)> {
    new.par_iter()
        .position_first(|p| !p.is_finite())
        .map(|k| (indices.get(k).map_or(k, |&i| i as usize), new[k]))
}
