//! Selecting vertices: the queries an editing program makes before it edits — the
//! vertex nearest to a point, the extreme vertex in a direction, the vertices within a
//! Euclidean or an edge-path (graph geodesic) radius, connected components, select
//! linked, grow and shrink. Picking along a ray is in [`crate::bvh`]; the exact geodesic
//! (surface) ball, by fast marching, is `edit::distance::geodesic_ball` in the `edit`
//! crate.
//!
//! A [`Selection`] is a set of vertices of one mesh kept as a mask indexed by
//! [`Mesh::vertex_index`] (what the `edit` deformers take as `Vertices::Mask`). Queries
//! that look for vertices by position skip isolated vertices (scans often carry
//! unreferenced ones, which no edit can move meaningfully); selections made from
//! handles or by connectivity keep whatever vertices they are given.
//!
//! ```
//! use glam::DVec3;
//! use halfedge::generators;
//! let mesh = generators::icosphere(3);
//! let top = mesh.extreme_vertex(DVec3::Z).unwrap().unwrap();
//! assert!(mesh.position(top).z > 0.99);
//! let cap = mesh.select_ball(mesh.position(top), 0.5).unwrap();
//! let mut grown = cap.clone();
//! grown.grow(&mesh, 1).unwrap();
//! assert!(grown.len() > cap.len());
//! grown.shrink(&mesh, 1).unwrap();
//! assert_eq!(grown, cap); // the cap is a round disk: shrinking undoes growing
//! assert_eq!(mesh.select_linked(&[top]).unwrap().len(), mesh.n_vertices());
//! ```

use glam::DVec3;

use crate::error::{Error, Result};

use crate::handle::VertexId;

use crate::mesh::Mesh;

use crate::vertex_data::VertexData;

/// A set of vertices of one mesh: a mask indexed by [`Mesh::vertex_index`] (see the
/// [module docs](self)), bound to the mesh it was made for like every
/// [`VertexData`]: operations that take the mesh refuse another one (or the same one
/// after its connectivity changed, or at another hierarchy level) with
/// [`Error::Stale`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Selection {
    mask: VertexData<bool>,
    len: usize,
}

impl Selection {
    /// The empty selection of `mesh`.
    pub fn empty(mesh: &Mesh) -> Self {
        Self {
            mask: VertexData::filled(mesh, false),
            len: 0,
        }
    }

    /// The given vertices (duplicates ignored).
    ///
    /// # Errors
    /// [`Error::InvalidHandle`] for a vertex that is not a live vertex of `mesh`.
    pub fn from_vertices(mesh: &Mesh, vertices: &[VertexId]) -> Result<Self> {
        let mut s = Self::empty(mesh);
        for &v in vertices {
            mesh.ensure_vertex(v)?;
            s.set(mesh.vertex_index(v));
        }
        Ok(s)
    }

