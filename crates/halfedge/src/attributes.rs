//! Typed per-element attributes that stay in step with the mesh.
//!
//! An attribute is a dense array with one value per element slot, created with a
//! default value and grown with that default whenever the mesh creates elements.
//! Collapses keep the values of removed elements (tombstones), so a vertex split brings
//! back a vertex together with its attribute values.
//!
//! ```
//! use halfedge::{generators, Mesh};
//! let mut mesh = generators::icosphere(1);
//! let label = mesh.add_vertex_attribute("label", 0u32).unwrap();
//! let v = mesh.vertices().next().unwrap();
//! *mesh.attribute_mut(label, v) = 7;
//! assert_eq!(*mesh.attribute(label, v), 7);
//! ```

use std::any::Any;
use std::marker::PhantomData;

use crate::handle::slot;
use crate::{Error, FaceId, HalfedgeId, Mesh, Result, VertexId};

/// Typed handle of an attribute on elements of kind `K` (`VertexId`, `HalfedgeId` or
/// `FaceId`) with values of type `T`.
pub struct Attribute<K, T> {
    column: usize,
    /// Which attribute that column held when the handle was made: a column freed by
    /// `remove_attribute` and taken by a new attribute has another generation, so an old
    /// handle never reads the new attribute's values.
    generation: u64,
    _marker: PhantomData<fn(K) -> T>,
}

impl<K, T> Clone for Attribute<K, T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<K, T> Copy for Attribute<K, T> {}
/// Two handles are equal when they name the same attribute (column and generation).
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

/// A value type that can be stored as an attribute.
pub trait AttributeValue: Clone + Send + Sync + 'static {}
impl<T: Clone + Send + Sync + 'static> AttributeValue for T {}

trait Column: Send + Sync {
    fn resize(&mut self, len: usize);
    fn clone_box(&self) -> Box<dyn Column>;
    fn as_any(&self) -> &dyn Any;
    fn as_any_mut(&mut self) -> &mut dyn Any;
}

struct TypedColumn<T> {
    data: Vec<T>,
    default: T,
}

