//! What an edit made at a coarse level of a [`Hierarchy`] tells the hierarchy, so that
//! refinement brings it back at full resolution as it was made: its **region** (the
//! coarse vertices it may move, [`Hierarchy::mark_region`]: their fine vertices follow
//! the motion of their neighbourhood, everything else stays bit for bit), its
//! **affine parts** (coarse vertices moved by one affine map, [`Hierarchy::mark_affine`]:
//! their fine vertices land exactly on the map's image of where they were) and its
//! **fields** (coarse vertices moved by a map of space that is not affine, such as a twist
//! ramping along its axis, [`Hierarchy::mark_field`]: their fine vertices are that map of
//! where they were). Local-frame
//! detail after Kobbelt, Campagna, Vorsatz & Seidel 1998; see the
//! [coarse edits guide](crate::guide::coarse_edits).
//!
//! Every method that can edit a coarse level says what it did:
//! [`SubMesh::hierarchy_marks`](crate::deform::submesh::SubMesh::hierarchy_marks) (and
//! [`SubMesh::apply_in_hierarchy`](crate::deform::submesh::SubMesh::apply_in_hierarchy)),
//! [`AreaSession::hierarchy_marks`](crate::area::AreaSession::hierarchy_marks),
//! [`Ffd::hierarchy_marks`](crate::deform::ffd::Ffd::hierarchy_marks);
//! [`BlendSession::mark_in_hierarchy`](crate::bendels_klein::mesh::BlendSession::mark_in_hierarchy)
//! marks a Bendels & Klein edit directly.

use glam::DAffine3;
use halfedge::{Binding, DetailMode, Field, Hierarchy, Mesh, VertexId};

use crate::{EditError, Result};

/// The region, affine parts and fields of one edit, for the [`Hierarchy`] whose mesh it
/// was made on (see the [module docs](self)).
#[derive(Clone)]
pub struct HierarchyMarks {
    binding: Binding,
    region: Vec<VertexId>,
    affine: Vec<(Vec<VertexId>, DAffine3)>,
    fields: Vec<(Vec<VertexId>, Field)>,
}

impl std::fmt::Debug for HierarchyMarks {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HierarchyMarks")
            .field("region", &self.region.len())
            .field("affine", &self.affine)
            .field(
                "fields",
                &self.fields.iter().map(|(v, _)| v.len()).collect::<Vec<_>>(),
            )
            .finish()
    }
}

impl HierarchyMarks {
    /// Marks for `mesh` (the hierarchy's mesh, or a clone of it): `region`, the vertices
    /// the edit may move, and `affine`, groups of vertices each moved by one affine map.
    ///
    /// # Errors
    /// [`EditError::InvalidVertex`] for a vertex that is not live in `mesh`;
    /// [`EditError::NonFiniteMatrix`] for a map that is not finite.
    pub fn new(
        mesh: &Mesh,
        region: Vec<VertexId>,
        affine: Vec<(Vec<VertexId>, DAffine3)>,
    ) -> Result<Self> {
        let all = region.iter().chain(affine.iter().flat_map(|(v, _)| v));
        if let Some(&v) = all.into_iter().find(|&&v| !mesh.is_valid_vertex(v)) {
            return Err(EditError::InvalidVertex(v));
        }
        if affine.iter().any(|(_, map)| !map.is_finite()) {
            return Err(EditError::NonFiniteMatrix);
        }
        Ok(Self {
            binding: mesh.binding(),
            region,
            affine,
            fields: Vec::new(),
        })
    }

    /// The same marks, checked against `binding` (the one of the value that made them:
    /// a sub-mesh, an area, an attachment) instead of the mesh they were computed on,
    /// which may be a clone of the hierarchy's mesh.
    pub(crate) fn bound_to(mut self, binding: Binding) -> Self {
        self.binding = binding;
        self
    }

    /// The same marks with `vertices` moved by the affine `map`.
    pub(crate) fn with_affine(mut self, vertices: Vec<VertexId>, map: DAffine3) -> Self {
        self.affine.push((vertices, map));
        self
    }

    /// The same marks with `vertices` moved by `field`, a map of space
    /// ([`Hierarchy::mark_field`]).
    pub(crate) fn with_field(mut self, vertices: Vec<VertexId>, field: Field) -> Self {
        self.fields.push((vertices, field));
        self
    }

    /// The vertices the edit may move.
    pub fn region(&self) -> &[VertexId] {
        &self.region
    }

    /// The groups of vertices moved by one affine map each.
    pub fn affine_parts(&self) -> &[(Vec<VertexId>, DAffine3)] {
        &self.affine
    }

    /// The groups of vertices moved by one map of space each (a deformation that is not
    /// affine, given to the hierarchy with [`Hierarchy::mark_field`]).
    pub fn field_parts(&self) -> &[(Vec<VertexId>, Field)] {
        &self.fields
    }

    /// Tells `hierarchy` about the edit: [`Hierarchy::mark_affine`] for every affine part
    /// and [`Hierarchy::mark_shared_field`] for every field (composing with the marks the
    /// vertices already have: use this once per edit), and [`Hierarchy::mark_region`] for
    /// the region. With the paper's translations
    /// ([`DetailMode::Translation`]) nothing is marked.
    ///
    /// # Errors
    /// [`EditError::Stale`] when the marks were not made for the hierarchy's mesh at its
    /// current level; nothing is marked then.
    pub fn mark(&self, hierarchy: &mut Hierarchy) -> Result<()> {
        self.give(hierarchy, true)
    }

    /// [`mark`](Self::mark), replacing the affine marks the vertices had instead of
    /// composing with them: for an edit applied again and again from the same starting
    /// positions (an interactive drag), whose maps are its whole motion since the
    /// hierarchy placed the vertices.
    ///
    /// # Errors
    /// As [`mark`](Self::mark).
    pub fn replace(&self, hierarchy: &mut Hierarchy) -> Result<()> {
        self.give(hierarchy, false)
    }

    fn give(&self, hierarchy: &mut Hierarchy, compose: bool) -> Result<()> {
        self.binding
            .check(hierarchy.mesh(), "the hierarchy marks")?;
        if hierarchy.detail_mode() != DetailMode::LocalFrame {
            return Ok(());
        }
        // Checked at construction and by the binding: the hierarchy cannot refuse now, so
        // nothing is half-marked.
        for (vertices, map) in &self.affine {
            if compose {
                hierarchy.mark_affine(vertices, *map)?;
            } else {
                hierarchy.set_affine_mark(vertices, *map)?;
            }
        }
        for (vertices, field) in &self.fields {
            if compose {
                hierarchy.mark_shared_field(vertices, field.clone())?;
            } else {
                hierarchy.set_field_mark(vertices, field.clone())?;
            }
        }
        hierarchy.mark_region(&self.region)?;
        Ok(())
    }
}
