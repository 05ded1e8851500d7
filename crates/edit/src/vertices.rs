//! Vertex selections and position snapshots shared by the deformers of *Interactive
//! editing of multiresolution meshes* §4 ([`crate::submesh`], [`crate::barr`],
//! [`crate::smoothing`], [`crate::ffd`]).
//!
//! A deformer works on the whole mesh or on a set of vertices, given either as a mask
//! indexed by [`Mesh::vertex_index`] or as a list of handles. [`Snapshot`] keeps the
//! positions of a vertex set so that any edit can be undone bit for bit.

use glam::DVec3;
use halfedge::{Mesh, VertexData, VertexId};
use rayon::prelude::*;

use crate::{EditError, Result};

/// The vertices a deformer acts on.
#[derive(Clone, Copy, Debug, Default)]
pub enum Vertices<'a> {
    /// Every live vertex of the mesh.
    #[default]
    All,
    /// The live vertices whose entry is `true`: per-vertex data of the mesh acted on
    /// (a [`halfedge::Selection::mask`], or [`VertexData::new`] over a `Vec<bool>`);
    /// data made for another mesh is refused with [`EditError::Stale`].
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
    pub(crate) fn resolve(&self, mesh: &Mesh) -> Result<Resolved> {
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
                mask.check(mesh)?;
                if mask.len() != slots {
                    return Err(EditError::VertexArrayLength {
                        expected: slots,
                        found: mask.len(),
                    });
                }
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
                    if !mesh.is_valid_vertex(v) {
                        return Err(EditError::InvalidVertex(v));
                    }
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
    pub fn take(mesh: &Mesh, vertices: Vertices<'_>) -> Result<Self> {
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
    /// [`EditError::Stale`], changing nothing, for another mesh than the one the snapshot
    /// was taken on, or that mesh at another hierarchy level or with other connectivity.
    pub fn restore(&self, mesh: &mut Mesh) -> Result<()> {
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

/// Checks that `d` is finite and not zero, and returns it normalised.
pub(crate) fn unit_direction(name: &'static str, d: DVec3) -> Result<DVec3> {
    // Scaled by its largest component first: (1e300, 1e300, 0) is a fine direction.
    let largest = d.abs().max_element();
    if !d.is_finite() || largest == 0.0 {
        return Err(EditError::DegenerateDirection { name, value: d });
    }
    let d = d / largest;
    Ok(d / d.length())
}

/// `Err(EditError::Overflow)` naming the first of the new positions (of the vertices
/// with the given indices) that is not finite: checked before an edit writes them, so
/// that no NaN or infinity ever reaches the mesh through an `Ok`.
pub(crate) fn check_finite_positions(what: &str, indices: &[u32], new: &[DVec3]) -> Result<()> {
    match new.par_iter().position_first(|p| !p.is_finite()) {
        None => Ok(()),
        Some(k) => Err(EditError::Overflow(format!(
            "{what} would move vertex v{} to {} (the parameters are too large for the \
             coordinates, or the vertex or a neighbour already had a non-finite position)",
            indices.get(k).map_or(k, |&i| i as usize),
            new[k]
        ))),
    }
}

/// Checks that a scalar parameter is finite.
pub(crate) fn finite(name: &'static str, x: f64) -> Result<f64> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(EditError::InvalidParameter {
            name,
            reason: format!("{x} is not finite"),
        })
    }
}

/// Checks that a point is finite.
pub(crate) fn finite_point(name: &'static str, p: DVec3) -> Result<DVec3> {
    if p.is_finite() {
        Ok(p)
    } else {
        Err(EditError::InvalidParameter {
            name,
            reason: format!("{p} is not finite"),
        })
    }
}