    /// The live vertices whose mask entry is `true` (entries of removed slots are
    /// dropped).
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] when `mask` is not [`Mesh::vertex_slots`] long.
    pub fn from_mask(mesh: &Mesh, mask: Vec<bool>) -> Result<Self> {
        Self::from_data(mesh, VertexData::new(mesh, mask)?)
    }

    /// [`from_mask`](Self::from_mask) for a mask that carries its binding.
    ///
    /// # Errors
    /// [`Error::Stale`] when `mask` was made for another mesh (or this one before a
    /// change of connectivity).
    pub fn from_data(mesh: &Mesh, mut mask: VertexData<bool>) -> Result<Self> {
        mask.check(mesh)?;
        for (i, m) in mask.iter_mut().enumerate() {
            *m = *m && mesh.vertex_at(i).is_some();
        }
        let len = mask.iter().filter(|&&m| m).count();
        Ok(Self { mask, len })
    }

    /// Number of selected vertices.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when nothing is selected.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The mask, indexed by [`Mesh::vertex_index`], [`Mesh::vertex_slots`] long, with
    /// the binding of the mesh it was made for.
    pub fn mask(&self) -> &VertexData<bool> {
        &self.mask
    }

    /// `Ok` when the selection was made for `mesh` as it is now (see
    /// [`crate::Binding`]).
    ///
    /// # Errors
    /// [`Error::Stale`] naming what it was made for and what it met.
    pub fn check(&self, mesh: &Mesh) -> Result<()> {
        Ok(self.mask.binding().check(mesh, "the selection")?)
    }

    /// True when `v` is a live vertex of `mesh` and selected; false on a mesh the
    /// selection was not made for.
    pub fn contains(&self, mesh: &Mesh, v: VertexId) -> bool {
        mesh.is_valid_vertex(v)
            && self.mask.binding().fits(mesh)
            && self.mask.values().get(mesh.vertex_index(v)) == Some(&true)
    }

    /// Adds `v`; returns whether it was new.
    ///
    /// # Errors
    /// [`Error::InvalidHandle`] for a vertex not of `mesh`; [`Error::Stale`] when the
    /// selection was made for another mesh (see [`check`](Self::check)).
    pub fn insert(&mut self, mesh: &Mesh, v: VertexId) -> Result<bool> {
        self.check(mesh)?;
        mesh.ensure_vertex(v)?;
        Ok(self.set(mesh.vertex_index(v)))
    }

    /// The selected vertices, by increasing [`Mesh::vertex_index`]; vertices removed
    /// from `mesh` since the selection was made are left out.
    pub fn vertices(&self, mesh: &Mesh) -> Vec<VertexId> {
        self.mask
            .iter()
            .enumerate()
            .filter(|&(_, &m)| m)
            .filter_map(|(i, _)| mesh.vertex_at(i))
            .collect()
    }

    /// The selected vertex with faces furthest along `direction` (largest
    /// `p · direction`; ties go to the lowest index), as [`Mesh::extreme_vertex`] within
    /// the selection (the tip of the largest component, not of a loose part). Vertices
    /// whose position is not finite are skipped; `None` when no other selected vertex
    /// has a face.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] for a zero or non-finite direction; [`Error::Stale`]
    /// when the selection was made for another mesh (see [`check`](Self::check)).
    pub fn extreme_vertex(&self, mesh: &Mesh, direction: DVec3) -> Result<Option<VertexId>> {
        self.check(mesh)?;
        let Some(d) = direction.try_normalize() else {
            return Err(Error::InvalidArgument(format!(
                "extreme_vertex needs a non-zero finite direction, got {direction}"
            )));
        };
        let mut best: Option<(f64, VertexId)> = None;
        for v in self.vertices(mesh) {
            if mesh.is_isolated(v) {
                continue;
            }
            let p = mesh.position(v);
            let s = p.dot(d);
            if p.is_finite() && !s.is_nan() && best.is_none_or(|(b, _)| s > b) {
                best = Some((s, v));
            }
        }
        Ok(best.map(|(_, v)| v))
    }

    /// Grows the selection by `rings` rings: each ring adds every vertex joined by an
    /// edge to a selected vertex.
    ///
    /// # Errors
    /// [`Error::Stale`] when the selection was made for another mesh (see
    /// [`check`](Self::check)); nothing changes then.
    pub fn grow(&mut self, mesh: &Mesh, rings: usize) -> Result<()> {
        self.check(mesh)?;
        let mut front: Vec<VertexId> = self.vertices(mesh);
        for _ in 0..rings {
            let mut next = Vec::new();
            for &v in &front {
                for w in mesh.adjacent_vertices(v) {
                    if self.set(mesh.vertex_index(w)) {
                        next.push(w);
                    }
                }
            }
            if next.is_empty() {
                break;
            }
            front = next;
        }
        Ok(())
    }

    /// Shrinks the selection by `rings` rings: each ring removes every selected vertex
    /// joined by an edge to an unselected vertex (the selection's border; the mesh's
    /// own boundary does not count).
    ///
    /// # Errors
    /// As [`grow`](Self::grow).
    pub fn shrink(&mut self, mesh: &Mesh, rings: usize) -> Result<()> {
        self.check(mesh)?;
        for _ in 0..rings {
            let border: Vec<usize> = self
                .vertices(mesh)
                .into_iter()
                .filter(|&v| {
                    mesh.adjacent_vertices(v)
                        .any(|w| !self.mask[mesh.vertex_index(w)])
                })
                .map(|v| mesh.vertex_index(v))
                .collect();
            if border.is_empty() {
                break;
            }
            for i in border {
                self.mask[i] = false;
                self.len -= 1;
            }
        }
        Ok(())
    }

    /// Select linked: every vertex connected by edges to a selected vertex (the
    /// connected components the selection touches).
    ///
    /// # Errors
    /// As [`grow`](Self::grow).
    pub fn linked(&self, mesh: &Mesh) -> Result<Selection> {
        let mut out = self.clone();
        out.grow(mesh, usize::MAX)?;
        Ok(out)
    }

    /// Marks slot `i`; true when it was not marked.
    fn set(&mut self, i: usize) -> bool {
        let new = !std::mem::replace(&mut self.mask[i], true);
        self.len += usize::from(new);
        new
    }
}

