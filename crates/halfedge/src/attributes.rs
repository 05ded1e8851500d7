use std::marker::PhantomData;

use crate::attribute_store::AttributeStore;
pub use crate::attribute_store::AttributeValue;
use crate::binding::{Binding, Stale};
use crate::error::{Error, Result};
use crate::handle::{slot, FaceId, HalfedgeId, VertexId};
use crate::mesh::Mesh;

/// Typed handle of an attribute on elements of kind `K` (`VertexId`, `HalfedgeId` or
/// `FaceId`) with values of type `T`.
///
/// A handle is bound to the attribute it names: the mesh that made it and the clones of
/// that mesh (which copy its attributes) accept it; another mesh, or the same mesh after
/// the attribute was removed, refuses it with [`Error::Stale`], whatever the type.
///
/// Typed per-element attributes that stay in step with the mesh.
///
/// An attribute is a dense array with one value per element slot, created with a
/// default value and grown with that default whenever the mesh creates elements.
/// Collapses keep the values of removed elements (tombstones), so a vertex split brings
/// back a vertex together with its attribute values.
///
/// ```
/// use halfedge::{generators, Mesh};
/// let mut mesh = generators::icosphere(1);
/// let label = mesh.add_vertex_attribute("label", 0u32).unwrap();
/// let v = mesh.vertices().next().unwrap();
/// *mesh.attribute_mut(label, v).unwrap() = 7;
/// assert_eq!(*mesh.attribute(label, v).unwrap(), 7);
/// ```
pub struct Attribute<K, T> {
    column: usize,
    /// Which attribute that column held when the handle was made: a number no other
    /// attribute of any mesh has (clones copy it with the attribute), so a handle never
    /// reads another attribute's values, on its own mesh or on another one.
    generation: u64,
    /// The mesh the attribute was made on, as it was then (for the error).
    binding: Binding,
    _marker: PhantomData<fn(K) -> T>,
}

impl<K, T> Clone for Attribute<K, T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<K, T> Copy for Attribute<K, T> {}
/// Two handles are equal when they name the same attribute.
impl<K, T> PartialEq for Attribute<K, T> {
    fn eq(&self, other: &Self) -> bool {
        (self.column, self.generation) == (other.column, other.generation)
    }
}
impl<K, T> Eq for Attribute<K, T> {}
impl<K, T> std::fmt::Debug for Attribute<K, T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Attribute({}#{})", self.column, self.generation)
    }
}

/// Element kinds that carry attributes.
pub trait Element: slotmap::Key + std::fmt::Display {
    #[doc(hidden)]
    fn store(mesh: &Mesh) -> &AttributeStore;
    #[doc(hidden)]
    fn store_mut(mesh: &mut Mesh) -> &mut AttributeStore;
    #[doc(hidden)]
    fn is_live(mesh: &Mesh, key: Self) -> bool;
}

impl Element for VertexId {
    fn store(mesh: &Mesh) -> &AttributeStore {
        &mesh.vertex_attributes
    }
    fn store_mut(mesh: &mut Mesh) -> &mut AttributeStore {
        &mut mesh.vertex_attributes
    }
    fn is_live(mesh: &Mesh, key: Self) -> bool {
        mesh.vertex_slots_.contains(key)
    }
}
impl Element for HalfedgeId {
    fn store(mesh: &Mesh) -> &AttributeStore {
        &mesh.halfedge_attributes
    }
    fn store_mut(mesh: &mut Mesh) -> &mut AttributeStore {
        &mut mesh.halfedge_attributes
    }
    fn is_live(mesh: &Mesh, key: Self) -> bool {
        mesh.halfedge_slots_.contains(key)
    }
}
impl Element for FaceId {
    fn store(mesh: &Mesh) -> &AttributeStore {
        &mesh.face_attributes
    }
    fn store_mut(mesh: &mut Mesh) -> &mut AttributeStore {
        &mut mesh.face_attributes
    }
    fn is_live(mesh: &Mesh, key: Self) -> bool {
        mesh.face_slots_.contains(key)
    }
}

