//! Element handles: versioned `slotmap` keys.
//!
//! A handle stays valid until its element is removed for good (by
//! [`Mesh::garbage_collection`](crate::Mesh::garbage_collection)); a stale handle is
//! detected by the slot's version and never silently aliases another element.
//! Collapsed elements are kept as tombstones so that a vertex split revives the very
//! handles the collapse removed.

use slotmap::{new_key_type, Key};

new_key_type! {
    /// Handle of a vertex.
    pub struct VertexId;
    /// Handle of a halfedge (one side of an edge, oriented from `from_vertex` to `to_vertex`).
    pub struct HalfedgeId;
    /// Handle of a (triangle) face.
    pub struct FaceId;
}

/// Dense slot index of a key: the position of its element in per-element arrays
/// (positions, attributes). Slot 0 of a `SlotMap` is a sentinel, so indices start at 0
/// for the first element ever inserted.
#[inline]
pub(crate) fn slot<K: Key>(key: K) -> usize {
    ((key.data().as_ffi() & 0xffff_ffff) as usize).wrapping_sub(1)
}

impl std::fmt::Display for VertexId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "v{}", slot(*self))
    }
}
impl std::fmt::Display for HalfedgeId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "h{}", slot(*self))
    }
}
impl std::fmt::Display for FaceId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "f{}", slot(*self))
    }
}
