//! The sub-mesh: its vertices, frontier, inward levels and outward collars
//! (*Interactive editing of multiresolution meshes* §4).

use std::collections::VecDeque;

use glam::DVec3;
use halfedge::{Attribute, AttributeValue, Mesh, VertexData, VertexId};

use crate::deform::error::{DeformError, Result};
use crate::deform::submesh::axis::Axis;
use crate::deform::submesh::plane::Plane;

/// Marks a vertex not reached by a ring search.
const UNREACHED: u32 = u32::MAX;

/// Sub-mesh edits of *Interactive editing of multiresolution meshes* §4: a sub-mesh is
/// a set of vertices delimited by its frontier; edits (pull, scale, rotate, Barr taper
/// and twist) act on it and fade over `n` *propagation levels*, collars of faces beyond
/// the frontier.
///
/// # Sub-meshes, frontier, levels
///
/// A [`SubMesh`] is the set of vertices *inside* it. Its **frontier** is the inside
/// vertices that have an outside neighbour (the paper's frontier vertices, shared by the
/// sub-mesh and its host). Two families of rings are counted from the frontier, by
/// breadth-first search over the one-rings (two vertices of a triangle mesh are
/// neighbours exactly when they share a face, so ring `k` is face-ring distance `k`):
///
/// - **collars** outward: collar `k ≥ 1` is the outside vertices first reached at ring
///   distance `k` from the sub-mesh; `n` propagation levels are collars `1..=n`;
/// - **levels** inward: level `ℓ` is the inside vertices at ring distance `ℓ` from the
///   frontier (the frontier is level 0). The paper's "vertex levels" of the taper and
///   twist.
///
/// The kernel's sub-mesh labels plug in through [`SubMesh::from_labels`]; everything else
/// goes through [`SubMesh::from_mask`].
///
/// # Edits and propagation
///
/// Every [`SubmeshEdit`](crate::deform::SubmeshEdit) is a one-parameter family of maps `T_τ`, `T_0` the identity and `T_1`
/// the full edit: pull by `τ·d`; scale by `s^τ`; rotate by `τ·θ`; taper by `s^τ`
/// perpendicular to an axis; twist by `τ·θ` about it. A vertex gets its strength `τ`:
/// 1 inside the sub-mesh (or the taper/twist [`Variation`](crate::deform::Variation)), `w_k` on collar `k ≤ n`
/// ([`Propagation`](crate::deform::Propagation), decreasing from 1 to 0 across the collars), 0 beyond. So `n = 0`
/// moves nothing outside the sub-mesh and nothing beyond collar `n` ever moves. Scale
/// factors are interpolated geometrically (`s^τ`) so that the edit with `1/s` undoes the
/// one with `s` at every strength; [`SubmeshEdit::inverse`](crate::deform::SubmeshEdit::inverse) gives that inverse, and every
/// [`SubMesh::apply`](crate::deform::SubMesh::apply) returns a [`Snapshot`](crate::vertices::Snapshot) that restores
/// the moved vertices bit for bit.
///
/// Scaling without propagation re-seats the scaled sub-mesh on the plane fitted to its
/// frontier (the paper's Fig. 9 b); rotation can be bounded by that plane so that no
/// vertex crosses it (Fig. 11).
///
/// A sub-mesh: the vertices inside it, its frontier and the inward levels (see
/// above). It holds topology only, so it stays valid while positions
/// change; rebuild it when the connectivity changes.
#[derive(Clone, Debug)]
pub struct SubMesh {
    pub(super) binding: halfedge::Binding,
    pub(super) inside: Vec<bool>,
    pub(super) vertices: Vec<u32>,
    pub(super) frontier: Vec<u32>,
    pub(super) level: Vec<u32>,
    pub(super) max_level: u32,
}

/// The one-ring neighbours of slot `i` as slots.
fn neighbours(mesh: &Mesh, i: usize) -> impl Iterator<Item = usize> + '_ {
    mesh.vertex_at(i)
        .into_iter()
        .flat_map(move |v| mesh.adjacent_vertices(v))
        .map(move |w| mesh.vertex_index(w))
}

impl SubMesh {
    /// The sub-mesh of the live vertices whose `inside` entry is true (per-vertex data
    /// of `mesh`: a [`halfedge::selection::Selection::mask`], or [`VertexData::new`] over a
    /// `Vec<bool>`). This is the one place where a sub-mesh is built; the other
    /// constructors convert to a mask.
    ///
    /// # Errors
    /// [`DeformError::Stale`] when `inside` was made for another mesh (or this one before
    /// a change of connectivity); [`DeformError::EmptySubMesh`] when no live vertex is
    /// inside.
    pub fn from_mask(mesh: &Mesh, inside: &VertexData<bool>) -> Result<Self> {
        inside.check(mesh)?;
        Self::from_slots(mesh, inside)
    }