/// A connected component of a mesh, as [`Mesh::components`] lists it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Component {
    /// A vertex of the component (its lowest [`Mesh::vertex_index`]); select the whole
    /// component with [`Mesh::select_linked`].
    pub vertex: VertexId,
    /// Its vertices.
    pub vertices: usize,
    /// Its faces (0 for an isolated vertex).
    pub faces: usize,
    /// Its surface area.
    pub area: f64,
    /// The area-weighted centroid of its faces (the vertex's position for an isolated
    /// vertex).
    pub centroid: DVec3,
}

/// # Selection
impl Mesh {
    /// The vertex with faces nearest to `point` (linear scan; ties go to the lowest
    /// index; vertices whose position is not finite are skipped); `None` when no other
    /// vertex has a face.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] for a non-finite point.
    pub fn nearest_vertex(&self, point: DVec3) -> Result<Option<VertexId>> {
        if !point.is_finite() {
            return Err(Error::InvalidArgument(format!(
                "nearest_vertex needs a finite point, got {point}"
            )));
        }
        Ok(self.best_vertex(|p| -p.distance_squared(point)))
    }

    /// The vertex with faces furthest along `direction` (largest `p · direction`; ties
    /// go to the lowest index; vertices whose position is not finite are skipped): the
    /// tip of a nose, the top of a head. `None` when no other vertex has a face.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] for a zero or non-finite direction.
    pub fn extreme_vertex(&self, direction: DVec3) -> Result<Option<VertexId>> {
        let Some(d) = direction.try_normalize() else {
            return Err(Error::InvalidArgument(format!(
                "extreme_vertex needs a non-zero finite direction, got {direction}"
            )));
        };
        Ok(self.best_vertex(|p| p.dot(d)))
    }

    /// The vertex with faces of largest `score(position)`, ties to the lowest index (a
    /// vertex whose position is not finite is never chosen).
    fn best_vertex(&self, score: impl Fn(DVec3) -> f64) -> Option<VertexId> {
        let mut best: Option<(f64, VertexId)> = None;
        for v in self.vertices() {
            if self.is_isolated(v) {
                continue;
            }
            let p = self.position(v);
            let s = score(p);
            if p.is_finite() && !s.is_nan() && best.is_none_or(|(b, _)| s > b) {
                best = Some((s, v));
            }
        }
        best.map(|(_, v)| v)
    }