/// # Attributes
impl Mesh {
    /// Adds a named attribute on elements of kind `K` with a default value for every
    /// existing and future element.
    ///
    /// # Errors
    /// [`Error::DuplicateAttribute`] when the name is taken for this element kind.
    pub fn add_attribute<K: Element, T: AttributeValue>(
        &mut self,
        name: &str,
        default: T,
    ) -> Result<Attribute<K, T>> {
        let (column, generation) = K::store_mut(self).add(name, default)?;
        Ok(self.handle(column, generation))
    }
    /// [`add_attribute`](Self::add_attribute) for vertices.
    ///
    /// # Errors
    /// As [`add_attribute`](Self::add_attribute).
    pub fn add_vertex_attribute<T: AttributeValue>(
        &mut self,
        name: &str,
        default: T,
    ) -> Result<Attribute<VertexId, T>> {
        self.add_attribute(name, default)
    }
    /// [`add_attribute`](Self::add_attribute) for faces.
    ///
    /// # Errors
    /// As [`add_attribute`](Self::add_attribute).
    pub fn add_face_attribute<T: AttributeValue>(
        &mut self,
        name: &str,
        default: T,
    ) -> Result<Attribute<FaceId, T>> {
        self.add_attribute(name, default)
    }
    /// [`add_attribute`](Self::add_attribute) for halfedges.
    ///
    /// # Errors
    /// As [`add_attribute`](Self::add_attribute).
    pub fn add_halfedge_attribute<T: AttributeValue>(
        &mut self,
        name: &str,
        default: T,
    ) -> Result<Attribute<HalfedgeId, T>> {
        self.add_attribute(name, default)
    }
    /// Looks an attribute up by name and type.
    pub fn find_attribute<K: Element, T: AttributeValue>(
        &self,
        name: &str,
    ) -> Option<Attribute<K, T>> {
        K::store(self)
            .find::<T>(name)
            .map(|(column, generation)| self.handle(column, generation))
    }
    fn handle<K, T>(&self, column: usize, generation: u64) -> Attribute<K, T> {
        Attribute {
            column,
            generation,
            binding: self.binding(),
            _marker: PhantomData,
        }
    }
    /// True when `attribute` is an attribute of this mesh: made on it (or on the mesh it
    /// was cloned from, before the clone) and not removed since.
    pub fn has_attribute<K: Element, T: AttributeValue>(&self, attribute: Attribute<K, T>) -> bool {
        K::store(self).has::<T>(attribute.column, attribute.generation)
    }
    /// The name of `attribute`, when it is an attribute of this mesh.
    pub(crate) fn attribute_name<K: Element, T: AttributeValue>(
        &self,
        attribute: Attribute<K, T>,
    ) -> Option<&str> {
        if !self.has_attribute(attribute) {
            return None;
        }
        K::store(self).name(attribute.column, attribute.generation)
    }
    /// [`Error::Stale`] for a handle that is not an attribute of this mesh.
    fn stale<K, T>(&self, attribute: Attribute<K, T>) -> Error {
        Stale::new(
            "the attribute handle (removed, or made on another mesh)",
            attribute.binding,
            self.binding(),
        )
        .into()
    }
    /// Removes an attribute; its handle is refused afterwards.
    ///
    /// # Errors
    /// [`Error::Stale`] when `attribute` is not an attribute of this mesh (nothing is
    /// removed then).
    pub fn remove_attribute<K: Element, T: AttributeValue>(
        &mut self,
        attribute: Attribute<K, T>,
    ) -> Result<()> {
        if !self.has_attribute(attribute) {
            return Err(self.stale(attribute));
        }
        K::store_mut(self).remove(attribute.column);
        Ok(())
    }
    /// The value of `attribute` at element `k` (live, or removed by a collapse: its value
    /// is kept for the split).
    ///
    /// # Errors
    /// [`Error::Stale`] when `attribute` is not an attribute of this mesh;
    /// [`Error::InvalidHandle`] when `k` is not an element of it (freed by garbage
    /// collection, or of another mesh).
    #[inline]
    pub fn attribute<K: Element, T: AttributeValue>(
        &self,
        attribute: Attribute<K, T>,
        k: K,
    ) -> Result<&T> {
        let values = self.attribute_values(attribute)?;
        if !K::is_live(self, k) {
            return Err(Error::InvalidHandle(format!("{k}")));
        }
        values
            .get(slot(k))
            .ok_or_else(|| Error::InvalidHandle(format!("{k}")))
    }
    /// Mutable access to the value of `attribute` at element `k`.
    ///
    /// # Errors
    /// As [`attribute`](Self::attribute).
    #[inline]
    pub fn attribute_mut<K: Element, T: AttributeValue>(
        &mut self,
        attribute: Attribute<K, T>,
        k: K,
    ) -> Result<&mut T> {
        if !K::is_live(self, k) {
            return Err(Error::InvalidHandle(format!("{k}")));
        }
        let values = self.attribute_values_mut(attribute)?;
        values
            .get_mut(slot(k))
            .ok_or_else(|| Error::InvalidHandle(format!("{k}")))
    }
    /// All values, indexed by element index ([`vertex_index`](Self::vertex_index), …).
    ///
    /// # Errors
    /// [`Error::Stale`] when `attribute` is not an attribute of this mesh.
    pub fn attribute_values<K: Element, T: AttributeValue>(
        &self,
        attribute: Attribute<K, T>,
    ) -> Result<&[T]> {
        match K::store(self).data::<T>(attribute.column, attribute.generation) {
            Some(values) => Ok(values),
            None => Err(self.stale(attribute)),
        }
    }
    /// All values, mutable, indexed by element index (for parallel updates).
    ///
    /// # Errors
    /// [`Error::Stale`] when `attribute` is not an attribute of this mesh.
    pub fn attribute_values_mut<K: Element, T: AttributeValue>(
        &mut self,
        attribute: Attribute<K, T>,
    ) -> Result<&mut [T]> {
        if !self.has_attribute(attribute) {
            return Err(self.stale(attribute));
        }
        Ok(K::store_mut(self)
            .data_mut::<T>(attribute.column, attribute.generation)
            .map(Vec::as_mut_slice)
            .unwrap_or_default())
    }
}