    /// [`from_mask`](Self::from_mask) on a mask that fits `mesh` (one entry per vertex
    /// slot).
    fn from_slots(mesh: &Mesh, inside: &[bool]) -> Result<Self> {
        let slots = mesh.vertex_slots();
        debug_assert_eq!(inside.len(), slots);
        let mut mask = vec![false; slots];
        let mut vertices = Vec::new();
        for v in mesh.vertices() {
            let i = mesh.vertex_index(v);
            if inside[i] {
                mask[i] = true;
                vertices.push(i as u32);
            }
        }
        vertices.sort_unstable();
        if vertices.is_empty() {
            return Err(DeformError::EmptySubMesh);
        }
        let frontier: Vec<u32> = vertices
            .iter()
            .copied()
            .filter(|&i| neighbours(mesh, i as usize).any(|j| !mask[j]))
            .collect();
        // inward levels: breadth-first from the frontier through inside vertices
        let mut level = vec![UNREACHED; slots];
        let mut queue: VecDeque<u32> = VecDeque::with_capacity(vertices.len());
        for &f in &frontier {
            level[f as usize] = 0;
            queue.push_back(f);
        }
        let mut max_level = 0;
        while let Some(i) = queue.pop_front() {
            let next = level[i as usize] + 1;
            for j in neighbours(mesh, i as usize) {
                if mask[j] && level[j] == UNREACHED {
                    level[j] = next;
                    max_level = max_level.max(next);
                    queue.push_back(j as u32);
                }
            }
        }
        Ok(Self {
            binding: mesh.binding(),
            inside: mask,
            vertices,
            frontier,
            level,
            max_level,
        })
    }

    /// The sub-mesh of the given vertices.
    pub fn from_vertices(mesh: &Mesh, vertices: &[VertexId]) -> Result<Self> {
        let mut mask = vec![false; mesh.vertex_slots()];
        for &v in vertices {
            mesh.ensure_vertex(v)?;
            mask[mesh.vertex_index(v)] = true;
        }
        Self::from_slots(mesh, &mask)
    }

    /// The sub-mesh of the vertices whose label satisfies `is_inside`: the conversion
    /// from the kernel's sub-mesh labels (the vertex attribute of `Mesh::label_sides`).
    ///
    /// # Errors
    /// [`DeformError::Stale`] when `labels` is not an attribute of `mesh` (another mesh's,
    /// or a removed one); [`DeformError::EmptySubMesh`] when no live vertex is inside.
    pub fn from_labels<L: AttributeValue>(
        mesh: &Mesh,
        labels: Attribute<VertexId, L>,
        is_inside: impl Fn(&L) -> bool,
    ) -> Result<Self> {
        let mask: Vec<bool> = mesh
            .attribute_values(labels)?
            .iter()
            .map(is_inside)
            .collect();
        Self::from_slots(mesh, &mask)
    }

    /// Number of vertices inside.
    pub fn len(&self) -> usize {
        self.vertices.len()
    }

