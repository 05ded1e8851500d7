use std::ops::{Deref, DerefMut, Index, IndexMut};

use crate::binding::{Binding, Stale};
use crate::error::{Error, Result};
use crate::handle::slot;
use crate::handle::VertexId;
use crate::mesh::Mesh;

/// One value per vertex slot of one mesh, with that mesh's binding (see the
/// [docs above](Self)).
///
/// Per-vertex values that know which mesh they belong to.
///
/// A [`VertexData`] is one value per vertex slot (indexed by [`Mesh::vertex_index`], as
/// pmp's vertex properties are) together with the [`Binding`] of the mesh it was
/// computed for: distance fields, normals, weights, masks. It reads like a slice
/// (`data[i]`, `data.iter()`, `&data[..]`) and by handle (`data[v]`), and
/// [`VertexData::check`] / [`VertexData::get`] refuse it, with the one [`Stale`]
/// error every derived value uses, on a mesh it was not made for: another mesh, the same
/// mesh after a change of connectivity, or a hierarchy at another level. The library's
/// functions that take per-vertex data make that check before they read it.
///
/// ```
/// use halfedge::{generators, VertexData};
/// let mut mesh = generators::icosphere(1);
/// let heights = VertexData::from_fn(&mesh, 0.0, |v| mesh.position(v).z);
/// let top = mesh.extreme_vertex(glam::DVec3::Z).unwrap().unwrap();
/// assert_eq!(*heights.get(&mesh, top).unwrap(), mesh.position(top).z);
/// let h = mesh.halfedges().find(|&h| mesh.is_collapse_ok(h).is_ok()).unwrap();
/// mesh.collapse(h).unwrap();
/// assert!(heights.check(&mesh).is_err()); // made before the collapse
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VertexData<T> {
    values: Vec<T>,
    binding: Binding,
}

impl<T> VertexData<T> {
    /// Wraps `values` (one per [`Mesh::vertex_slots`], by [`Mesh::vertex_index`]) as data
    /// of `mesh` as it is now.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] when `values` does not have one entry per vertex slot.
    pub fn new(mesh: &Mesh, values: Vec<T>) -> Result<Self> {
        if values.len() != mesh.vertex_slots() {
            return Err(Error::InvalidArgument(format!(
                "per-vertex data needs one value per vertex slot ({}), got {}",
                mesh.vertex_slots(),
                values.len()
            )));
        }
        Ok(Self {
            values,
            binding: mesh.binding(),
        })
    }

    /// `f(v)` for every live vertex `v` of `mesh`, `fill` in the slots of removed
    /// vertices.
    pub fn from_fn(mesh: &Mesh, fill: T, mut f: impl FnMut(VertexId) -> T) -> Self
    where
        T: Clone,
    {
        let mut values = vec![fill; mesh.vertex_slots()];
        for v in mesh.vertices() {
            values[slot(v)] = f(v);
        }
        Self {
            values,
            binding: mesh.binding(),
        }
    }

    /// `value` in every slot of `mesh`.
    pub fn filled(mesh: &Mesh, value: T) -> Self
    where
        T: Clone,
    {
        Self {
            values: vec![value; mesh.vertex_slots()],
            binding: mesh.binding(),
        }
    }

    /// Values computed for the mesh `binding` names (for example by a solver made for
    /// that mesh, which keeps its binding): the caller guarantees one value per vertex
    /// slot of that mesh, as [`VertexData::new`] checks when the mesh is at hand.
    pub fn with_binding(values: Vec<T>, binding: Binding) -> Self {
        Self { values, binding }
    }

    /// Binds the data to `mesh` as it is now, grown (with `fill`) or cut to its vertex
    /// slots: for an owner that keeps its values up to date through a change of
    /// connectivity it made itself (a session that splits edges and fills in the new
    /// vertices' values).
    pub fn rebind(&mut self, mesh: &Mesh, fill: T)
    where
        T: Clone,
    {
        self.values.resize(mesh.vertex_slots(), fill);
        self.binding = mesh.binding();
    }

    /// The mesh this data was made for.
    #[must_use]
    pub fn binding(&self) -> Binding {
        self.binding
    }

    /// `Ok` when this data fits `mesh` (see [`Binding`]).
    ///
    /// # Errors
    /// [`Stale`] naming what it was made for and what it met.
    pub fn check(&self, mesh: &Mesh) -> std::result::Result<(), Stale> {
        self.binding.check(mesh, "the per-vertex data")
    }