    /// The vertices with faces within Euclidean distance `radius` of `centre`
    /// (`|p − centre| ≤ radius`).
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] for a non-finite centre or a negative or NaN radius.
    pub fn select_ball(&self, centre: DVec3, radius: f64) -> Result<Selection> {
        if !centre.is_finite() || radius.is_nan() || radius < 0.0 {
            return Err(Error::InvalidArgument(format!(
                "select_ball needs a finite centre and a radius ≥ 0, got {centre} and {radius}"
            )));
        }
        let mut s = Selection::empty(self);
        let r2 = radius * radius;
        for v in self.vertices() {
            if !self.is_isolated(v) && self.position(v).distance_squared(centre) <= r2 {
                s.set(self.vertex_index(v));
            }
        }
        Ok(s)
    }

    /// The vertices within edge-path distance `radius` of `seeds` (a graph-geodesic
    /// ball; see [`edge_distances`](Self::edge_distances)); the seeds are always in it.
    ///
    /// # Errors
    /// As [`edge_distances`](Self::edge_distances).
    pub fn select_edge_ball(&self, seeds: &[VertexId], radius: f64) -> Result<Selection> {
        let dist = self.edge_distances(seeds, radius)?;
        Selection::from_data(self, dist.map(|d| d.is_finite()))
    }

    /// Select linked: the connected components of `seeds` (every vertex joined to a
    /// seed by a path of edges).
    ///
    /// # Errors
    /// [`Error::InvalidHandle`] for a seed that is not a live vertex.
    pub fn select_linked(&self, seeds: &[VertexId]) -> Result<Selection> {
        Selection::from_vertices(self, seeds)?.linked(self)
    }

    /// The vertex with faces farthest from the mesh boundary by edge-path distance (ties
    /// go to the lowest index): the middle of an open patch, where a disk-shaped editing
    /// area fits best. `None` for a closed mesh (no boundary) or a mesh without faces;
    /// vertices of closed components are never chosen.
    ///
    /// # Errors
    /// Those of [`edge_distances`](Self::edge_distances) (none for a valid mesh).
    pub fn farthest_from_boundary(&self) -> Result<Option<VertexId>> {
        let boundary: Vec<VertexId> = self
            .vertices()
            .filter(|&v| !self.is_isolated(v) && self.is_boundary_vertex(v))
            .collect();
        if boundary.is_empty() {
            return Ok(None);
        }
        let d = self.edge_distances(&boundary, f64::INFINITY)?;
        let mut best: Option<(f64, VertexId)> = None;
        for v in self.vertices().filter(|&v| !self.is_isolated(v)) {
            let dv = d[self.vertex_index(v)];
            if dv.is_finite() && best.is_none_or(|(b, _)| dv > b) {
                best = Some((dv, v));
            }
        }
        Ok(best.map(|(_, v)| v))
    }

    /// The largest connected component (the first of [`components`](Self::components):
    /// most faces, then most vertices) as a selection; empty for a mesh without
    /// vertices. What to edit by default on a mesh with loose parts.
    pub fn select_largest_component(&self) -> Selection {
        match self.components().first() {
            Some(c) => self
                .select_linked(&[c.vertex])
                .unwrap_or_else(|_| Selection::empty(self)),
            None => Selection::empty(self),
        }
    }

    /// The connected components (through edges), largest first (by faces, then
    /// vertices); an isolated vertex is a component of its own, with no face.
    pub fn components(&self) -> Vec<Component> {
        let (of_vertex, count) = self.connected_components();
        let mut out: Vec<Option<Component>> = vec![None; count];
        let mut weighted = vec![DVec3::ZERO; count];
        for v in self.vertices() {
            let c = of_vertex[self.vertex_index(v)];
            let entry = out[c].get_or_insert(Component {
                vertex: v,
                vertices: 0,
                faces: 0,
                area: 0.0,
                centroid: self.position(v),
            });
            entry.vertices += 1;
        }
        for f in self.faces() {
            let v = self.triangle(f)[0];
            let c = of_vertex[self.vertex_index(v)];
            let area = self.face_area(f);
            if let Some(entry) = out[c].as_mut() {
                entry.faces += 1;
                entry.area += area;
            }
            weighted[c] += area * self.face_centroid(f);
        }
        let mut list: Vec<Component> = out
            .into_iter()
            .zip(weighted)
            .filter_map(|(c, w)| {
                let mut c = c?;
                if c.area > 0.0 {
                    c.centroid = w / c.area;
                }
                Some(c)
            })
            .collect();
        list.sort_by(|a, b| {
            (b.faces, b.vertices).cmp(&(a.faces, a.vertices)).then(
                self.vertex_index(a.vertex)
                    .cmp(&self.vertex_index(b.vertex)),
            )
        });
        list
    }
}
