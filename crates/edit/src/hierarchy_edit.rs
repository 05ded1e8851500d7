//! What an edit made at a coarse level of a [`Hierarchy`] tells the hierarchy, so that
//! refinement brings it back at full resolution as it was made: its **region** (the
//! coarse vertices it may move, [`Hierarchy::mark_region`]: their fine vertices follow
//! the motion of their neighbourhood, everything else stays bit for bit), its
//! **affine parts** (coarse vertices moved by one affine map, [`Hierarchy::mark_affine`]:
//! their fine vertices land exactly on the map's image of where they were) and its
//! **fields** (coarse vertices moved by a map of space that is not affine, such as a twist
//! ramping along its axis, [`Hierarchy::mark_field`]: their fine vertices are that map of
//! where they were). Local-frame detail after Kobbelt, Campagna, Vorsatz & Seidel 1998;
//! see the coarse edits guide (`multires::guide::coarse_edits`, `docs/guide/coarse-edits.md`).
//!
//! Every edit that can be made at a coarse level says what it did through one trait,
//! [`HierarchyEdit`]: a Lee 1999 [`AreaSession`](crate::lee::AreaSession), a Bendels &
//! Klein [`BlendSession`](crate::bendels_klein::BlendSession), an applied sub-mesh edit
//! ([`AppliedSubmeshEdit`](crate::deform::AppliedSubmeshEdit)) and an
//! [`Ffd`](crate::deform::Ffd).

use glam::DAffine3;
use halfedge::hierarchy::{DetailMode, Field, Hierarchy};
use halfedge::{Binding, Mesh, VertexId};

use crate::error::Error;

/// An edit made at a coarse level of a [`Hierarchy`] that tells the hierarchy what it did
/// (its region, affine parts and fields, [`HierarchyMarks`]): implemented by every editing session or applied edit
/// that can edit a coarse level.
///
/// Paper: local-frame detail after Kobbelt, Campagna, Vorsatz & Seidel 1998, *Interactive
/// multi-resolution modeling on arbitrary meshes*, for the edits of Lee 1999, *Interactive
/// multiresolution editing of arbitrary meshes*, Bendels & Klein 2003, *Image and 3D-object
/// editing with precisely specified editing regions* and *Interactive editing of
/// multiresolution meshes*.
pub trait HierarchyEdit {
    /// What the edit did, for a [`Hierarchy`] whose current level `mesh` is (the
    /// hierarchy's mesh, or a clone of it): the region, affine parts and fields of the edit.
    ///
    /// # Errors
    /// The family's `Stale` error when the edit was not made on `mesh` at its current
    /// level (or the kernel's [`halfedge::Stale`] for marks kept by an applied edit).
    fn hierarchy_marks(&self, mesh: &Mesh) -> Result<HierarchyMarks, Error>;

    /// Tells `hierarchy` what the edit did: its [`hierarchy_marks`](Self::hierarchy_marks)
    /// given with [`HierarchyMarks::mark`], which composes with the marks the vertices
    /// already have (use it once per edit). With the paper's translations
    /// ([`DetailMode::Translation`]) nothing is marked.
    ///
    /// # Errors
    /// As [`hierarchy_marks`](Self::hierarchy_marks) for the hierarchy's mesh; nothing is
    /// marked then.
    fn mark(&self, hierarchy: &mut Hierarchy) -> Result<(), Error> {
        self.hierarchy_marks(hierarchy.mesh())?.mark(hierarchy)?;
        Ok(())
    }
}

/// The region, affine parts and fields of one edit, for the [`Hierarchy`] whose mesh it
/// was made on (see [`HierarchyEdit`]).
///
/// Paper: local-frame detail after Kobbelt, Campagna, Vorsatz & Seidel 1998.
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
    /// [`halfedge::Error::InvalidHandle`] for a vertex that is not live in `mesh`;
    /// [`halfedge::Error::InvalidArgument`] for a map that is not finite.
    pub fn new(
        mesh: &Mesh,
        region: Vec<VertexId>,
        affine: Vec<(Vec<VertexId>, DAffine3)>,
    ) -> Result<Self, halfedge::Error> {
        let all = region.iter().chain(affine.iter().flat_map(|(v, _)| v));
        for &v in all {
            mesh.ensure_vertex(v)?;
        }
        if let Some(k) = affine.iter().position(|(_, map)| !map.is_finite()) {
            return Err(halfedge::Error::InvalidArgument(format!(
                "the affine map of part {k} is not finite"
            )));
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

    /// `Ok` when the marks fit `mesh` (see [`Binding::check`]).
    pub(crate) fn check(&self, mesh: &Mesh) -> Result<(), halfedge::Stale> {
        self.binding.check(mesh, "the hierarchy marks")
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
    /// [`halfedge::Error::Stale`] when the marks were not made for the hierarchy's mesh at
    /// its current level; nothing is marked then.
    pub fn mark(&self, hierarchy: &mut Hierarchy) -> Result<(), halfedge::Error> {
        self.give(hierarchy, true)
    }

    /// [`mark`](Self::mark), replacing the affine marks the vertices had instead of
    /// composing with them: for an edit applied again and again from the same starting
    /// positions (an interactive drag), whose maps are its whole motion since the
    /// hierarchy placed the vertices.
    ///
    /// # Errors
    /// As [`mark`](Self::mark).
    pub fn replace(&self, hierarchy: &mut Hierarchy) -> Result<(), halfedge::Error> {
        self.give(hierarchy, false)
    }

    fn give(&self, hierarchy: &mut Hierarchy, compose: bool) -> Result<(), halfedge::Error> {
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