impl<T: AttributeValue> Column for TypedColumn<T> {
    fn resize(&mut self, len: usize) {
        if self.data.len() < len {
            self.data.resize(len, self.default.clone());
        }
    }
    fn clone_box(&self) -> Box<dyn Column> {
        Box::new(TypedColumn {
            data: self.data.clone(),
            default: self.default.clone(),
        })
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

struct Named {
    name: String,
    generation: u64,
    column: Box<dyn Column>,
}

/// The attributes of one element kind (internal storage, not nameable outside the crate).
#[derive(Default)]
pub struct AttributeStore {
    columns: Vec<Option<Named>>,
    len: usize,
    /// Attributes added so far (the next one's generation).
    added: u64,
}

impl Clone for AttributeStore {
    fn clone(&self) -> Self {
        Self {
            columns: self
                .columns
                .iter()
                .map(|c| {
                    c.as_ref().map(|n| Named {
                        name: n.name.clone(),
                        generation: n.generation,
                        column: n.column.clone_box(),
                    })
                })
                .collect(),
            len: self.len,
            added: self.added,
        }
    }
}

impl AttributeStore {
    pub(crate) fn ensure_len(&mut self, len: usize) {
        if len > self.len {
            self.len = len;
            for c in self.columns.iter_mut().flatten() {
                c.column.resize(len);
            }
        }
    }
    fn add<T: AttributeValue>(&mut self, name: &str, default: T) -> Result<(usize, u64)> {
        if self.columns.iter().flatten().any(|c| c.name == name) {
            return Err(Error::DuplicateAttribute(name.to_owned()));
        }
        let column = Box::new(TypedColumn {
            data: vec![default.clone(); self.len],
            default,
        });
        let generation = self.added;
        self.added += 1;
        let named = Named {
            name: name.to_owned(),
            generation,
            column,
        };
        if let Some(i) = self.columns.iter().position(Option::is_none) {
            self.columns[i] = Some(named);
            Ok((i, generation))
        } else {
            self.columns.push(Some(named));
            Ok((self.columns.len() - 1, generation))
        }
    }
    fn has<T: AttributeValue>(&self, column: usize, generation: u64) -> bool {
        self.columns
            .get(column)
            .and_then(Option::as_ref)
            .is_some_and(|c| c.generation == generation && c.column.as_any().is::<TypedColumn<T>>())
    }
    fn find<T: AttributeValue>(&self, name: &str) -> Option<(usize, u64)> {
        self.columns.iter().enumerate().find_map(|(i, c)| {
            c.as_ref()
                .filter(|c| c.name == name && c.column.as_any().is::<TypedColumn<T>>())
                .map(|c| (i, c.generation))
        })
    }
    fn data<T: AttributeValue>(&self, column: usize, generation: u64) -> &Vec<T> {
        let c = self
            .columns
            .get(column)
            .and_then(Option::as_ref)
            .filter(|c| c.generation == generation)
            .expect("attribute was removed");
        &c.column
            .as_any()
            .downcast_ref::<TypedColumn<T>>()
            .expect("attribute of another type")
            .data
    }
    fn data_mut<T: AttributeValue>(&mut self, column: usize, generation: u64) -> &mut Vec<T> {
        let c = self
            .columns
            .get_mut(column)
            .and_then(Option::as_mut)
            .filter(|c| c.generation == generation)
            .expect("attribute was removed");
        &mut c
            .column
            .as_any_mut()
            .downcast_mut::<TypedColumn<T>>()
            .expect("attribute of another type")
            .data
    }
    /// Number of attributes (columns not removed).
    #[cfg(test)]
    pub(crate) fn column_count(&self) -> usize {
        self.columns.iter().flatten().count()
    }
    fn remove(&mut self, column: usize) {
        if let Some(c) = self.columns.get_mut(column) {
            *c = None;
        }
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
    /// existing and future element. Fails if the name is taken for this element kind.
    pub fn add_attribute<K: Element, T: AttributeValue>(
        &mut self,
        name: &str,
        default: T,
    ) -> Result<Attribute<K, T>> {
        let (column, generation) = K::store_mut(self).add(name, default)?;
        Ok(Attribute {
            column,
            generation,
            _marker: PhantomData,
        })
    }
    /// [`add_attribute`](Self::add_attribute) for vertices.
    pub fn add_vertex_attribute<T: AttributeValue>(
        &mut self,
        name: &str,
        default: T,
    ) -> Result<Attribute<VertexId, T>> {
        self.add_attribute(name, default)
    }
    /// [`add_attribute`](Self::add_attribute) for faces.
    pub fn add_face_attribute<T: AttributeValue>(
        &mut self,
        name: &str,
        default: T,
    ) -> Result<Attribute<FaceId, T>> {
        self.add_attribute(name, default)
    }
    /// [`add_attribute`](Self::add_attribute) for halfedges.
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
            .map(|(column, generation)| Attribute {
                column,
                generation,
                _marker: PhantomData,
            })
    }
    /// True when `attribute` is an attribute of this mesh: it was not removed (an
    /// attribute added since in its place is another attribute, whatever its type). The
    /// accessors below panic on an attribute for which this is false; check it (or use
    /// [`try_attribute_values`](Self::try_attribute_values)) for handles you did not
    /// just make.
    pub fn has_attribute<K: Element, T: AttributeValue>(&self, attribute: Attribute<K, T>) -> bool {
        K::store(self).has::<T>(attribute.column, attribute.generation)
    }
    /// All values of `attribute` (as [`attribute_values`](Self::attribute_values)), or an
    /// error when the attribute is not (any longer) an attribute of this mesh.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] naming the stale handle.
    pub fn try_attribute_values<K: Element, T: AttributeValue>(
        &self,
        attribute: Attribute<K, T>,
    ) -> Result<&[T]> {
        if !self.has_attribute(attribute) {
            return Err(Error::InvalidArgument(format!(
                "{attribute:?} is not an attribute of this mesh (removed, or made on another mesh)"
            )));
        }
        Ok(K::store(self).data::<T>(attribute.column, attribute.generation))
    }
    /// Removes an attribute; its handle must not be used afterwards.
    pub fn remove_attribute<K: Element, T: AttributeValue>(&mut self, attribute: Attribute<K, T>) {
        if self.has_attribute(attribute) {
            K::store_mut(self).remove(attribute.column);
        }
    }
    /// The value of `attribute` at element `k`.
    ///
    /// # Panics
    /// If `k` is stale (its element was freed by garbage collection) or the attribute was removed.
    #[inline]
    pub fn attribute<K: Element, T: AttributeValue>(&self, attribute: Attribute<K, T>, k: K) -> &T {
        assert!(K::is_live(self, k), "stale handle {k}");
        &K::store(self).data::<T>(attribute.column, attribute.generation)[slot(k)]
    }
    /// Mutable access to the value of `attribute` at element `k`.
    ///
    /// # Panics
    /// As [`attribute`](Self::attribute).
    #[inline]
    pub fn attribute_mut<K: Element, T: AttributeValue>(
        &mut self,
        attribute: Attribute<K, T>,
        k: K,
    ) -> &mut T {
        assert!(K::is_live(self, k), "stale handle {k}");
        &mut K::store_mut(self).data_mut::<T>(attribute.column, attribute.generation)[slot(k)]
    }
    /// All values, indexed by element index ([`vertex_index`](Self::vertex_index), …).
    pub fn attribute_values<K: Element, T: AttributeValue>(
        &self,
        attribute: Attribute<K, T>,
    ) -> &[T] {
        K::store(self).data::<T>(attribute.column, attribute.generation)
    }
    /// All values, mutable, indexed by element index (for parallel updates).
    pub fn attribute_values_mut<K: Element, T: AttributeValue>(
        &mut self,
        attribute: Attribute<K, T>,
    ) -> &mut [T] {
        K::store_mut(self).data_mut::<T>(attribute.column, attribute.generation)
    }
}