    /// The value of `v`, checked: the data fits `mesh` and `v` is a vertex of it (live or
    /// removed by a collapse).
    ///
    /// # Errors
    /// [`Error::Stale`] when the data does not fit `mesh`; [`Error::InvalidHandle`] when
    /// `v` is not a vertex of `mesh`.
    pub fn get(&self, mesh: &Mesh, v: VertexId) -> Result<&T> {
        self.check(mesh)?;
        if !mesh.vertex_slots_.contains(v) {
            return Err(Error::InvalidHandle(format!("vertex {v}")));
        }
        self.values
            .get(slot(v))
            .ok_or_else(|| Error::InvalidHandle(format!("vertex {v}")))
    }

    /// The values, by [`Mesh::vertex_index`].
    #[must_use]
    pub fn values(&self) -> &[T] {
        &self.values
    }

    /// The values, mutable (the length cannot change).
    pub fn values_mut(&mut self) -> &mut [T] {
        &mut self.values
    }

    /// The values as a plain vector (the binding is dropped).
    #[must_use]
    pub fn into_values(self) -> Vec<T> {
        self.values
    }

    /// The same binding with `f` applied to every value.
    #[must_use]
    pub fn map<U>(&self, f: impl FnMut(&T) -> U) -> VertexData<U> {
        VertexData {
            values: self.values.iter().map(f).collect(),
            binding: self.binding,
        }
    }
}

/// Reads as a slice indexed by [`Mesh::vertex_index`].
impl<T> Deref for VertexData<T> {
    type Target = [T];
    fn deref(&self) -> &[T] {
        &self.values
    }
}

/// Writes as a slice (the length cannot change).
impl<T> DerefMut for VertexData<T> {
    fn deref_mut(&mut self) -> &mut [T] {
        &mut self.values
    }
}

/// The value of a vertex by handle (unchecked against the mesh: use
/// [`VertexData::get`] for a handle or data you did not just make).
///
/// # Panics
/// When the handle's slot is past the data.
impl<T> Index<VertexId> for VertexData<T> {
    type Output = T;
    fn index(&self, v: VertexId) -> &T {
        &self.values[slot(v)]
    }
}

/// The value of a vertex by handle, mutable (see [`Index`]).
impl<T> IndexMut<VertexId> for VertexData<T> {
    fn index_mut(&mut self, v: VertexId) -> &mut T {
        &mut self.values[slot(v)]
    }
}

/// Slice indexing by [`Mesh::vertex_index`] (`data[i]`, `data[a..b]`), as on the values.
impl<T, I: std::slice::SliceIndex<[T]>> Index<I> for VertexData<T> {
    type Output = I::Output;
    fn index(&self, index: I) -> &I::Output {
        &self.values[index]
    }
}

/// Slice indexing, mutable.
impl<T, I: std::slice::SliceIndex<[T]>> IndexMut<I> for VertexData<T> {
    fn index_mut(&mut self, index: I) -> &mut I::Output {
        &mut self.values[index]
    }
}

/// Iterates the values, by [`Mesh::vertex_index`].
impl<'a, T> IntoIterator for &'a VertexData<T> {
    type Item = &'a T;
    type IntoIter = std::slice::Iter<'a, T>;
    fn into_iter(self) -> Self::IntoIter {
        self.values.iter()
    }
}

/// Iterates the values mutably.
impl<'a, T> IntoIterator for &'a mut VertexData<T> {
    type Item = &'a mut T;
    type IntoIter = std::slice::IterMut<'a, T>;
    fn into_iter(self) -> Self::IntoIter {
        self.values.iter_mut()
    }
}

/// The values as a slice.
impl<T> AsRef<[T]> for VertexData<T> {
    fn as_ref(&self) -> &[T] {
        &self.values
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generators;

    #[test]
    fn data_fits_its_mesh_and_clones_and_refuses_others() {
        let mut mesh = generators::icosphere(1);
        let data = VertexData::filled(&mesh, 1u8);
        assert_eq!(data.len(), mesh.vertex_slots());
        data.check(&mesh).unwrap();
        let clone = mesh.clone();
        data.check(&clone).unwrap();
        let other = generators::icosphere(1);
        assert!(data.check(&other).is_err(), "another mesh of the same size");
        let v = mesh.vertices().next().unwrap();
        assert_eq!(*data.get(&mesh, v).unwrap(), 1);
        assert!(matches!(data.get(&other, v), Err(Error::Stale(_))));
        let h = mesh
            .halfedges()
            .find(|&h| mesh.is_collapse_ok(h).is_ok())
            .unwrap();
        mesh.collapse(h).unwrap();
        assert!(data.check(&mesh).is_err(), "connectivity changed");
        assert!(VertexData::new(&mesh, vec![0u8; 3]).is_err());
    }
}
