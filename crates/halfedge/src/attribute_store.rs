//! The storage of attributes: one typed column per attribute, grown with the mesh
//! (internal to the crate; the handles and accessors are in [`crate::attributes`]).

use std::any::Any;

use crate::error::{Error, Result};

/// A value type that can be stored as an attribute.
pub trait AttributeValue: Clone + Send + Sync + 'static {}
impl<T: Clone + Send + Sync + 'static> AttributeValue for T {}

pub(crate) trait Column: Send + Sync {
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
}

/// A number no attribute had before (see [`Attribute`]).
fn next_generation() -> u64 {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
    NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
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
    pub(crate) fn add<T: AttributeValue>(
        &mut self,
        name: &str,
        default: T,
    ) -> Result<(usize, u64)> {
        if self.columns.iter().flatten().any(|c| c.name == name) {
            return Err(Error::DuplicateAttribute(name.to_owned()));
        }
        let column = Box::new(TypedColumn {
            data: vec![default.clone(); self.len],
            default,
        });
        let generation = next_generation();
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
    pub(crate) fn has<T: AttributeValue>(&self, column: usize, generation: u64) -> bool {
        self.columns
            .get(column)
            .and_then(Option::as_ref)
            .is_some_and(|c| c.generation == generation && c.column.as_any().is::<TypedColumn<T>>())
    }
    pub(crate) fn find<T: AttributeValue>(&self, name: &str) -> Option<(usize, u64)> {
        self.columns.iter().enumerate().find_map(|(i, c)| {
            c.as_ref()
                .filter(|c| c.name == name && c.column.as_any().is::<TypedColumn<T>>())
                .map(|c| (i, c.generation))
        })
    }
    pub(crate) fn name(&self, column: usize, generation: u64) -> Option<&str> {
        let c = self.columns.get(column)?.as_ref()?;
        (c.generation == generation).then_some(c.name.as_str())
    }
    pub(crate) fn data<T: AttributeValue>(
        &self,
        column: usize,
        generation: u64,
    ) -> Option<&Vec<T>> {
        let c = self.columns.get(column)?.as_ref()?;
        if c.generation != generation {
            return None;
        }
        Some(&c.column.as_any().downcast_ref::<TypedColumn<T>>()?.data)
    }
    pub(crate) fn data_mut<T: AttributeValue>(
        &mut self,
        column: usize,
        generation: u64,
    ) -> Option<&mut Vec<T>> {
        let c = self.columns.get_mut(column)?.as_mut()?;
        if c.generation != generation {
            return None;
        }
        Some(&mut c.column.as_any_mut().downcast_mut::<TypedColumn<T>>()?.data)
    }
    /// Number of attributes (columns not removed).
    #[cfg(test)]
    pub(crate) fn column_count(&self) -> usize {
        self.columns.iter().flatten().count()
    }
    pub(crate) fn remove(&mut self, column: usize) {
        if let Some(c) = self.columns.get_mut(column) {
            *c = None;
        }
    }
}