    /// Always false: a sub-mesh has at least one vertex.
    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty()
    }

    /// The per-slot inside mask.
    pub fn mask(&self) -> &[bool] {
        &self.inside
    }

    /// True when the vertex with index `index` is inside.
    pub fn contains_index(&self, index: usize) -> bool {
        self.inside.get(index).copied().unwrap_or(false)
    }

    /// The inside vertices' indices, ascending.
    pub fn vertex_indices(&self) -> &[u32] {
        &self.vertices
    }

    /// The frontier vertices' indices (inside vertices with an outside neighbour),
    /// ascending.
    pub fn frontier_indices(&self) -> &[u32] {
        &self.frontier
    }

    /// The inward level of an inside vertex (ring distance from the frontier; 0 on the
    /// frontier), `None` outside or when no frontier vertex can be reached from it.
    pub fn level(&self, index: usize) -> Option<u32> {
        match self.level.get(index) {
            Some(&l) if l != UNREACHED => Some(l),
            _ => None,
        }
    }

    /// The largest inward level (the paper's "maximum" number of levels).
    pub fn max_level(&self) -> u32 {
        self.max_level
    }

    /// The outward collars `1..=n`: `result[k − 1]` holds the outside vertices first
    /// reached at ring distance `k` from the sub-mesh (ascending indices). Stops early
    /// when nothing more can be reached.
    pub fn collars(&self, mesh: &Mesh, n: usize) -> Result<Vec<Vec<u32>>> {
        self.check_mesh(mesh)?;
        let mut seen = self.inside.clone();
        let mut collars: Vec<Vec<u32>> = Vec::new();
        let mut front: Vec<u32> = self.frontier.clone();
        for _ in 0..n {
            let mut next = Vec::new();
            for &i in &front {
                for j in neighbours(mesh, i as usize) {
                    if !seen[j] {
                        seen[j] = true;
                        next.push(j as u32);
                    }
                }
            }
            if next.is_empty() {
                break;
            }
            next.sort_unstable();
            front = next.clone();
            collars.push(next);
        }
        Ok(collars)
    }

    /// The plane fitted to the frontier (least squares), its normal turned towards the
    /// inside of the sub-mesh.
    pub fn frontier_plane(&self, mesh: &Mesh) -> Result<Plane> {
        self.check_mesh(mesh)?;
        if self.frontier.is_empty() {
            return Err(DeformError::NoFrontier);
        }
        let positions = mesh.positions();
        let points: Vec<DVec3> = self
            .frontier
            .iter()
            .map(|&i| positions[i as usize])
            .collect();
        let mut plane = Plane::fit(&points).ok_or(DeformError::DegenerateFrontier {
            vertices: points.len(),
        })?;
        // orient towards the inside: the centroid of the non-frontier inside vertices,
        // or (for a flat sub-mesh) the mean vertex normal of the inside vertices
        let interior: Vec<DVec3> = self
            .vertices
            .iter()
            .filter(|&&i| self.level[i as usize] != 0)
            .map(|&i| positions[i as usize])
            .collect();
        let mut side = 0.0;
        if !interior.is_empty() {
            let centroid = interior.iter().sum::<DVec3>() / interior.len() as f64;
            side = plane.signed_distance(centroid);
        }
        let scale = points
            .iter()
            .map(|p| p.distance(plane.point))
            .fold(0.0, f64::max);
        if side.abs() <= 1e-9 * scale {
            let normal_sum: DVec3 = self
                .vertices
                .iter()
                .filter_map(|&i| mesh.vertex_at(i as usize))
                .map(|v| mesh.vertex_normal(v))
                .sum();
            side = normal_sum.dot(plane.normal);
        }
        if side < 0.0 {
            plane.normal = -plane.normal;
        }
        Ok(plane)
    }

    /// The sub-mesh's own axis: through the centroid of the frontier along the frontier
    /// plane's normal, into the sub-mesh (the default axis of taper and twist).
    pub fn axis(&self, mesh: &Mesh) -> Result<Axis> {
        let plane = self.frontier_plane(mesh)?;
        Axis::new(plane.point, plane.normal)
    }

    /// The range `(min, max)` of the axial coordinates `(p − axis.point)·axis.direction`
    /// of the inside vertices.
    pub fn axial_extent(&self, mesh: &Mesh, axis: &Axis) -> Result<(f64, f64)> {
        self.check_mesh(mesh)?;
        let positions = mesh.positions();
        Ok(self
            .vertices
            .iter()
            .map(|&i| axis.coordinate(positions[i as usize]))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
                (lo.min(s), hi.max(s))
            }))
    }

    /// Fails unless `mesh` is the mesh the sub-mesh was built on, at the same hierarchy
    /// level and with the same connectivity (see [`halfedge::Binding`]).
    pub(crate) fn check_mesh(&self, mesh: &Mesh) -> Result<()> {
        Ok(self.binding.check(mesh, "the sub-mesh")?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use halfedge::generators;

    /// A 10×10 grid with the 2×2-cell square around the centre inside.
    fn grid_submesh() -> (Mesh, SubMesh) {
        let mesh = generators::grid(10, 10, 10.0, 10.0);
        let inside = VertexData::from_fn(&mesh, false, |v| {
            let p = mesh.position(v);
            (p.x - 5.0).abs() <= 1.0 && (p.y - 5.0).abs() <= 1.0
        });
        let sub = SubMesh::from_mask(&mesh, &inside).unwrap();
        (mesh, sub)
    }

    #[test]
    fn frontier_levels_and_collars_on_a_grid() {
        let (mesh, sub) = grid_submesh();
        assert_eq!(sub.len(), 9);
        assert_eq!(sub.frontier_indices().len(), 8);
        let centre = 5 + 5 * 11;
        assert_eq!(sub.level(centre), Some(1));
        assert_eq!(sub.max_level(), 1);
        let collars = sub.collars(&mesh, 2).unwrap();
        assert_eq!(collars.len(), 2);
        // every collar-1 vertex touches the sub-mesh, no collar-2 vertex does
        for &i in &collars[0] {
            assert!(neighbours(&mesh, i as usize).any(|j| sub.contains_index(j)));
        }
        for &i in &collars[1] {
            assert!(!neighbours(&mesh, i as usize).any(|j| sub.contains_index(j)));
            assert!(!sub.contains_index(i as usize));
        }
        let plane = sub.frontier_plane(&mesh).unwrap();
        assert!((plane.normal.dot(DVec3::Z).abs() - 1.0).abs() < 1e-12);
        assert!(plane.normal.z > 0.0, "a flat sub-mesh faces its normals");
    }

    #[test]
    fn rejects_bad_input() {
        let mesh = generators::grid(3, 3, 1.0, 1.0);
        // A mask of the wrong length cannot be made; one of another mesh is stale.
        assert!(VertexData::new(&mesh, vec![true; 3]).is_err());
        let other = generators::grid(3, 3, 1.0, 1.0);
        assert!(matches!(
            SubMesh::from_mask(&mesh, &VertexData::filled(&other, true)),
            Err(DeformError::Stale(_))
        ));
        assert!(matches!(
            SubMesh::from_mask(&mesh, &VertexData::filled(&mesh, false)),
            Err(DeformError::EmptySubMesh)
        ));
        let whole = SubMesh::from_mask(&mesh, &VertexData::filled(&mesh, true)).unwrap();
        assert!(whole.frontier_indices().is_empty());
        assert!(matches!(
            whole.frontier_plane(&mesh),
            Err(DeformError::NoFrontier)
        ));
    }
}
